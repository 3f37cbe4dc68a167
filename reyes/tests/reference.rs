//! Reference renderer tests: normals, whole-scene renders, statistics.

mod common;

use std::time::Instant;

use glam::{Vec3, Vec4};
use reyes::bezier;
use reyes::dicing::GridSize;
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::reference::{self, dice::surface_normal};
use reyes::scene::{Resolution, Sampling, Scene};

#[test]
fn exact_normals_match_finite_differences_on_a_smooth_patch() {
    // A smooth, curved patch: z = sin-like bump over a 3x3 square.
    let points: [Vec3; 16] = std::array::from_fn(|k| {
        let (u, v) = ((k % 4) as f32, (k / 4) as f32);
        Vec3::new(
            u,
            v,
            0.3 * (u - 1.5) * (u - 1.5) - 0.2 * (v - 1.5) * (v - 1.2) + 0.1 * u * v,
        )
    });
    let eye = Vec3::new(1.5, 1.5, 10.0).extend(1.0);
    let h = 1e-3f32;
    for j in 0..16 {
        for i in 0..16 {
            let (s, t) = (i as f32 / 15.0, j as f32 / 15.0);
            let n = surface_normal(&points, s, t, bezier::position(&points, s, t), eye);
            // Central differences (one-sided at the borders), in f64-ish care.
            let (s0, s1) = ((s - h).max(0.0), (s + h).min(1.0));
            let (t0, t1) = ((t - h).max(0.0), (t + h).min(1.0));
            let ds =
                (bezier::position(&points, s1, t) - bezier::position(&points, s0, t)) / (s1 - s0);
            let dt =
                (bezier::position(&points, s, t1) - bezier::position(&points, s, t0)) / (t1 - t0);
            let mut fd = ds.cross(dt).normalize();
            if fd.dot(n) < 0.0 {
                fd = -fd;
            }
            let angle = n.dot(fd).clamp(-1.0, 1.0).acos().to_degrees();
            assert!(angle < 1.0, "angle {angle} degrees at ({s}, {t})");
            assert!((n.length() - 1.0).abs() < 1e-5);
        }
    }
}

#[test]
fn teapot_grids_have_no_nan_normals() {
    let teapot = Model::teapot();
    let eye = Vec3::new(3.0, -12.0, 7.0).extend(1.0);
    let mut degenerate_patches = 0;
    for patch in &teapot.patches {
        let whole = Vec4::new(0.0, 0.0, 1.0, 1.0);
        let grid = reference::dice::dice(&patch.points, whole, GridSize::FIXED, None, eye, None)
            .expect("undisplaced");
        let mut had_vanishing_tangent = false;
        for (k, (p, n)) in grid.positions.iter().zip(&grid.normals).enumerate() {
            assert!(p.is_finite() && n.is_finite(), "NaN at grid point {k}");
            assert!((n.length() - 1.0).abs() < 1e-4, "normal not unit: {n}");
            assert!(
                n.dot(eye.truncate() - *p) >= 0.0,
                "normal not facing the eye"
            );
            let (s, t) = ((k % 16) as f32 / 15.0, (k / 16) as f32 / 15.0);
            let e = bezier::evaluate(&patch.points, s, t);
            had_vanishing_tangent |= e.d_ds.cross(e.d_dt).length_squared() < 1e-12;
        }
        degenerate_patches += usize::from(had_vanishing_tangent);
    }
    assert_eq!(
        degenerate_patches, 8,
        "the teapot has 8 patches with a collapsed edge"
    );
}

#[test]
fn default_teapot_at_256() {
    let mut scene = Scene::default_teapot();
    scene.resolution = Resolution {
        width: 256,
        height: 256,
    };
    scene.camera = None; // re-frame for the square image
    // Plain rounding: the background pixels below are compared code for
    // code (the dither is checked in `exposure.rs`).
    scene.quantize = reyes::quantize::Quantize::NO_DITHER;
    let prepared = PreparedScene::load(&scene).unwrap();
    let start = Instant::now();
    let rendered = reference::render(&prepared);
    let elapsed = start.elapsed();
    let stats = &rendered.stats;
    println!(
        "teapot 256x256 spp {}: {elapsed:?}\n{}",
        scene.spp,
        serde_json::to_string_pretty(stats).unwrap()
    );

    let out = common::target_dir().join("reference-teapot.png");
    reyes::output::write_png(&rendered.image, &out).unwrap();
    println!("wrote {}", out.display());
    let covered = rendered.coverage.iter().filter(|&&c| c).count();
    let fraction = covered as f64 / rendered.coverage.len() as f64;
    println!("coverage {:.1}%", fraction * 100.0);
    assert!(fraction >= 0.15, "coverage {fraction}");
    assert_eq!(stats.input_patches, 32);
    // Rate dicing: every grid holds 1 to 256 micropolygons, and each is
    // counted in its class.
    assert!(stats.micropolygons >= stats.grids_diced);
    assert!(stats.micropolygons <= stats.grids_diced * 256);
    assert_eq!(stats.grids_by_class.iter().sum::<u64>(), stats.grids_diced);
    assert!(stats.grids_diced > 32);
    assert_eq!(stats.depth_guard_drops, 0);
    assert!(stats.samples_hit > 0 && stats.samples_hit <= stats.samples_tested);
    assert!(stats.largest_micropolygon_px.is_finite());
    assert!(stats.largest_micropolygon_px <= scene.dice_threshold);
    // Every patch is split into two, diced, culled or dropped.
    assert_eq!(
        stats.input_patches + stats.splits,
        stats.grids_diced + stats.culled_patches + stats.depth_guard_drops
    );
    // Pixels whose filter window (the default gaussian reaches one pixel
    // around) holds no covered sample are the background.
    let background = rendered.image.get_pixel(0, 0).0;
    assert!(!rendered.coverage[0]);
    let (w, h) = rendered.image.dimensions();
    let covered_at = |x: i64, y: i64| {
        x >= 0
            && y >= 0
            && x < i64::from(w)
            && y < i64::from(h)
            && rendered.coverage[(y * i64::from(w) + x) as usize]
    };
    for (x, y, pixel) in rendered.image.enumerate_pixels() {
        assert_eq!(pixel.0[3], 255);
        let (x, y) = (i64::from(x), i64::from(y));
        let near = (-1..=1).any(|dy| (-1..=1).any(|dx| covered_at(x + dx, y + dy)));
        if !near {
            assert_eq!(pixel.0, background, "pixel ({x}, {y})");
        }
    }
    // Release-mode budget from the spec, with slack for a loaded machine.
    if !cfg!(debug_assertions) {
        assert!(elapsed.as_secs_f64() < 2.0, "took {elapsed:?}");
    }
}

