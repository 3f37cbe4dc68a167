//! The depth output (`Display "x.z" "zfile" "z"`, `--aov z`) of the CPU
//! reference against arithmetic: a plane at a known distance, a sphere's
//! nearest point and its depth under every pixel; the RIB requests that
//! choose it (`Display` modes, `Hider "depthfilter"`) and the files the
//! command line writes.

mod files;

use std::process::Command;

use files::TempDir;
use reyes::depth::{DepthFilter, NO_SURFACE};
use reyes::rib::RibScene;
use reyes::{Aov, reference};

/// Image size and the vertical field of view (RenderMan's `fov` is that of
/// the shorter side).
const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;
const FOV_DEGREES: f64 = 40.0;

/// A RIB frame of `WIDTH x HEIGHT` pixels, 2 x 2 samples, whose world holds
/// `world`, after the options `options`.
fn frame(options: &str, world: &str) -> String {
    format!(
        "Format {WIDTH} {HEIGHT} 1\nPixelSamples 2 2\nProjection \"perspective\" \"fov\" {FOV_DEGREES}\nClipping 0.5 100\n{options}\nWorldBegin\n{world}\nWorldEnd\n"
    )
}

/// The depths of a RIB frame rendered by the CPU reference, row-major.
fn reference_depths(text: &str) -> Vec<f32> {
    let rib = RibScene::from_text(text, "depth.rib").expect("the RIB reads");
    assert_eq!(
        rib.scene.aov,
        Aov::Z,
        "Display mode z selects the depth output"
    );
    let prepared = reyes::PreparedScene::new(&rib.scene, &rib.models).unwrap();
    reyes::depth::depths(&reference::render(&prepared).linear)
}

/// The camera-space direction through image point `(px, py)` (pixels,
/// y down), with z = 1: RenderMan's camera looks down +z, x right, y up.
fn ray(px: f64, py: f64) -> [f64; 3] {
    let t = (FOV_DEGREES.to_radians() / 2.0).tan();
    let half_h = f64::from(HEIGHT) / 2.0;
    [
        (px - f64::from(WIDTH) / 2.0) / half_h * t,
        (half_h - py) / half_h * t,
        1.0,
    ]
}

/// The depth (camera z) where the ray through `(px, py)` first meets the
/// sphere of radius `r` about `(0, 0, distance)`, if it does.
fn sphere_depth(px: f64, py: f64, r: f64, distance: f64) -> Option<f64> {
    let d = ray(px, py);
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let dc = d[2] * distance;
    let disc = dc * dc - dd * (distance * distance - r * r);
    (disc > 0.0).then(|| (dc - disc.sqrt()) / dd)
}

#[test]
fn a_plane_facing_the_camera_has_its_distance_as_depth() {
    let distance = 5.0;
    let text = frame(
        "Display \"plane.z\" \"zfile\" \"z\"",
        &format!("Translate 0 0 {distance}\nPolygon \"P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]"),
    );
    let depths = reference_depths(&text);
    // The plane's half-width of 1 at distance 5 spans 1 / (5 tan 20 deg)
    // of the half-height: 13.2 pixels about the centre.
    let half_span = f64::from(HEIGHT) / 2.0 / (distance * (FOV_DEGREES.to_radians() / 2.0).tan());
    let (cx, cy) = (f64::from(WIDTH) / 2.0, f64::from(HEIGHT) / 2.0);
    let mut inside = 0;
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let depth = depths[(y * WIDTH + x) as usize];
            // How far the pixel's farthest and nearest corners are from the
            // centre, in the larger axis.
            let far = (f64::from(x) - cx)
                .abs()
                .max((f64::from(x) + 1.0 - cx).abs())
                .max(
                    (f64::from(y) - cy)
                        .abs()
                        .max((f64::from(y) + 1.0 - cy).abs()),
                );
            if far < half_span - 0.1 {
                inside += 1;
                // Camera z, not the distance from the eye (which is up to
                // 3.5% longer at the plane's corners).
                assert!(
                    (f64::from(depth) - distance).abs() < 1e-4 * distance,
                    "pixel ({x}, {y}): {depth}"
                );
            } else if far > half_span + 1.5 {
                assert_eq!(depth, NO_SURFACE, "pixel ({x}, {y}) sees no surface");
            }
        }
    }
    assert!(inside > 400, "{inside} pixels inside the plane");
}

