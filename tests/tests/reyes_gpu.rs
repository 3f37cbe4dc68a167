//! The Reyes GPU renderer against the CPU reference (`reyes::reference`),
//! on small scenes (256 x 256, spp 1-4) so that lavapipe runs them in
//! seconds. Both implement the same algorithm in f32 with the same operation
//! order; the thresholds below allow for the GPU's float contraction and its
//! `pow`, which can move a split decision, an edge test or a rounded
//! channel by one step.

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::gpu::{GpuOptions, GpuRendered, GpuRenderer, RenderError};
use reyes::prepare::PreparedScene;
use reyes::reference::{self, Rendered};
use reyes::scene::{CameraDesc, Sampling, Scene};
use tests::reyes_support::{
    Agreement, agreement, assert_counts_close, framed_teapot, gpu_turn, renderer,
};

/// The default teapot at `size x size` (see [`framed_teapot`]).
fn teapot(size: u32, spp: u32) -> Scene {
    framed_teapot(size, size, spp)
}

/// Renders `scene` on both and returns both with their agreement.
fn compare(renderer: &mut GpuRenderer<'_>, scene: &Scene) -> (GpuRendered, Rendered, Agreement) {
    let prepared = PreparedScene::load(scene).expect("scene prepares");
    let gpu = renderer.render(&prepared).expect("GPU render");
    let cpu = reference::render(&prepared);
    let agreement = agreement(&gpu, &cpu);
    eprintln!("GPU stats: {:?}", gpu.stats);
    eprintln!("CPU stats: {:?}", cpu.stats);
    eprintln!(
        "agreement: {agreement:?}; retries: overflow {}, loop limit {}",
        gpu.overflow_retries, gpu.loop_retries
    );
    if let Some(report) = &gpu.report {
        eprintln!("{report}");
    }
    (gpu, cpu, agreement)
}

#[gpu_test]
fn teapot_matches_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    let (g, c, a) = compare(&mut renderer, &teapot(256, 4));
    assert!(a.coverage >= 0.15, "coverage {:.3} < 15%", a.coverage);
    a.assert_at_least("render", 0.995, 0.99);
    assert_eq!(g.stats.input_patches, c.stats.input_patches);
    assert_counts_close("grids diced", g.stats.grids_diced, c.stats.grids_diced);
    assert_counts_close("splits", g.stats.splits, c.stats.splits);
    assert_counts_close("culled", g.stats.culled_patches, c.stats.culled_patches);
    assert_counts_close(
        "micropolygons",
        g.stats.micropolygons,
        c.stats.micropolygons,
    );
    assert_eq!(
        g.stats.grids_by_class.iter().sum::<u64>(),
        g.stats.grids_diced
    );
    assert_counts_close("samples hit", g.stats.samples_hit, c.stats.samples_hit);
    assert_eq!(g.stats.depth_guard_drops, 0);
    assert_eq!(g.overflow_retries, 0);
}

#[gpu_test]
fn renders_are_deterministic_across_runs_and_workgroup_counts() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let scene = PreparedScene::load(&teapot(256, 4)).expect("scene prepares");
    let mut default = renderer(gpu, GpuOptions::default());
    let first = default.render(&scene).expect("first render");
    let second = default.render(&scene).expect("second render");
    assert!(
        first.image.as_raw() == second.image.as_raw(),
        "two runs on the same renderer differ"
    );
    let mut single = renderer(
        gpu,
        GpuOptions {
            workgroups: Some(1),
            ..GpuOptions::default()
        },
    );
    let one = single.render(&scene).expect("1-workgroup render");
    assert_eq!(one.report.as_ref().map(|r| r.workgroups), Some(1));
    assert!(
        first.image.as_raw() == one.image.as_raw(),
        "1 workgroup and the default count give different images"
    );
    // The counters do not depend on the schedule either.
    let mut a = first.stats.clone();
    let mut b = one.stats.clone();
    a.frame_time_ms = None;
    b.frame_time_ms = None;
    assert_eq!(a, b);
}

