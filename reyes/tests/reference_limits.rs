//! The CPU reference's bounds (issue 19, D7/D8): frame size, work and
//! time, through the API and the `reyes render --cpu` command line.

mod files;

use std::time::{Duration, Instant};

use files::{TempDir, run_cli};
use reyes::prepare::{MAX_IMAGE_BYTES, PreparedScene};
use reyes::reference::{self, ReferenceError, ReferenceOptions};
use reyes::scene::{Dicing, Scene};

/// The teapot at `width x height`, diced to 16 x 16 points under a dice
/// threshold of `threshold` pixels.
fn fixed_teapot(width: u32, height: u32, threshold: f32) -> PreparedScene {
    let mut scene = Scene::default_teapot();
    scene.resolution.width = width;
    scene.resolution.height = height;
    scene.dicing = Dicing::Fixed;
    scene.dice_threshold = threshold;
    PreparedScene::load(&scene).unwrap()
}

fn out(dir: &TempDir) -> String {
    dir.path("out.png").to_string_lossy().into_owned()
}

#[test]
fn the_cli_refuses_a_65536_square_cpu_frame_quickly() {
    let dir = TempDir::new("cpu-65536");
    let start = Instant::now();
    let (ok, stderr) = run_cli(&[
        "render",
        "--cpu",
        "--width",
        "65536",
        "--height",
        "65536",
        "-o",
        &out(&dir),
    ]);
    let elapsed = start.elapsed();
    assert!(!ok, "a 65536 x 65536 CPU frame must be refused: {stderr}");
    assert!(
        stderr.contains("65536x65536") && stderr.contains("RGBA image"),
        "the error names the size: {stderr}"
    );
    assert!(stderr.contains("lower the resolution"), "{stderr}");
    assert!(!stderr.contains("memory allocation"), "{stderr}");
    assert!(
        elapsed < Duration::from_secs(10),
        "refused after {elapsed:?}"
    );
    assert!(!dir.path("out.png").exists());
}