#[test]
fn a_sphere_s_depth_is_where_each_pixel_s_rays_meet_it() {
    let (r, distance) = (1.0, 5.0);
    let text = frame(
        "Display \"ball.exr\" \"openexr\" \"z\"",
        &format!("Translate 0 0 {distance}\nSphere {r} -{r} {r} 360"),
    );
    let depths = reference_depths(&text);
    let nearest = depths.iter().copied().fold(f32::INFINITY, f32::min);
    // The nearest point faces the eye: distance - r. Micropolygons are
    // chords, behind the surface by at most their sagitta (about 1e-3 at
    // a pixel's size).
    assert!(
        (f64::from(nearest) - (distance - r)).abs() < 2e-3,
        "nearest {nearest}"
    );
    let mut checked = 0;
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            // The depths the rays through the pixel see (a 9 x 9 lattice
            // over its square): the minimum over its samples lies between
            // their least and greatest, where every ray hits.
            let hits: Option<Vec<f64>> = (0..81)
                .map(|k| {
                    let px = f64::from(x) + f64::from(k % 9) / 8.0;
                    let py = f64::from(y) + f64::from(k / 9) / 8.0;
                    sphere_depth(px, py, r, distance)
                })
                .collect();
            let depth = f64::from(depths[(y * WIDTH + x) as usize]);
            match hits {
                Some(hits) => {
                    let lo = hits.iter().copied().fold(f64::INFINITY, f64::min);
                    let hi = hits.iter().copied().fold(0.0, f64::max);
                    assert!(
                        depth >= lo - 2e-3 && depth <= hi + 2e-3,
                        "pixel ({x}, {y}): {depth} outside [{lo}, {hi}]"
                    );
                    checked += 1;
                }
                None if sphere_depth(f64::from(x) + 0.5, f64::from(y) + 0.5, r * 1.1, distance)
                    .is_none() =>
                {
                    assert_eq!(depth as f32, NO_SURFACE, "pixel ({x}, {y})");
                }
                None => {}
            }
        }
    }
    assert!(checked > 300, "{checked} pixels wholly on the sphere");
}

#[test]
fn display_modes_and_hider_depthfilter_choose_the_output() {
    let world = "Translate 0 0 5\nSphere 1 -1 1 360";
    for (display, depth) in [
        ("Display \"a.z\" \"zfile\" \"z\"", true),
        ("Display \"a.shad\" \"shadow\" \"z\"", true),
        ("Display \"a.exr\" \"file\" \"z\"", true),
        ("Display \"a.png\" \"file\" \"rgba\"", false),
        ("Display \"a.exr\" \"openexr\" \"rgb\"", false),
    ] {
        let rib = RibScene::from_text(&frame(display, world), "d.rib").expect(display);
        assert_eq!(rib.scene.aov == Aov::Z, depth, "{display}");
    }
    let hider = "Display \"a.z\" \"zfile\" \"z\"\nHider \"hidden\" \"depthfilter\" \"min\"";
    let rib = RibScene::from_text(&frame(hider, world), "h.rib").unwrap();
    assert_eq!(rib.scene.depth_filter, DepthFilter::Min);
    assert!(rib.warnings.is_empty(), "{:?}", rib.warnings);

    let midpoint = "Display \"a.z\" \"zfile\" \"z\"\nHider \"hidden\" \"depthfilter\" \"midpoint\"";
    let rib = RibScene::from_text(&frame(midpoint, world), "m.rib").unwrap();
    assert_eq!(rib.scene.depth_filter, DepthFilter::Midpoint);

    let unknown = "Display \"a.z\" \"zfile\" \"z\"\nHider \"hidden\" \"depthfilter\" \"median\"";
    let rib = RibScene::from_text(&frame(unknown, world), "u.rib").unwrap();
    assert_eq!(rib.scene.depth_filter, DepthFilter::Min);
    let all: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    assert!(
        all.iter()
            .any(|w| w.starts_with("u.rib:6: Hider \"depthfilter\" \"median\" is unknown")),
        "{all:?}"
    );
}

#[test]
fn a_depth_display_named_png_is_an_error_naming_its_line() {
    let text = frame("Display \"depth.png\" \"file\" \"z\"", "Sphere 1 -1 1 360");
    let error = RibScene::from_text(&text, "bad.rib").expect_err("a PNG cannot hold depth");
    let message = error.to_string();
    assert!(
        message.contains("bad.rib:5") && message.contains("*.exr"),
        "{message}"
    );
}