/// The camera inside the teapot's bounding box, looking across the body,
/// with a near plane (1.5) farther than the nearest walls: patches cross the
/// near/eye planes, are split in object space, pieces entirely in front of
/// the near plane are culled, and those that still straddle it at the
/// maximum depth are dropped (and counted). The run must finish, match the
/// reference on what stays visible, and drop a bounded number of pieces.
#[gpu_test]
fn eye_inside_the_bounding_box() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut scene = teapot(256, 1);
    let (lo, hi) = reyes::model::Model::teapot().bounds();
    let centre = (lo + hi) * 0.5;
    let eye = centre + Vec3::new(0.0, -0.2 * (hi.y - lo.y), 0.1 * (hi.z - lo.z));
    assert!(
        eye.cmpge(lo).all() && eye.cmple(hi).all(),
        "eye inside the box"
    );
    scene.camera = Some(CameraDesc {
        eye,
        target: centre + Vec3::new(hi.x - lo.x, 0.0, 0.0),
        up: Vec3::Z,
        fov_y_degrees: 70.0,
        near: 1.5,
        far: 100.0,
        projection: reyes::scene::Projection::Perspective,
        ortho_height: None,
    });
    // A lower guard keeps this run short; it is the bound the test states.
    scene.max_split_depth = 16;
    let mut renderer = renderer(gpu, GpuOptions::default());
    let (g, c, a) = compare(&mut renderer, &scene);
    assert!(a.coverage > 0.05, "the inside of the teapot is visible");
    a.assert_at_least("render", 0.99, 0.98);
    assert_counts_close(
        "depth-guard drops",
        g.stats.depth_guard_drops,
        c.stats.depth_guard_drops,
    );
    // Each drop is a piece at depth 16 along the curve where the surface
    // meets the near plane: 314 on lavapipe, as on the CPU. The bound allows
    // for float differences but not for a guard that fails to stop splitting
    // (2^16 per patch).
    assert!(g.stats.depth_guard_drops > 0, "the guard was exercised");
    assert!(
        g.stats.depth_guard_drops <= 1_000,
        "{} depth-guard drops",
        g.stats.depth_guard_drops
    );
}

/// A point light near the teapot (its falloff varies several times over
/// the surface) beside a distant one: the GPU shades as the reference does.
/// A GPU that took the point light for a distant one (or lost its falloff)
/// would disagree on most pixels.
#[gpu_test]
fn point_lights_match_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut scene = teapot(256, 1);
    let camera = scene.camera.expect("framed");
    let to_target = camera.target - camera.eye;
    // Beside the eye, a third of the way to the teapot: the near side is
    // lit about four times as brightly as the far side.
    let position = camera.eye + to_target / 3.0 + camera.up.normalize() * to_target.length() * 0.2;
    let distance = (camera.target - position).length();
    scene.lights = vec![
        reyes::scene::Light::point(
            position,
            Vec3::new(1.0, 0.9, 0.8),
            0.8 * distance * distance,
        ),
        reyes::scene::Light {
            intensity: 0.3,
            ..reyes::scene::Light::default()
        },
    ];
    let mut renderer = renderer(gpu, GpuOptions::default());
    let (_, c, a) = compare(&mut renderer, &scene);
    a.assert_at_least("point light", 0.995, 0.99);
    // The point light matters: without it the reference is another picture.
    let mut distant_only = scene.clone();
    distant_only.lights.remove(0);
    let without = reference::render(&PreparedScene::load(&distant_only).expect("prepares"));
    let changed = c
        .image
        .iter()
        .zip(without.image.iter())
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        changed * 20 > c.image.len(),
        "the point light changed only {changed} of {} channels",
        c.image.len()
    );
}

