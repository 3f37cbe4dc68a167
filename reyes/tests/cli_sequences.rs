//! `reyes render --frames` refuses bad input before any frame renders:
//! malformed ranges, an output name without `#`s for several frames, an
//! output directory that takes no files and keys that break the scene.
//! No GPU is needed: nothing gets as far as rendering.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SCENE: &str = r#"
spp = 1
[resolution]
width = 16
height = 12
[[objects]]
model = "teapot"
[[objects.keys]]
frame = 1
rotate_degrees = [0.0, 0.0, 0.0]
[[objects.keys]]
frame = 12
rotate_degrees = [0.0, 0.0, 90.0]
"#;

/// A fresh directory holding `scene.toml` (`SCENE` with `from` replaced by
/// `to`).
fn scene_dir(name: &str, from: &str, to: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("cli_sequences")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    assert!(SCENE.contains(from));
    std::fs::write(dir.join("scene.toml"), SCENE.replacen(from, to, 1)).unwrap();
    dir
}

fn render(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_reyes"))
        .current_dir(dir)
        .arg("render")
        .arg("scene.toml")
        .args(args)
        .output()
        .unwrap()
}

/// The stderr of a run that must fail before rendering: no frame started
/// and nothing was written in `dir` but the scene.
fn refused(dir: &Path, args: &[&str]) -> String {
    let output = render(dir, args);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success(), "{args:?}: {stderr}");
    assert!(
        !stderr.contains("of 12 (elapsed"),
        "{args:?}: a frame started: {stderr}"
    );
    assert!(
        !stderr.contains("no GPU found"),
        "{args:?}: the GPU was opened: {stderr}"
    );
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert!(
        names.iter().all(|n| n == "scene.toml" || n == "file"),
        "{args:?}: wrote {names:?}"
    );
    stderr
}

#[test]
fn malformed_ranges_are_refused() {
    let dir = scene_dir("ranges", "", "");
    for (range, message) in [
        ("5-1", "the range 5-1 is empty"),
        ("1-", "the range's last frame is missing"),
        ("0x0", "a step (x) needs a range"),
        ("1-10x0", "the step must be at least 1"),
        ("1-4000000000", "selects more than 100000 frames"),
        ("a-b", "is not a frame number"),
    ] {
        let stderr = refused(&dir, &["--frames", range, "-o", "out/f.####.png"]);
        assert!(stderr.contains(message), "{range}: {stderr}");
    }
}

#[test]
fn a_range_needs_a_numbered_output_in_a_directory_that_takes_files() {
    let dir = scene_dir("outputs", "", "");
    let stderr = refused(&dir, &["--frames", "1-12", "-o", "out/f.png"]);
    assert!(stderr.contains("several frames are selected"), "{stderr}");
    assert!(stderr.contains("out/f.####.png"), "{stderr}");
    // A directory that cannot be made: a file is in its place.
    std::fs::write(dir.join("file"), "").unwrap();
    let stderr = refused(&dir, &["--frames", "1-12", "-o", "file/f.####.png"]);
    assert!(stderr.contains("file"), "{stderr}");
    // One frame may go to a plain name.
    std::fs::remove_file(dir.join("file")).unwrap();
}

#[test]
fn bad_keys_are_refused_naming_the_file_and_key() {
    let dir = scene_dir("order", "frame = 12", "frame = 0.5");
    let stderr = refused(&dir, &["--frames", "1-12", "-o", "f.####.png"]);
    assert!(stderr.contains("scene.toml"), "{stderr}");
    assert!(stderr.contains("objects[0].keys[1]"), "{stderr}");
    assert!(stderr.contains("keys out of order"), "{stderr}");
    let dir = scene_dir("nan", "[0.0, 0.0, 90.0]", "[0.0, nan, 90.0]");
    let stderr = refused(&dir, &["--frames", "1-12", "-o", "f.####.png"]);
    assert!(
        stderr.contains("objects[0].keys[1].rotate_degrees must be finite"),
        "{stderr}"
    );
}

#[test]
fn motion_options_are_refused_for_an_animated_scene() {
    let dir = scene_dir("motion", "", "");
    let stderr = refused(&dir, &["--frames", "1-2", "--spin", "10", "-o", "f.#.png"]);
    assert!(
        stderr.contains("--spin") && stderr.contains("animated"),
        "{stderr}"
    );
    // --frame (a RIB's) and --frames are one selection.
    let stderr = refused(&dir, &["--frames", "1-2", "--frame", "1", "-o", "f.#.png"]);
    assert!(stderr.contains("cannot be used with"), "{stderr}");
}
