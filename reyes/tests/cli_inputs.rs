//! The `reyes` command line reads its files through the same checks: every
//! case here fails while reading, before any GPU work starts.

mod files;

use std::path::Path;

use files::{TempDir, run_cli, symlink};
use reyes::load::bpt;
use reyes::model::Model;

fn path_str(path: &Path) -> &str {
    path.to_str().expect("temp paths are UTF-8")
}

#[test]
fn wgsl_link_to_a_device_is_refused() {
    if !Path::new("/dev/zero").exists() {
        println!("NOTICE: /dev/zero not found; skipping");
        return;
    }
    let dir = TempDir::new("cli-wgsl");
    let link = dir.path("zero.wgsl");
    if !symlink(Path::new("/dev/zero"), &link) {
        return;
    }
    let (ok, stderr) = run_cli(&[
        "render",
        "--displace",
        path_str(&link),
        "--displace-scale",
        "0.1",
        "--displace-bound",
        "0.1",
        "-o",
        path_str(&dir.path("out.png")),
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("zero.wgsl") && stderr.contains("a character device"),
        "{stderr}"
    );
}

#[test]
fn stdin_as_a_height_map_does_not_block() {
    // The test's stdin for the child is a pipe that stays open and empty:
    // reading it would block until the time bound kills the child.
    if !Path::new("/dev/stdin").exists() {
        println!("NOTICE: /dev/stdin not found; skipping");
        return;
    }
    let dir = TempDir::new("cli-stdin");
    let (ok, stderr) = run_cli(&[
        "render",
        "--displace",
        "/dev/stdin",
        "--displace-scale",
        "0.1",
        "-o",
        path_str(&dir.path("out.png")),
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("/dev/stdin") && stderr.contains("FIFO"),
        "{stderr}"
    );
}

#[test]
fn max_input_bytes_sets_the_cap() {
    let dir = TempDir::new("cli-cap");
    let scene = dir.path("scene.toml");
    std::fs::write(&scene, "[[objects]]\nmodel = \"teapot\"\n").unwrap();
    let out = dir.path("out.png");
    let (ok, stderr) = run_cli(&[
        "render",
        path_str(&scene),
        "--max-input-bytes",
        "10",
        "-o",
        path_str(&out),
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("scene.toml")
            && stderr.contains("larger than the limit of 10 bytes")
            && stderr.contains("--max-input-bytes"),
        "{stderr}"
    );

    // A model over a small cap is refused; with the cap raised it is read
    // (and here fails to parse, which shows it got past the cap).
    let model = dir.path("bad.bpt");
    let mut text = bpt::write(&Model::teapot());
    text.push_str("trailing\n");
    std::fs::write(&model, &text).unwrap();
    let (ok, stderr) = run_cli(&[
        "render",
        path_str(&model),
        "--max-input-bytes",
        "1K",
        "-o",
        path_str(&out),
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("larger than the limit of 1024 bytes"),
        "{stderr}"
    );
    let (ok, stderr) = run_cli(&[
        "render",
        path_str(&model),
        "--max-input-bytes",
        "1M",
        "-o",
        path_str(&out),
    ]);
    assert!(!ok);
    assert!(
        stderr.contains("unexpected text after the end of the data"),
        "{stderr}"
    );
    assert!(!out.exists(), "nothing is written when reading fails");

    let (ok, stderr) = run_cli(&["render", "--max-input-bytes", "lots"]);
    assert!(!ok);
    assert!(stderr.contains("not a byte count"), "{stderr}");
}
