//! What `reyes render` prints about its progress on the GPU: with stderr
//! not a terminal (a pipe here) no progress line, with or without
//! `--quiet`; on a software adapter the notice, exactly once, unless
//! `--quiet`. Both renders are a small teapot, whose megakernel is the
//! default one that the other GPU tests compile too.

use std::path::PathBuf;
use std::process::Command;

use gpu_test::gpu_test;
use reyes::progress::{AdapterSummary, is_software};

/// Renders a small teapot on the GPU with `extra` arguments; returns
/// stdout and stderr.
fn render(name: &str, extra: &[&str]) -> (String, String) {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_progress");
    std::fs::create_dir_all(&dir).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_reyes"))
        .args(["render", "--width", "64", "--height", "48", "--spp", "1"])
        .arg("-o")
        .arg(dir.join(name))
        .args(extra)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "{stdout}\n{stderr}");
    (stdout, stderr)
}

/// The start of the notice about a software adapter.
const NOTICE: &str = "note: no GPU found: rendering on ";

/// Words only the progress line has.
const PROGRESS: [&str; 3] = ["compiling the GPU program", "rendering 64x48", " … "];

#[gpu_test]
fn no_progress_line_without_a_terminal_and_the_notice_once_unless_quiet() {
    // The adapter the binary will pick: the tests' shared device's.
    let software = is_software(&gpu_test::gpu().adapter.get_info());
    let (stdout, stderr) = render("loud.png", &[]);
    assert!(stdout.contains("wrote "), "{stdout}");
    for words in PROGRESS {
        assert!(!stderr.contains(words), "{words:?} in {stderr:?}");
    }
    assert!(!stderr.contains('\r'), "{stderr:?}");
    let expected = usize::from(software);
    assert_eq!(stderr.matches(NOTICE).count(), expected, "{stderr:?}");
    if software {
        let name = AdapterSummary::of(&gpu_test::gpu().adapter.get_info());
        assert!(
            stderr.contains(&format!("{NOTICE}{}, a CPU driver", name.short_name())),
            "{stderr:?}"
        );
    }

    let (stdout, stderr) = render("quiet.png", &["--quiet"]);
    assert!(stdout.contains("wrote "), "{stdout}");
    assert!(!stderr.contains(NOTICE), "{stderr:?}");
    for words in PROGRESS {
        assert!(!stderr.contains(words), "{words:?} in {stderr:?}");
    }
}