/// Two squares facing the camera, one of half-width 1 at depth `near`, one
/// of half-width 3 behind it at `far`.
fn two_planes(near: f64, far: f64) -> String {
    format!(
        "AttributeBegin\nTranslate 0 0 {near}\nPolygon \"P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]\nAttributeEnd\nTranslate 0 0 {far}\nPolygon \"P\" [-3 -3 0  3 -3 0  3 3 0  -3 3 0]"
    )
}

#[test]
fn midpoint_is_halfway_between_the_two_nearest_surfaces() {
    let (near, far) = (4.0, 6.0);
    let text = frame(
        "Display \"planes.z\" \"zfile\" \"z\"\nHider \"hidden\" \"depthfilter\" \"midpoint\"",
        &two_planes(near, far),
    );
    let depths = reference_depths(&text);
    let t = (FOV_DEGREES.to_radians() / 2.0).tan();
    let half_h = f64::from(HEIGHT) / 2.0;
    // Pixels of the near square (half-width 1 / (4 t) of the half-height):
    // both surfaces, the mean. The far square alone fills the rest of the
    // frame (3 / (6 t) > the half-width): a single surface, nothing behind
    // it to shadow, +inf.
    let near_span = half_h / (near * t);
    let (cx, cy) = (f64::from(WIDTH) / 2.0, half_h);
    let (mut both, mut single) = (0, 0);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let depth = depths[(y * WIDTH + x) as usize];
            let far_corner = [f64::from(x), f64::from(x) + 1.0]
                .map(|px| (px - cx).abs())
                .into_iter()
                .chain([f64::from(y), f64::from(y) + 1.0].map(|py| (py - cy).abs()))
                .fold(0.0, f64::max);
            let near_corner = (f64::from(x) + 0.5 - cx)
                .abs()
                .max((f64::from(y) + 0.5 - cy).abs())
                - 0.5;
            if far_corner < near_span - 0.1 {
                both += 1;
                assert!(
                    (f64::from(depth) - (near + far) / 2.0).abs() < 1e-4 * far,
                    "pixel ({x}, {y}): {depth}"
                );
            } else if near_corner > near_span + 0.1 {
                single += 1;
                assert_eq!(depth, NO_SURFACE, "pixel ({x}, {y}): the far square alone");
            }
        }
    }
    assert!(
        both > 500 && single > 1000,
        "{both} pixels of both, {single} of one"
    );
    // The same frame with the default filter: the near square's depth.
    let min = reference_depths(&text.replace("\"midpoint\"", "\"min\""));
    let centre = ((HEIGHT / 2) * WIDTH + WIDTH / 2) as usize;
    assert!(
        (f64::from(min[centre]) - near).abs() < 1e-4 * near,
        "{}",
        min[centre]
    );
    assert!((f64::from(min[0]) - far).abs() < 1e-4 * far, "{}", min[0]);
}

