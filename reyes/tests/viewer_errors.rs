//! `reyes view` without a display: a clear message and exit code 1, not a
//! panic. Needs no GPU: the window is refused before any device is made.
#![cfg(feature = "viewer")]

use std::process::Command;

#[test]
fn no_display_is_a_clear_error() {
    let output = Command::new(env!("CARGO_BIN_EXE_reyes"))
        .args(["view", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the reyes binary runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("cannot open a window"), "{stderr}");
    assert!(stderr.contains("xvfb-run"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
