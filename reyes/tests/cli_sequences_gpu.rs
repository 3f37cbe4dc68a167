//! Sequences of an animated TOML scene rendered by `reyes render --frames`
//! on the GPU: a frame renders byte for byte the same alone or in a range,
//! an animated camera matches still scenes written by hand, a frame's
//! motion blur across a key matches the still scene of its poses at open
//! and close, `--skip-existing` renders only the missing frames, and
//! `--keep-going` carries on past a failed frame and names it.
//!
//! The frames are tiny (32 x 24) so that the test stays quick on lavapipe.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use gpu_test::gpu_test;

/// A teapot that turns half a turn over frames 0 to 8 and slides along x,
/// with keys at 0, 4 and 8 (a smooth middle key), under a 180-degree
/// shutter: every frame is motion blurred.
const SPINNING: &str = r#"
spp = 4
shutter = 0.5
[resolution]
width = 32
height = 24
[camera]
eye = [0.0, -9.0, 4.0]
target = [0.0, 0.0, 1.2]
[animation]
fps = 24
[[objects]]
model = "teapot"
[[objects.keys]]
frame = 0
rotate_degrees = [0.0, 0.0, 0.0]
translate = [-1.0, 0.0, 0.0]
[[objects.keys]]
frame = 4
interpolation = "smooth"
rotate_degrees = [0.0, 0.0, 60.0]
[[objects.keys]]
frame = 8
rotate_degrees = [0.0, 0.0, 180.0]
translate = [1.0, 0.0, 0.0]
"#;

/// A fresh directory for the test `name`.
fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("cli_sequences_gpu")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `reyes render` with `args` in `dir`.
fn render(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_reyes"))
        .current_dir(dir)
        .env("RUST_LOG", "reyes=info")
        .arg("render")
        .args(args)
        .output()
        .unwrap()
}

