//! The lines the command line writes for the user on standard output
//! ("wrote out.png", the statistics table) and standard error (warnings,
//! notes, the error).
//!
//! `println!` and `eprintln!` panic when the write fails (a closed pipe, a
//! full disk, `> /dev/full`), which ends the run with the panic's status and
//! a backtrace hint instead of a message. These functions return the
//! failure instead, so that the command reports it (on standard error when
//! that still works) and exits with a failure status. Each line is flushed
//! at once, so a failed write is found at the line that failed and not at
//! exit, where nothing could report it.

use std::fmt;
use std::io::{self, Write};

/// A stream the command line writes to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stream {
    /// Standard output: what the command produced.
    Stdout,
    /// Standard error: warnings, notes and errors.
    Stderr,
}

impl fmt::Display for Stream {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stream::Stdout => "standard output",
            Stream::Stderr => "standard error",
        })
    }
}

/// A line could not be written to standard output or standard error.
#[derive(Debug, thiserror::Error)]
#[error("cannot write to {stream}: {source}")]
pub struct ConsoleError {
    /// The stream that failed.
    pub stream: Stream,
    /// Why it failed.
    #[source]
    pub source: io::Error,
}

/// Writes `line` and a newline to `out` and flushes it.
fn write_line(mut out: impl Write, line: fmt::Arguments<'_>) -> io::Result<()> {
    out.write_fmt(line)?;
    out.write_all(b"\n")?;
    out.flush()
}

/// Writes one line to standard output (see `outln!`).
pub fn out_line(line: fmt::Arguments<'_>) -> Result<(), ConsoleError> {
    write_line(io::stdout().lock(), line).map_err(|source| ConsoleError {
        stream: Stream::Stdout,
        source,
    })
}

/// Writes one line to standard error (see `errln!`).
pub fn err_line(line: fmt::Arguments<'_>) -> Result<(), ConsoleError> {
    write_line(io::stderr().lock(), line).map_err(|source| ConsoleError {
        stream: Stream::Stderr,
        source,
    })
}

/// `println!` that returns a [`ConsoleError`] instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::output::console::out_line(format_args!($($arg)*))
    };
}

/// `eprintln!` that returns a [`ConsoleError`] instead of panicking.
macro_rules! errln {
    ($($arg:tt)*) => {
        $crate::output::console::err_line(format_args!($($arg)*))
    };
}

pub(crate) use {errln, outln};

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer that fails every write, as `/dev/full` does.
    struct Full;

    impl Write for Full {
        fn write(&mut self, _: &[u8]) -> io::Result<usize> {
            Err(io::Error::from_raw_os_error(28))
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_failed_write_is_an_error_not_a_panic() {
        let error = write_line(Full, format_args!("wrote {}", "out.png")).unwrap_err();
        assert_eq!(error.raw_os_error(), Some(28));
        let error = ConsoleError {
            stream: Stream::Stdout,
            source: error,
        };
        assert!(
            error
                .to_string()
                .starts_with("cannot write to standard output: "),
            "{error}"
        );
    }

    #[test]
    fn a_line_ends_with_a_newline() {
        let mut written = Vec::new();
        write_line(&mut written, format_args!("a {}", 1)).unwrap();
        assert_eq!(written, b"a 1\n");
    }
}
