//! `reyes`: render a scene or a Bezier patch model on the GPU. The command
//! line lives in the library, [`reyes::cli`]; this binary parses it, sets up
//! logging, runs the command and maps its outcome to an exit code.

use std::process::ExitCode;

use clap::Parser;
use reyes::cli::{Cli, print_error, run};
use std::io::Write;

fn main() -> ExitCode {
    // The renderer reports retries (warn) and tile progress (info) through
    // `log`; show them unless RUST_LOG says otherwise.
    env_logger::Builder::from_env(
        env_logger::Env::default().default_filter_or("reyes=info,scheduler=warn"),
    )
    .init();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => return parse_failure(&error),
    };
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            print_error(error.as_ref());
            ExitCode::FAILURE
        }
    }
}

/// Prints clap's message for `error` (the help, the version or a usage
/// error) and returns its exit code; a message that cannot be written
/// (`reyes --help > /dev/full`) fails the run, reported on stderr when that
/// still works.
fn parse_failure(error: &clap::Error) -> ExitCode {
    let printed = error.print().and_then(|()| {
        std::io::stdout().flush()?;
        std::io::stderr().flush()
    });
    match printed {
        Ok(()) => ExitCode::from(u8::try_from(error.exit_code()).unwrap_or(2)),
        Err(source) => {
            let stream = if error.use_stderr() {
                "standard error"
            } else {
                "standard output"
            };
            let _ = writeln!(
                std::io::stderr(),
                "error: cannot write to {stream}: {source}"
            );
            ExitCode::FAILURE
        }
    }
}
