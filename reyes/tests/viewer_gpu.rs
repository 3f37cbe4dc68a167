//! `reyes view` through a real window and surface: the refined frame on
//! screen matches `reyes render` at the same camera, and scripted input
//! moves the camera as the events say and renders again.
//!
//! The tests need an X display: `DISPLAY`, or else an `Xvfb` on `PATH`
//! that they start themselves. Without either they fail, unless
//! `SKIP_GPU_TESTS=1` (then they are `ignored`).

// Without the `viewer` feature there is no `reyes view` to test.
#![cfg(feature = "viewer")]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use glam::{Quat, Vec3};
use gpu_test::gpu_test;
use serde_json::Value;

/// The camera both tests use: the teapot seen from the front, above.
const CAMERA: [&str; 8] = [
    "--eye", "0,-11,5", "--target", "0,0,1.2", "--up", "0,0,1", "--fov", "35",
];
/// The size both tests use (the preview is half of it).
const SIZE: [&str; 4] = ["--width", "640", "--height", "480"];

/// The two tests take turns: lavapipe has two cores to share.
static TURN: Mutex<()> = Mutex::new(());

fn turn() -> MutexGuard<'static, ()> {
    TURN.lock().unwrap_or_else(PoisonError::into_inner)
}

/// An X display for the viewer: `DISPLAY` if set, else an Xvfb this test
/// starts (and stops when dropped).
struct Display {
    name: String,
    server: Option<Child>,
}

impl Drop for Display {
    fn drop(&mut self) {
        if let Some(server) = &mut self.server {
            let _ = server.kill();
            let _ = server.wait();
        }
    }
}

