//! Grid points whose position turns infinite or NaN (issue 19, D9) are
//! counted by the stage that turned them, on the CPU reference, and a frame
//! with any says so on stderr and in `--stats-json`. The GPU counts the same
//! (`tests/tests/reyes_non_finite.rs`).

mod files;

use std::fs;

use files::{TempDir, run_cli};
use reyes::displacement::{CpuHeight, DisplacementDesc};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Resolution, Scene};
use reyes::stats::RenderStats;

/// Renders `args` on the CPU at 64 x 48, 1 spp, writing the statistics;
/// returns stderr and the three counts of the `--stats-json` file (read as
/// JSON values: an infinite largest micropolygon is written as `null`).
fn render_cpu(temp: &TempDir, args: &[&str]) -> (String, [u64; 3]) {
    let image = temp.path("r.png");
    let json = temp.path("stats.json");
    let mut all = vec![
        "render",
        "--cpu",
        "--width",
        "64",
        "--height",
        "48",
        "--spp",
        "1",
        "-o",
        image.to_str().unwrap(),
        "--stats-json",
        json.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    let (ok, stderr) = run_cli(&all);
    assert!(ok, "the frame renders (exit 0): {stderr}");
    let stats: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(&json).unwrap()).unwrap();
    let count = |name: &str| {
        stats[name]
            .as_u64()
            .unwrap_or_else(|| panic!("{name} in {stats}"))
    };
    (
        stderr,
        [
            count("non_finite_displacement"),
            count("non_finite_transform"),
            count("non_finite_camera"),
        ],
    )
}

/// The three counts: displacement, transform, camera.
fn counts(stats: &RenderStats) -> [u64; 3] {
    [
        stats.non_finite_displacement,
        stats.non_finite_transform,
        stats.non_finite_camera,
    ]
}

#[test]
fn a_displacement_beyond_the_projection_warns_of_the_camera() {
    let temp = TempDir::new("nonfinite-camera");
    // |sines| <= 1, so the displaced points stay finite (near 1e38), but a
    // narrow field of view multiplies them past f32::MAX in clip space.
    let (stderr, counts) = render_cpu(
        &temp,
        &[
            "--displace",
            "sines",
            "--displace-scale",
            "1e38",
            "--fov",
            "10",
        ],
    );
    let [displacement, transform, camera] = counts;
    assert_eq!((displacement, transform), (0, 0), "{counts:?}");
    assert!(camera > 0, "{counts:?}");
    assert!(
        stderr.contains(&format!(
            "warning: {camera} grid point(s) got an infinite or NaN position from the camera's projection"
        )) && stderr.contains("overflows f32 when projected"),
        "{stderr}"
    );
    // The same teapot at a sane scale loses nothing and warns of nothing.
    let (stderr, counts) = render_cpu(&temp, &["--displace", "sines", "--displace-scale", "0.1"]);
    assert_eq!(counts, [0, 0, 0]);
    assert!(!stderr.contains("warning:"), "{stderr}");
}

#[test]
fn a_motion_that_overflows_warns_of_the_transform() {
    let temp = TempDir::new("nonfinite-transform");
    let scene = temp.path("moving.toml");
    // The control points at close (the teapot times 1e10) are finite, so
    // the scene is valid; its points displaced by up to 1e30 are not once
    // the motion scales them by 1e10.
    fs::write(
        &scene,
        "[[objects]]\nmodel = \"teapot\"\n[objects.displacement]\nsource = \"sines\"\nscale = 1e30\n\
         [objects.transform_close]\nscale = 1e10\n",
    )
    .unwrap();
    let (stderr, counts) = render_cpu(&temp, &[scene.to_str().unwrap()]);
    let [displacement, transform, _] = counts;
    assert_eq!(displacement, 0, "{counts:?}");
    assert!(transform > 0, "{counts:?}");
    assert!(
        stderr.contains(&format!(
            "warning: {transform} grid point(s) got an infinite or NaN position from the object's transform"
        )) && stderr.contains("transform_close"),
        "{stderr}"
    );
}

/// The teapot displaced by a user function whose CPU twin is `height`,
/// rendered by the reference at 64 x 48.
fn user_displaced(height: fn(f32, f32) -> f32) -> RenderStats {
    let mut scene = Scene::default_teapot();
    scene.resolution = Resolution {
        width: 64,
        height: 48,
    };
    scene.objects[0].displacement = Some(DisplacementDesc {
        source: "wgsl".into(),
        scale: 0.1,
        bound: Some(0.1),
        tiling: 1.0,
        wgsl: Some("fn displacement_user(u: f32, v: f32) -> f32 { return u; }".into()),
        file: None,
        parameters: Default::default(),
    });
    let mut prepared = PreparedScene::load(&scene).expect("scene prepares");
    assert!(prepared.set_height_twin(0, CpuHeight::new(height)));
    reference::try_render(&prepared).expect("CPU render").stats
}

#[test]
fn a_user_function_returning_nan_or_infinity_is_counted_as_displacement() {
    for (what, height) in [
        (
            "NaN",
            (|u, _| if u > 0.5 { f32::NAN } else { 0.0 }) as fn(f32, f32) -> f32,
        ),
        ("infinity", |u, _| if u > 0.5 { f32::INFINITY } else { 0.0 }),
    ] {
        let stats = user_displaced(height);
        let [displacement, transform, camera] = counts(&stats);
        assert!(displacement > 0, "{what}: {stats:?}");
        // Lost at the displacement, so not counted again when projected.
        assert_eq!((transform, camera), (0, 0), "{what}: {stats:?}");
    }
    assert_eq!(counts(&user_displaced(|u, _| u)), [0, 0, 0]);
}