#[test]
fn rendering_is_deterministic_and_modes_agree_roughly() {
    let mut scene = Scene::default_teapot();
    scene.resolution = Resolution {
        width: 96,
        height: 72,
    };
    scene.jitter = true;
    let prepared = PreparedScene::load(&scene).unwrap();
    let a = reference::render(&prepared);
    let b = reference::render(&prepared);
    assert_eq!(a.image, b.image);
    let (mut sa, mut sb) = (a.stats.clone(), b.stats.clone());
    (sa.frame_time_ms, sb.frame_time_ms) = (None, None);
    assert_eq!(sa, sb);

    // Patch order does not matter (min-key framebuffer).
    let mut reversed = prepared.clone();
    reversed.patches.reverse();
    assert_eq!(
        reference::render_samples(&reversed).0,
        reference::render_samples(&prepared).0
    );

    scene.sampling = Sampling::Nearest;
    scene.jitter = false;
    let nearest = reference::render(&PreparedScene::load(&scene).unwrap());
    assert_eq!(nearest.stats.samples_tested, nearest.stats.micropolygons);
    let covered = |r: &reference::Rendered| r.coverage.iter().filter(|&&c| c).count() as f64;
    let ratio = covered(&nearest) / covered(&a);
    assert!(
        ratio > 0.5 && ratio <= 1.05,
        "nearest/bbox coverage ratio {ratio}"
    );
}

#[test]
fn camera_inside_the_model_uses_the_depth_guard_or_culls() {
    // Eye inside the teapot body: patches cross the eye plane.
    let mut scene = Scene::default_teapot();
    scene.resolution = Resolution {
        width: 64,
        height: 48,
    };
    scene.max_split_depth = 10;
    scene.camera = Some(reyes::scene::CameraDesc {
        eye: Vec3::new(0.0, 0.0, 1.5),
        target: Vec3::new(0.0, -1.0, 1.5),
        up: Vec3::Z,
        fov_y_degrees: 90.0,
        near: 0.05,
        far: 100.0,
        projection: reyes::scene::Projection::Perspective,
        ortho_height: None,
    });
    let rendered = reference::render(&PreparedScene::load(&scene).unwrap());
    let s = &rendered.stats;
    assert_eq!(
        s.input_patches + s.splits,
        s.grids_diced + s.culled_patches + s.depth_guard_drops
    );
    assert!(s.culled_patches > 0);
    assert!(
        rendered.coverage.iter().filter(|&&c| c).count() > 64 * 48 / 2,
        "inside walls are seen"
    );
}

#[test]
fn killeroo_800x600_spp1() {
    let Some(path) = common::killeroo_path() else {
        return;
    };
    let model = Model::load(&path).unwrap();
    let mut scene = Scene::for_model(path.to_string_lossy(), &model);
    scene.spp = 1;
    let prepared = PreparedScene::new(&scene, &[model]).unwrap();
    let start = Instant::now();
    let rendered = reference::render(&prepared);
    let elapsed = start.elapsed();
    println!(
        "killeroo 800x600 spp 1: {elapsed:?}\n{}",
        serde_json::to_string_pretty(&rendered.stats).unwrap()
    );
    assert_eq!(rendered.stats.input_patches, 11_532);
    let fraction = rendered.coverage.iter().filter(|&&c| c).count() as f64 / (800.0 * 600.0);
    assert!(fraction > 0.1, "coverage {fraction}");
    reyes::output::write_png(
        &rendered.image,
        common::target_dir().join("reference-killeroo.png"),
    )
    .unwrap();
    if !cfg!(debug_assertions) {
        assert!(elapsed.as_secs_f64() < 60.0, "took {elapsed:?}");
    }
}
