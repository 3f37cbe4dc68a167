//! Helpers for the input-file tests (included with `mod files;`): temporary
//! directories, FIFOs and links, a time bound, and a CRC-32 for crafting PNGs.

#![allow(dead_code, reason = "each test binary uses a different subset")]

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

/// How long one read may take before the test calls it a hang.
pub(crate) const READ_BOUND: Duration = Duration::from_secs(30);

/// A fresh directory under the system temp directory, removed on drop.
pub(crate) struct TempDir(PathBuf);

impl TempDir {
    /// A new empty directory whose name includes `name` and the process id.
    pub(crate) fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("reyes-input-{}-{name}", std::process::id()));
        // Left over from an earlier run with the same process id.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }

    /// `name` inside the directory.
    pub(crate) fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Creates a FIFO with the `mkfifo` tool; `false` (with a notice) where
/// the system has none.
pub(crate) fn mkfifo(path: &Path) -> bool {
    match std::process::Command::new("mkfifo").arg(path).status() {
        Ok(status) if status.success() => true,
        outcome => {
            println!("NOTICE: mkfifo failed ({outcome:?}); skipping the FIFO checks");
            false
        }
    }
}

/// Creates a symbolic link `link` -> `target`; `false` (with a notice)
/// where links are not supported.
pub(crate) fn symlink(target: &Path, link: &Path) -> bool {
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(target, link).unwrap();
        true
    }
    #[cfg(not(unix))]
    {
        let _ = (target, link);
        println!("NOTICE: no symbolic links on this system; skipping the link checks");
        false
    }
}

/// Runs `f` on its own thread and returns its result, failing the test if
/// it takes longer than [`READ_BOUND`] (a reader blocked on a FIFO, or
/// reading a device without end).
///
/// On a hang, `unblock` is opened for writing from another thread: a reader
/// stuck opening a FIFO then gets a writer, and end of file when it goes.
pub(crate) fn bounded<T: Send + 'static>(
    what: &str,
    unblock: &Path,
    f: impl FnOnce() -> T + Send + 'static,
) -> T {
    let (send, receive) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = send.send(f());
    });
    match receive.recv_timeout(READ_BOUND) {
        Ok(value) => value,
        Err(_) => {
            let unblock = unblock.to_path_buf();
            // Detached: this open blocks too if nobody is reading the FIFO.
            std::thread::spawn(move || drop(std::fs::OpenOptions::new().write(true).open(unblock)));
            panic!("{what} did not finish within {READ_BOUND:?}: it blocked or read without end");
        }
    }
}

/// The CRC-32 (ISO 3309, as PNG chunks use) of `bytes`.
pub(crate) fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &byte in bytes {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// Runs the `reyes` binary with `args` and a stdin pipe that stays open
/// (and empty) while it runs, killing it if it runs longer than
/// [`READ_BOUND`]. Returns (success, stderr).
pub(crate) fn run_cli(args: &[&str]) -> (bool, String) {
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_reyes"));
    command.args(args);
    run_command(command)
}

#[test]
fn crc32_matches_the_reference_value() {
    // The standard check value of CRC-32.
    assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
}

/// Runs `command` (a `reyes` invocation the caller set up: another working
/// directory, a shell with resource limits...) like [`run_cli`]: stdin an
/// open empty pipe, killed past [`READ_BOUND`]. Returns (success, stderr).
pub(crate) fn run_command(mut command: std::process::Command) -> (bool, String) {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = command
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the command starts");
    // Drained on its own thread, so a chatty child cannot fill the pipe and stall.
    let mut stderr_pipe = child.stderr.take().unwrap();
    let stderr_reader = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stderr_pipe.read_to_string(&mut text);
        text
    });
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > READ_BOUND {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{command:?} did not finish within {READ_BOUND:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    drop(child);
    (status.success(), stderr_reader.join().unwrap())
}