/// Runs `reyes render` in `dir` with `args`; its status and stderr.
fn reyes(dir: &TempDir, args: &[&str]) -> (bool, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_reyes"))
        .current_dir(dir.path("."))
        .arg("render")
        .args(args)
        .args(["--cpu", "--quiet"])
        .output()
        .expect("reyes starts");
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn the_command_line_writes_depth_as_a_single_channel_float_exr() {
    let dir = TempDir::new("depth-cli");
    let text = frame(
        "Display \"plane.z\" \"zfile\" \"z\"",
        "Translate 0 0 5\nPolygon \"P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]",
    );
    std::fs::write(dir.path("plane.rib"), &text).unwrap();
    let (ok, stderr) = reyes(&dir, &["plane.rib"]);
    assert!(ok, "{stderr}");
    let written = reyes::output::read_depth(&dir.path("plane.z")).expect("a depth EXR");
    assert_eq!((written.width, written.height), (WIDTH, HEIGHT));
    assert_eq!(
        written.depths,
        reference_depths(&text),
        "the file holds the depths"
    );
    let centre = written.depths[(HEIGHT / 2 * WIDTH + WIDTH / 2) as usize];
    assert!((centre - 5.0).abs() < 1e-4, "{centre}");

    // `--aov z` from a plain scene, to an EXR; a PNG is refused before
    // rendering.
    let (ok, stderr) = reyes(
        &dir,
        &[
            "--aov",
            "z",
            "--width",
            "16",
            "--height",
            "12",
            "-o",
            "teapot.exr",
        ],
    );
    assert!(ok, "{stderr}");
    let teapot = reyes::output::read_depth(&dir.path("teapot.exr")).unwrap();
    assert!(teapot.depths.iter().any(|d| d.is_finite()) && teapot.depths.contains(&NO_SURFACE));
    let (ok, stderr) = reyes(&dir, &["--aov", "z", "-o", "teapot.png"]);
    assert!(
        !ok && stderr.contains("teapot.png") && stderr.contains("*.exr"),
        "{stderr}"
    );
    assert!(!dir.path("teapot.png").exists());
}

#[test]
fn write_depth_round_trips_under_any_name_but_png() {
    let dir = TempDir::new("depth-write");
    let depths = image::Rgba32FImage::from_fn(3, 2, |x, y| {
        let z = if (x, y) == (2, 1) {
            NO_SURFACE
        } else {
            1.5 + x as f32 + 10.0 * y as f32
        };
        image::Rgba([z, z, z, 1.0])
    });
    let camera = reyes::camera::Camera::new(
        glam::Vec3::new(1.0, 2.0, 3.0),
        glam::Vec3::ZERO,
        glam::Vec3::Y,
        0.8,
        3,
        2,
        0.1,
        100.0,
    );
    for name in ["a.shad", "a.z", "a.exr"] {
        reyes::output::write_depth(&depths, &camera, dir.path(name)).expect(name);
        let read = reyes::output::read_depth(&dir.path(name)).expect(name);
        assert_eq!((read.width, read.height), (3, 2), "{name}");
        assert_eq!(read.depths, reyes::depth::depths(&depths), "{name}");
        // The camera travels with the depths: the file is a shadow map.
        let map = reyes::shadow::read_shadow_map(&dir.path(name)).expect(name);
        assert_eq!(map.world_to_camera, camera.view, "{name}");
        assert_eq!(map.world_to_clip, camera.view_proj(), "{name}");
    }
    let error = reyes::output::write_depth(&depths, &camera, dir.path("a.png")).unwrap_err();
    assert!(
        matches!(error, reyes::output::OutputError::DepthNeedsExr { .. }),
        "{error}"
    );
    assert!(!dir.path("a.png").exists());
}

#[test]
fn max_and_average_take_the_largest_and_the_mean_of_a_pixel_s_samples() {
    let (near, far) = (4.0f32, 6.0f32);
    let filtered = |name: &str| {
        let text = frame(
            &format!(
                "Display \"planes.z\" \"zfile\" \"z\"\nHider \"hidden\" \"depthfilter\" \"{name}\""
            ),
            &two_planes(f64::from(near), f64::from(far)),
        );
        let rib = RibScene::from_text(&text, "depth.rib").expect("the RIB reads");
        assert!(rib.warnings.is_empty(), "{name}: {:?}", rib.warnings);
        assert_eq!(DepthFilter::from_name(name), Some(rib.scene.depth_filter));
        reference_depths(&text)
    };
    let (min, max, average) = (filtered("min"), filtered("max"), filtered("average"));
    // Every pixel sees the near square with k of its 4 samples and the far
    // one with the rest: the mean is (k near + (4 - k) far) / 4, and k
    // decides the minimum and the maximum.
    let mut mixed = 0;
    for (i, ((&min, &max), &average)) in min.iter().zip(&max).zip(&average).enumerate() {
        let k = (4.0 * far - 4.0 * average) / (far - near);
        let samples_near = k.round();
        assert!(
            (k - samples_near).abs() < 1e-3 && (0.0..=4.0).contains(&samples_near),
            "pixel {i}: average {average} is no mean of {near}s and {far}s"
        );
        let close = |a: f32, b: f32| (a - b).abs() < 1e-4 * b;
        assert!(
            close(min, if samples_near > 0.0 { near } else { far }),
            "pixel {i}: min {min}"
        );
        assert!(
            close(max, if samples_near < 4.0 { far } else { near }),
            "pixel {i}: max {max}"
        );
        mixed += usize::from(samples_near > 0.0 && samples_near < 4.0);
    }
    assert!(mixed > 20, "{mixed} pixels on the near square's edges");
}
