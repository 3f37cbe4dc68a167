//! A message the command line cannot write (standard output or error on a
//! full disk, `> /dev/full`) is reported on the other stream where it can be
//! and fails the run with status 1: `println!` used to panic (status 101).
//! Renders are tiny `--cpu` ones; the cases are skipped with a notice where
//! the OS has no `/dev/full`.

mod files;

use std::fs::{File, OpenOptions};
use std::process::{Command, Stdio};

use files::TempDir;

/// `/dev/full` opened for writing, or `None` (with a notice) without it.
fn dev_full() -> Option<File> {
    match OpenOptions::new().write(true).open("/dev/full") {
        Ok(file) => Some(file),
        Err(error) => {
            eprintln!("skipped: no /dev/full ({error})");
            None
        }
    }
}

/// Which stream goes to `/dev/full`.
#[derive(Debug, Clone, Copy)]
enum Full {
    Stdout,
    Stderr,
}

/// Runs `reyes ARGS` with `full` on `/dev/full`: (exit code, the other
/// stream's text), `None` without `/dev/full`.
fn run(args: &[&str], full: Full) -> Option<(Option<i32>, String)> {
    let device = dev_full()?;
    let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
    command.args(args).stdin(Stdio::null());
    match full {
        Full::Stdout => command.stdout(device).stderr(Stdio::piped()),
        Full::Stderr => command.stderr(device).stdout(Stdio::piped()),
    };
    let output = command.output().expect("reyes starts");
    let other = match full {
        Full::Stdout => output.stderr,
        Full::Stderr => output.stdout,
    };
    Some((
        output.status.code(),
        String::from_utf8_lossy(&other).into_owned(),
    ))
}

const TINY: [&str; 7] = ["--cpu", "--width", "16", "--height", "12", "--spp", "1"];

#[test]
fn stats_on_a_full_stdout_fail_with_a_message() {
    let dir = TempDir::new("cli-full-stdout");
    let out = dir.path("out.png");
    let mut args = vec!["render", "--stats", "-o", out.to_str().unwrap()];
    args.extend(TINY);
    let Some((code, stderr)) = run(&args, Full::Stdout) else {
        return;
    };
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("error: cannot write to standard output") && !stderr.contains("panicked"),
        "{stderr}"
    );
}

#[test]
fn a_warning_on_a_full_stderr_fails_the_run() {
    let dir = TempDir::new("cli-full-stderr");
    let scene = dir.path("empty.toml");
    std::fs::write(&scene, "").unwrap();
    let out = dir.path("out.png");
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend(TINY);
    // The empty scene's warning cannot be written: nothing can report it,
    // but the status says so.
    let Some((code, stdout)) = run(&args, Full::Stderr) else {
        return;
    };
    assert_eq!(code, Some(1), "{stdout}");
}

#[test]
fn convert_and_cache_and_help_on_a_full_stdout_fail() {
    let dir = TempDir::new("cli-full-convert");
    let rib = dir.path("s.rib");
    std::fs::write(
        &rib,
        "WorldBegin\nTranslate 0 0 5\nSphere 1 -1 1 360\nWorldEnd\n",
    )
    .unwrap();
    let toml = dir.path("s.toml");
    let cache = dir.path("cache");
    for args in [
        vec![
            "convert",
            rib.to_str().unwrap(),
            "-o",
            toml.to_str().unwrap(),
        ],
        vec!["render", "--help"],
        vec!["--version"],
    ] {
        let Some((code, stderr)) = run(&args, Full::Stdout) else {
            return;
        };
        assert_eq!(code, Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("cannot write to standard output") && !stderr.contains("panicked"),
            "{args:?}: {stderr}"
        );
    }
    let device = dev_full().expect("checked above");
    let output = Command::new(env!("CARGO_BIN_EXE_reyes"))
        .args(["cache", "info"])
        .env("REYES_CACHE_DIR", &cache)
        .stdout(device)
        .output()
        .expect("reyes starts");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("cannot write to standard output"),
        "{stderr}"
    );
}