/// An orthographic camera: culling, normals and shading use the view
/// direction instead of the eye point on both sides. The picture must
/// differ from the perspective one (the projection is applied), and the GPU
/// must draw what the reference draws.
#[gpu_test]
fn orthographic_camera_matches_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut scene = teapot(256, 1);
    let perspective = scene.clone();
    let camera = scene.camera.as_mut().expect("framed");
    camera.projection = reyes::scene::Projection::Orthographic;
    let mut renderer = renderer(gpu, GpuOptions::default());
    let (g, c, a) = compare(&mut renderer, &scene);
    a.assert_at_least("orthographic", 0.995, 0.99);
    assert_eq!(g.stats.input_patches, c.stats.input_patches);
    assert_counts_close("grids diced", g.stats.grids_diced, c.stats.grids_diced);
    let flat = reference::render(&PreparedScene::load(&perspective).expect("prepares"));
    let differ = c
        .coverage
        .iter()
        .zip(&flat.coverage)
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        differ > 200,
        "only {differ} pixels changed coverage with the projection"
    );
}

#[gpu_test]
fn nearest_mode_runs_and_matches() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut scene = teapot(256, 1);
    scene.sampling = Sampling::Nearest;
    let mut renderer = renderer(gpu, GpuOptions::default());
    let (g, c, a) = compare(&mut renderer, &scene);
    assert!(g.stats.samples_hit > 0);
    // Nearest mode tests exactly one sample per micropolygon.
    assert_eq!(g.stats.samples_tested, g.stats.micropolygons);
    assert_counts_close("grids diced", g.stats.grids_diced, c.stats.grids_diced);
    assert!(a.iou >= 0.98, "coverage IoU {:.5}", a.iou);
}

#[gpu_test]
fn too_large_resolution_is_a_typed_error() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut scene = teapot(256, 64);
    scene.resolution.width = 60_000;
    scene.resolution.height = 60_000;
    let prepared = PreparedScene::load(&scene).expect("scene prepares");
    let mut renderer = renderer(gpu, GpuOptions::default());
    match renderer.render(&prepared) {
        Err(RenderError::TooLarge { needed, limit, .. }) => assert!(needed > limit),
        other => panic!("expected RenderError::TooLarge, got {other:?}"),
    }
}

/// The generated megakernel, for review of changes to the graph or the WGSL.
#[test]
fn reyes_megakernel_wgsl_snapshot() {
    let compiled = reyes::gpu::graph::compile(scheduler::wgpu::Features::empty())
        .expect("the Reyes graph compiles");
    insta::assert_snapshot!(compiled.wgsl());
}

/// The Rounds strategy renders the same frame as the megakernel, under both
/// policies: the image does not depend on the order in which items run, and
/// the per-procedure counts are equal.
#[gpu_test]
fn rounds_render_the_same_frame_as_the_megakernel() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let prepared = PreparedScene::load(&teapot(160, 4)).unwrap();
    let mut frames = Vec::new();
    // Each policy is a module of its own, and llvmpipe compiles a Reyes
    // megakernel for over a minute on a cold shader cache, so the
    // round-robin module runs only its (quickly compiled) round kernels.
    let configurations = [
        (scheduler::Policy::Priority, scheduler::Strategy::Megakernel),
        (scheduler::Policy::Priority, scheduler::Strategy::rounds()),
        (scheduler::Policy::RoundRobin, scheduler::Strategy::rounds()),
    ];
    {
        for (policy, strategy) in configurations {
            let options = GpuOptions {
                strategy,
                policy,
                ..GpuOptions::default()
            };
            let frame = renderer(gpu, options).render(&prepared).unwrap();
            let report = frame.report.clone().expect("the teapot has patches");
            assert_eq!(report.strategy, strategy);
            if matches!(strategy, scheduler::Strategy::Rounds { .. }) {
                assert!(report.rounds > 1, "{report}");
            }
            frames.push((policy, strategy, frame, report));
        }
    }
    let (_, _, first, first_report) = &frames[0];
    assert!(first.coverage.iter().filter(|&&c| c).count() > 1000);
    for (policy, strategy, frame, report) in &frames[1..] {
        assert!(
            frame.image == first.image,
            "{policy:?} {strategy}: the image differs from the megakernel's"
        );
        for (a, b) in report.procedures.iter().zip(&first_report.procedures) {
            assert_eq!(
                (a.executed, a.enqueued),
                (b.executed, b.enqueued),
                "{policy:?} {strategy}: `{}`",
                a.name
            );
        }
    }
}
