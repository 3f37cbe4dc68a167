//! `reyes`: render a scene or a Bezier patch model on the GPU. The command
//! line lives in the library, [`reyes::cli`]; this binary parses it, sets up
//! logging, runs the command and maps its outcome to an exit code.

use std::process::ExitCode;

use clap::Parser;
use reyes::cli::{Cli, print_error, run};

fn main() -> ExitCode {
    // The renderer reports retries (warn) and tile progress (info) through
    // `log`; show them unless RUST_LOG says otherwise.
    env_logger::Builder::from_env(
        env_logger::Env::default().default_filter_or("reyes=info,scheduler=warn"),
    )
    .init();
    let cli = Cli::parse();
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            print_error(error.as_ref());
            ExitCode::FAILURE
        }
    }
}