fn display() -> Display {
    if let Ok(name) = std::env::var("DISPLAY")
        && !name.is_empty()
    {
        return Display { name, server: None };
    }
    // A display number no other server uses.
    let number = (90..190)
        .find(|n| {
            !Path::new(&format!("/tmp/.X11-unix/X{n}")).exists()
                && !Path::new(&format!("/tmp/.X{n}-lock")).exists()
        })
        .expect("no free X display number in 90..190");
    let name = format!(":{number}");
    let server = Command::new("Xvfb")
        .args([&name, "-screen", "0", "1280x1024x24", "-nolisten", "tcp"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| {
            panic!(
                "the viewer tests need an X display: DISPLAY is unset and Xvfb cannot be started ({e}); \
                 install xvfb, or set SKIP_GPU_TESTS=1 to skip them"
            )
        });
    let socket = PathBuf::from(format!("/tmp/.X11-unix/X{number}"));
    let deadline = Instant::now() + Duration::from_secs(20);
    while !socket.exists() {
        assert!(
            Instant::now() < deadline,
            "Xvfb {name} did not start within 20 s"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    Display {
        name,
        server: Some(server),
    }
}

fn out_dir(test: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(test);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `reyes` with `args` (on `display` when given) and returns its stdout.
fn reyes(args: &[&str], display: Option<&Display>) -> String {
    let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
    command.args(args);
    if let Some(display) = display {
        command.env("DISPLAY", &display.name);
        command.env_remove("WAYLAND_DISPLAY");
    }
    let output = command.output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "reyes {args:?} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    stdout
}

fn load(path: &Path) -> image::RgbaImage {
    image::open(path).unwrap().to_rgba8()
}

#[gpu_test]
fn the_refined_frame_on_screen_matches_reyes_render() {
    let _turn = turn();
    let display = display();
    let dir = out_dir("viewer_matches_render");
    let shown = dir.join("view.png");
    let rendered = dir.join("render.png");
    let saved = dir.join("saved.png");
    let mut args = vec!["view"];
    args.extend(SIZE);
    args.extend(CAMERA);
    args.extend(["--hide-overlay", "--frames", "1"]);
    args.extend(["--screenshot", shown.to_str().unwrap()]);
    // `P` once refined: the PNG, and the command line that renders it.
    args.extend(["--script", "wait; key save", "-o", saved.to_str().unwrap()]);
    let stdout = reyes(&args, Some(&display));
    let command = stdout
        .lines()
        .find(|l| l.starts_with("reyes render "))
        .unwrap_or_else(|| panic!("P printed no command:\n{stdout}"));
    for part in [
        "--width 640 --height 480",
        "--eye 0,-11,5 --target 0,0,1.2 --up 0,0,1",
        "--spp 4",
    ] {
        assert!(command.contains(part), "{command:?} lacks {part:?}");
    }
    let mut args = vec!["render"];
    args.extend(SIZE);
    args.extend(CAMERA);
    args.extend(["-o", rendered.to_str().unwrap()]);
    reyes(&args, None);

    let (a, b) = (load(&shown), load(&rendered));
    assert!(load(&saved) == a, "P saved the frame on screen");
    assert_eq!(a.dimensions(), b.dimensions(), "the window is 640x480");
    let background = b.get_pixel(0, 0).0;
    let covered = |p: &image::Rgba<u8>| p.0 != background;
    let (mut both, mut either, mut within, mut max_diff) = (0usize, 0usize, 0usize, 0u8);
    for (pa, pb) in a.pixels().zip(b.pixels()) {
        let (ca, cb) = (covered(pa), covered(pb));
        either += usize::from(ca || cb);
        if ca && cb {
            both += 1;
            let diff = (0..3).map(|c| pa.0[c].abs_diff(pb.0[c])).max().unwrap_or(0);
            max_diff = max_diff.max(diff);
            within += usize::from(diff <= 2);
        }
    }
    assert!(both > 10_000, "the teapot is in view: {both} pixels");
    let iou = both as f64 / either as f64;
    let within = within as f64 / both as f64;
    println!("viewer vs render: IoU {iou:.5}, {within:.5} within 2/255, max diff {max_diff}");
    assert!(iou >= 0.995, "coverage IoU {iou:.5} < 0.995");
    assert!(
        within >= 0.999,
        "only {within:.5} of {both} pixels within 2/255 (max diff {max_diff})"
    );
}

fn vec3(value: &Value) -> Vec3 {
    let v: Vec<f32> = value
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap() as f32)
        .collect();
    Vec3::new(v[0], v[1], v[2])
}

#[gpu_test]
fn scripted_orbit_and_zoom_move_the_camera_and_render_again() {
    let _turn = turn();
    let display = display();
    let dir = out_dir("viewer_script");
    let log = dir.join("log.json");
    let mut args = vec!["view"];
    args.extend(SIZE);
    args.extend(CAMERA);
    // A 50-pixel drag to the right, two wheel lines towards the target, then
    // a smaller window.
    let script = "wait; drag left 300,200 350,200; wheel 2; wait; resize 400,300; wait";
    args.extend(["--hide-overlay", "--frames", "2", "--script", script]);
    args.extend(["--log-json", log.to_str().unwrap()]);
    reyes(&args, Some(&display));
    let log: Value = serde_json::from_str(&std::fs::read_to_string(&log).unwrap()).unwrap();

    let initial = &log["initial_camera"];
    let (eye0, target0, up) = (
        vec3(&initial["eye"]),
        vec3(&initial["target"]),
        vec3(&initial["up"]),
    );
    assert!(eye0.distance(Vec3::new(0.0, -11.0, 5.0)) < 1e-5);
    // The expected camera: 50 px * 0.01 rad/px about the up axis (the eye
    // turns clockwise for a drag to the right), then 0.9^2 of the distance.
    let offset = Quat::from_axis_angle(up.normalize(), -0.5) * (eye0 - target0) * 0.81;
    let expected = target0 + offset;
    let last = &log["final_camera"];
    let eye = vec3(&last["eye"]);
    assert!(
        eye.distance(expected) < 1e-3,
        "eye {eye}, expected {expected}"
    );
    assert!(vec3(&last["target"]).distance(target0) < 1e-5);

    let frames = log["frames"].as_array().unwrap();
    let first = &frames[0];
    assert_eq!(first["generation"], 0);
    assert_eq!(first["full"], true);
    assert!(vec3(&first["camera"]["eye"]).distance(eye0) < 1e-5);
    // After the input: a preview at half size and 1 spp (of the drag or of
    // the zoom: the worker renders only the newest request), then the
    // refined frame with the new camera.
    let preview = frames
        .iter()
        .find(|f| f["generation"].as_u64() > Some(0) && f["full"] == false)
        .unwrap_or_else(|| panic!("no preview after the input: {frames:#?}"));
    assert_eq!(
        (preview["width"].as_u64(), preview["spp"].as_u64()),
        (Some(320), Some(1))
    );
    let moved: Vec<&Value> = frames
        .iter()
        .filter(|f| vec3(&f["camera"]["eye"]).distance(expected) < 1e-3)
        .collect();
    assert!(
        !moved.is_empty(),
        "no frame with the new camera: {frames:#?}"
    );
    let refined = moved
        .iter()
        .find(|f| f["full"] == true)
        .unwrap_or_else(|| panic!("no refined frame with the new camera: {frames:#?}"));
    assert_eq!(refined["width"], 640);
    // The resized window is rendered at its new size, refined last.
    let last = frames.last().unwrap();
    assert_eq!(
        (
            last["width"].as_u64(),
            last["height"].as_u64(),
            last["full"].as_bool()
        ),
        (Some(400), Some(300), Some(true))
    );
    assert!(refined["micropolygons"].as_u64().unwrap() > 0);
    println!(
        "{} frames; preview {} ms, refined {} ms (wall)",
        frames.len(),
        preview["wall_ms"],
        refined["wall_ms"]
    );
}

/// `--frames N` without a script ends by itself when the view is refined,
/// even when fewer than N frames come (before, it waited forever in the
/// event loop with nothing printed), and says why it stopped.
#[gpu_test]
fn frames_beyond_the_refined_view_end_the_viewer_with_a_note() {
    let _turn = turn();
    let display = display();
    let dir = out_dir("viewer_frames_end");
    let shot = dir.join("shot.png");
    let _ = std::fs::remove_file(&shot);
    let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
    command
        .args([
            "view", "--width", "160", "--height", "120", "--frames", "50",
        ])
        .args(["--screenshot", shot.to_str().unwrap()])
        .env("DISPLAY", &display.name)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = command.spawn().unwrap();
    // The first frame compiles the megakernel (minutes on lavapipe with a
    // cold cache); the bound only has to tell a hang from that.
    let deadline = Instant::now() + Duration::from_secs(900);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("`reyes view --frames 50` did not end within 900 s");
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    let output = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.contains("note: --frames 50: the view is refined after"),
        "{stdout}"
    );
    assert!(shot.exists(), "the screenshot is written");
}