/// `output`'s stdout and stderr, for messages.
fn text(output: &Output) -> String {
    format!(
        "status {}\nstdout:\n{}\nstderr:\n{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

fn read(path: impl AsRef<Path>) -> Vec<u8> {
    let path = path.as_ref();
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[gpu_test]
fn a_frame_renders_the_same_alone_and_in_a_range() {
    let dir = scratch("determinism");
    std::fs::write(dir.join("spin.toml"), SPINNING).unwrap();
    let range = render(
        &dir,
        &["spin.toml", "--frames", "5-7", "-o", "range/s.####.png"],
    );
    assert!(range.status.success(), "{}", text(&range));
    let log = text(&range);
    // One process, one compile: the later frames reuse the pipeline.
    assert_eq!(log.matches("pipeline creation ").count(), 1, "{log}");
    assert_eq!(log.matches("is reused (no compile)").count(), 2, "{log}");
    // Progress on stderr, the summary table on stdout.
    assert!(log.contains("frame 6: 2 of 3 (elapsed"), "{log}");
    assert!(log.contains("ETA"), "{log}");
    assert!(
        log.contains("3 frames: 3 rendered, 0 skipped, 0 failed"),
        "{log}"
    );
    let alone = render(
        &dir,
        &["spin.toml", "--frames", "7", "-o", "alone/s.####.png"],
    );
    assert!(alone.status.success(), "{}", text(&alone));
    assert_eq!(
        read(dir.join("range/s.0007.png")),
        read(dir.join("alone/s.0007.png")),
        "frame 7 differs alone and after frames 5 and 6"
    );
    assert_ne!(
        read(dir.join("range/s.0006.png")),
        read(dir.join("range/s.0007.png"))
    );
}

/// A camera that dollies and pans over keys at frames 0 and 8 (fps 1, so
/// the interpolated values are exact in f32), with a still shutter.
const DOLLY: &str = r#"
spp = 4
shutter = 0.0
[resolution]
width = 32
height = 24
[animation]
fps = 1
[camera]
eye = [0.0, -10.0, 4.0]
target = [0.0, 0.0, 1.0]
fov_y_degrees = 40.0
[[animation.camera]]
frame = 0
eye = [0.0, -10.0, 4.0]
fov_y_degrees = 40.0
[[animation.camera]]
frame = 8
eye = [8.0, -6.0, 4.0]
target = [0.0, 0.0, 1.0]
fov_y_degrees = 24.0
[[objects]]
model = "teapot"
"#;

#[gpu_test]
fn a_camera_path_matches_still_scenes_written_by_hand() {
    let dir = scratch("camera_path");
    std::fs::write(dir.join("dolly.toml"), DOLLY).unwrap();
    let frames = render(&dir, &["dolly.toml", "--frames", "0-8x4", "-o", "f.#.png"]);
    assert!(frames.status.success(), "{}", text(&frames));
    // By hand: at frame f the eye is (f, -10 + f/2, 4), the fov 40 - 2f.
    for (frame, eye, fov) in [
        (0, "0.0, -10.0", "40.0"),
        (4, "4.0, -8.0", "32.0"),
        (8, "8.0, -6.0", "24.0"),
    ] {
        let still = format!(
            "spp = 4\n[resolution]\nwidth = 32\nheight = 24\n[camera]\neye = [{eye}, 4.0]\n\
             target = [0.0, 0.0, 1.0]\nfov_y_degrees = {fov}\n[[objects]]\nmodel = \"teapot\"\n"
        );
        let name = format!("still{frame}");
        std::fs::write(dir.join(format!("{name}.toml")), still).unwrap();
        let output = format!("{name}.png");
        let rendered = render(&dir, &[&format!("{name}.toml"), "-o", &output]);
        assert!(rendered.status.success(), "{}", text(&rendered));
        assert_eq!(
            read(dir.join(format!("f.{frame}.png"))),
            read(dir.join(&output)),
            "frame {frame} differs from its still scene"
        );
    }
}

/// Two keys, at frames 0 and 2, with the shutter of frame 1 open over the
/// whole frame interval, and a key at 1.5 inside it.
const ACROSS_A_KEY: &str = r#"
spp = 16
shutter = 1.0
[resolution]
width = 32
height = 24
[camera]
eye = [0.0, -9.0, 4.0]
target = [0.0, 0.0, 1.2]
[animation]
fps = 1
[[objects]]
model = "teapot"
[[objects.keys]]
frame = 0
translate = [0.0, 0.0, 0.0]
rotate_degrees = [0.0, 0.0, 0.0]
[[objects.keys]]
frame = 1.5
translate = [1.0, 0.0, 0.0]
rotate_degrees = [0.0, 0.0, 30.0]
[[objects.keys]]
frame = 2.5
translate = [1.0, 0.0, 1.0]
rotate_degrees = [0.0, 0.0, 40.0]
"#;

#[gpu_test]
fn motion_blur_across_a_key_is_the_still_scene_of_its_poses_at_open_and_close() {
    let dir = scratch("across_a_key");
    std::fs::write(dir.join("key.toml"), ACROSS_A_KEY).unwrap();
    // Frame 1's shutter opens at 1 and closes at 2. By hand, linear keys:
    // at 1, 2/3 of the way from key 0 to key 1.5: x = 2/3, z angle 20;
    // at 2, half way from 1.5 to 2.5: (1, 0, 0.5), angle 35.
    let still = r#"
spp = 16
shutter = 1.0
[resolution]
width = 32
height = 24
[camera]
eye = [0.0, -9.0, 4.0]
target = [0.0, 0.0, 1.2]
[[objects]]
model = "teapot"
transform = { translate = [0.6666667, 0.0, 0.0], rotate_degrees = [0.0, 0.0, 20.0] }
transform_close = { translate = [1.0, 0.0, 0.5], rotate_degrees = [0.0, 0.0, 35.0] }
"#;
    std::fs::write(dir.join("still.toml"), still).unwrap();
    let animated = render(&dir, &["key.toml", "--frames", "1", "-o", "a.#.png"]);
    assert!(animated.status.success(), "{}", text(&animated));
    // The still scene rendered as frame 1 too: the same samples.
    let by_hand = render(&dir, &["still.toml", "--frames", "1", "-o", "s.#.png"]);
    assert!(by_hand.status.success(), "{}", text(&by_hand));
    assert_eq!(read(dir.join("a.1.png")), read(dir.join("s.1.png")));
    // And the blur is there: the frame differs from a still at open.
    let open = render(
        &dir,
        &[
            "still.toml",
            "--frames",
            "1",
            "--shutter",
            "0",
            "-o",
            "o.#.png",
        ],
    );
    assert!(open.status.success(), "{}", text(&open));
    assert_ne!(read(dir.join("a.1.png")), read(dir.join("o.1.png")));
}

#[gpu_test]
fn skip_existing_renders_only_the_missing_frames() {
    let dir = scratch("skip_existing");
    std::fs::write(dir.join("spin.toml"), SPINNING).unwrap();
    let first = render(
        &dir,
        &["spin.toml", "--frames", "1-4", "-o", "out/s.##.png"],
    );
    assert!(first.status.success(), "{}", text(&first));
    std::fs::remove_file(dir.join("out/s.03.png")).unwrap();
    let kept = read(dir.join("out/s.02.png"));
    let again = render(
        &dir,
        &[
            "spin.toml",
            "--frames",
            "1-4",
            "--skip-existing",
            "-o",
            "out/s.##.png",
        ],
    );
    let log = text(&again);
    assert!(again.status.success(), "{log}");
    assert_eq!(
        log.matches("exists: skipped (--skip-existing)").count(),
        3,
        "{log}"
    );
    assert!(log.contains("wrote out/s.03.png"), "{log}");
    assert!(
        log.contains("4 frames: 1 rendered, 3 skipped, 0 failed"),
        "{log}"
    );
    assert_eq!(read(dir.join("out/s.02.png")), kept);
}

#[gpu_test]
fn keep_going_renders_past_a_failed_frame_and_names_it() {
    let dir = scratch("keep_going");
    // At frame 3 the scale maps the teapot beyond f32: that frame fails
    // when it is prepared.
    let scene = r#"
spp = 1
shutter = 0.0
[resolution]
width = 32
height = 24
[camera]
eye = [0.0, -9.0, 4.0]
target = [0.0, 0.0, 1.2]
[[objects]]
model = "teapot"
[[objects.keys]]
frame = 2
scale = 1.0
[[objects.keys]]
frame = 3
scale = 3e38
[[objects.keys]]
frame = 4
scale = 1.0
"#;
    std::fs::write(dir.join("bad.toml"), scene).unwrap();
    let stopped = render(&dir, &["bad.toml", "--frames", "1-4", "-o", "stop.#.png"]);
    let log = text(&stopped);
    assert!(!stopped.status.success(), "{log}");
    assert!(log.contains("not rendered: frame 4"), "{log}");
    let going = render(
        &dir,
        &[
            "bad.toml",
            "--frames",
            "1-4",
            "--keep-going",
            "-o",
            "go.#.png",
        ],
    );
    let log = text(&going);
    assert!(!going.status.success(), "{log}");
    assert!(log.contains("1 of 4 frames failed: frame 3"), "{log}");
    assert!(
        log.contains("4 frames: 3 rendered, 0 skipped, 1 failed"),
        "{log}"
    );
    for frame in [1, 2, 4] {
        assert!(dir.join(format!("go.{frame}.png")).is_file(), "{log}");
    }
    assert!(!dir.join("go.3.png").exists());
}

#[gpu_test]
fn a_rib_frame_renders_the_same_alone_and_with_the_files_others() {
    let dir = scratch("rib");
    let frame = |n: u32| {
        format!(
            "FrameBegin {n}\nWorldBegin\nTranslate 0 0 5\nMotionBegin [0 1]\nTranslate 0 0 0\n\
             Translate 0.{n} 0 0\nMotionEnd\nSphere 1 -1 1 360\nWorldEnd\nFrameEnd\n"
        )
    };
    let rib = format!(
        "Format 32 24 1\nPixelSamples 2 2\nShutter 0 1\nProjection \"perspective\" \"fov\" 40\n{}{}{}",
        frame(1),
        frame(2),
        frame(3)
    );
    std::fs::write(dir.join("three.rib"), rib).unwrap();
    let all = render(&dir, &["three.rib", "--frames", "1-3", "-o", "all.#.png"]);
    assert!(all.status.success(), "{}", text(&all));
    let alone = render(&dir, &["three.rib", "--frame", "3", "-o", "alone.#.png"]);
    assert!(alone.status.success(), "{}", text(&alone));
    assert_eq!(read(dir.join("all.3.png")), read(dir.join("alone.3.png")));
}

#[gpu_test]
fn skip_existing_skips_a_rib_files_finished_frames_too() {
    let dir = scratch("rib_skip");
    let frame = |n: u32| {
        format!(
            "FrameBegin {n}\nWorldBegin\nTranslate 0 0 5\nSphere 1 -1 1 360\nWorldEnd\nFrameEnd\n"
        )
    };
    let rib = format!("Format 16 12 1\nPixelSamples 1 1\n{}{}", frame(1), frame(2));
    std::fs::write(dir.join("two.rib"), rib).unwrap();
    std::fs::write(dir.join("f.1.png"), "kept").unwrap();
    let run = render(&dir, &["two.rib", "--skip-existing", "-o", "f.#.png"]);
    let log = text(&run);
    assert!(run.status.success(), "{log}");
    assert!(
        log.contains("frame 1: f.1.png exists: skipped (--skip-existing)"),
        "{log}"
    );
    assert!(log.contains("wrote f.2.png"), "{log}");
    assert_eq!(read(dir.join("f.1.png")), b"kept");
}