#[test]
fn the_image_limit_is_the_gpu_paths_and_frames_within_it_pass() {
    assert_eq!(MAX_IMAGE_BYTES, 128 << 20);
    let options = ReferenceOptions::default();
    // 12000 x 12000 needs a 576 MB image (and 4.6 GB of samples at spp 4).
    match options.check_frame(12000, 12000, 4) {
        Err(ReferenceError::ImageTooLarge { needed, limit, .. }) => {
            assert_eq!(needed, 4 * 12000 * 12000);
            assert_eq!(limit, MAX_IMAGE_BYTES);
        }
        other => panic!("{other:?}"),
    }
    options.check_frame(1920, 1080, 64).unwrap();
    options.check_frame(4096, 4096, 16).unwrap();
    // 256 spp: 1024 x 1024 is exactly the 2 GiB bound; 1920 x 1080 is
    // twice over it.
    options.check_frame(1024, 1024, 256).unwrap();
    match options.check_frame(1920, 1080, 256) {
        Err(ReferenceError::FramebufferTooLarge {
            spp: 256, needed, ..
        }) => assert_eq!(needed, 1920 * 1080 * 256 * 8),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_sample_framebuffer_over_the_bound_is_refused_before_allocating() {
    // 4096 x 4096: a 64 MiB image, but 8 GiB of samples at spp 64.
    let mut scene = Scene::default_teapot();
    scene.resolution.width = 4096;
    scene.resolution.height = 4096;
    scene.spp = 64;
    let prepared = PreparedScene::load(&scene).unwrap();
    let error = reference::try_render(&prepared).unwrap_err();
    assert!(
        matches!(error, ReferenceError::FramebufferTooLarge { spp: 64, needed, .. } if needed == 4096 * 4096 * 64 * 8),
        "{error:?}"
    );
    let text = error.to_string();
    assert!(text.contains("max_framebuffer_bytes"), "{text}");
}

#[test]
fn a_fine_dice_threshold_stops_at_the_cpu_timeout() {
    let dir = TempDir::new("cpu-timeout");
    let scene = dir.path("fine.toml");
    std::fs::write(
        &scene,
        "dicing = \"fixed\"\ndice_threshold = 0.5\n[[objects]]\nmodel = \"teapot\"\n",
    )
    .unwrap();
    let start = Instant::now();
    let (ok, stderr) = run_cli(&[
        "render",
        scene.to_str().unwrap(),
        "--cpu",
        "--timeout",
        "2",
        "-o",
        &out(&dir),
    ]);
    let elapsed = start.elapsed();
    assert!(!ok, "the frame cannot finish in 2 s: {stderr}");
    assert!(stderr.contains("timed out"), "{stderr}");
    assert!(
        stderr.contains("--timeout"),
        "says how to raise it: {stderr}"
    );
    assert!(
        elapsed < Duration::from_secs(20),
        "stopped after {elapsed:?}"
    );
}

#[test]
fn a_deep_split_limit_at_the_eye_stops_at_the_cpu_timeout() {
    // A plane through the eye: the pieces crossing the near plane split
    // until max_split_depth, here 64 (the test would have been killed after
    // 30 s before the CPU timeout). 64 copies of the plane, since one alone
    // can finish within the 2 s in a release build on an idle machine.
    let dir = TempDir::new("cpu-deep");
    const COPIES: usize = 64;
    let mut plane = format!("{COPIES}\n");
    for _ in 0..COPIES {
        plane.push_str("3 3\n");
        for v in 0..4 {
            for u in 0..4 {
                let (x, y) = (-10.0 + 20.0 * u as f32 / 3.0, -10.0 + 20.0 * v as f32 / 3.0);
                plane.push_str(&format!("{x} {y} 0\n"));
            }
        }
    }
    std::fs::write(dir.path("plane.bpt"), plane).unwrap();
    let scene = dir.path("deep.toml");
    std::fs::write(
        &scene,
        "max_split_depth = 64\n[camera]\neye = [0.0, -5.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\n[[objects]]\nmodel = \"plane.bpt\"\n",
    )
    .unwrap();
    let start = Instant::now();
    let (ok, stderr) = run_cli(&[
        "render",
        scene.to_str().unwrap(),
        "--cpu",
        "--timeout",
        "2",
        "-o",
        &out(&dir),
    ]);
    assert!(!ok, "{stderr}");
    assert!(stderr.contains("timed out"), "{stderr}");
    assert!(start.elapsed() < Duration::from_secs(20));
}

#[test]
fn the_work_bounds_stop_a_frame_with_a_typed_error() {
    let prepared = fixed_teapot(200, 150, 0.5);
    let error = reference::try_render_with(
        &prepared,
        &ReferenceOptions {
            max_items: 10_000,
            ..ReferenceOptions::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(
            error,
            ReferenceError::WorkLimit {
                limit: 10_000,
                field: "max_items",
                ..
            }
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("ReferenceOptions::max_items"));

    let error = reference::try_render_with(
        &prepared,
        &ReferenceOptions {
            max_micropolygons: 100_000,
            ..ReferenceOptions::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(
            error,
            ReferenceError::WorkLimit {
                field: "max_micropolygons",
                ..
            }
        ),
        "{error:?}"
    );
}

#[test]
fn the_api_timeout_stops_a_frame() {
    let prepared = fixed_teapot(400, 300, 0.5);
    let start = Instant::now();
    let error = reference::try_render_with(
        &prepared,
        &ReferenceOptions {
            timeout: Some(Duration::from_millis(300)),
            ..ReferenceOptions::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(error, ReferenceError::Timeout { timeout, .. } if timeout == Duration::from_millis(300)),
        "{error:?}"
    );
    assert!(start.elapsed() < Duration::from_secs(10));
}

#[test]
fn a_frame_within_the_bounds_renders_as_without_them() {
    let prepared = fixed_teapot(96, 72, 16.0);
    let bounded = reference::try_render(&prepared).unwrap();
    let unbounded = reference::render(&prepared);
    assert_eq!(bounded.image, unbounded.image);
    assert_eq!(bounded.stats.grids_diced, unbounded.stats.grids_diced);
    assert!(bounded.stats.samples_hit > 0);
}

#[test]
fn the_largest_timeout_does_not_panic() {
    let dir = TempDir::new("cpu-max-timeout");
    let (ok, stderr) = run_cli(&[
        "render",
        "--cpu",
        "--timeout",
        "18446744073709551615",
        "--width",
        "64",
        "--height",
        "48",
        "-o",
        &out(&dir),
    ]);
    assert!(ok, "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(dir.path("out.png").exists());
    // Through the API too.
    let prepared = fixed_teapot(64, 48, 16.0);
    reference::try_render_with(
        &prepared,
        &ReferenceOptions {
            timeout: Some(Duration::from_secs(u64::MAX)),
            ..ReferenceOptions::default()
        },
    )
    .unwrap();
}
