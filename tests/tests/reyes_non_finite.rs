//! Grid points whose position turns infinite or NaN (issue 19, D9): the GPU
//! counts them by source (displacement, transform, camera) as the CPU
//! reference does, on one scene per source. Renders are 64 x 48 at 1 spp.

use gpu_test::gpu_test;
use reyes::displacement::{CpuHeight, DisplacementDesc};
use reyes::gpu::GpuRenderer;
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Scale, Scene, Transform};
use reyes::stats::RenderStats;
use tests::reyes_support::{self, assert_counts_close, framed_teapot, gpu_turn};

/// The three counts: displacement, transform, camera.
fn counts(stats: &RenderStats) -> [u64; 3] {
    [
        stats.non_finite_displacement,
        stats.non_finite_transform,
        stats.non_finite_camera,
    ]
}

/// Renders `prepared` on both; checks that the counts of the sources other
/// than `source` (0 displacement, 1 transform, 2 camera) are 0 on both,
/// that `source`'s is positive on both and that they agree; returns the
/// CPU's.
fn assert_counted(renderer: &mut GpuRenderer<'_>, prepared: &PreparedScene, source: usize) -> u64 {
    let gpu = renderer.render(prepared).expect("GPU render");
    let cpu = reference::try_render(prepared).expect("CPU render");
    eprintln!("GPU stats: {:?}", gpu.stats);
    eprintln!("CPU stats: {:?}", cpu.stats);
    let (g, c) = (counts(&gpu.stats), counts(&cpu.stats));
    for other in (0..3).filter(|&s| s != source) {
        assert_eq!(
            (g[other], c[other]),
            (0, 0),
            "source {other}: GPU {g:?}, CPU {c:?}"
        );
    }
    assert!(g[source] > 0 && c[source] > 0, "GPU {g:?}, CPU {c:?}");
    assert_counts_close("non-finite points", g[source], c[source]);
    assert_counts_close("grids diced", gpu.stats.grids_diced, cpu.stats.grids_diced);
    c[source]
}

/// The teapot at 64 x 48, 1 spp, displaced by `desc`.
fn displaced_teapot(desc: DisplacementDesc) -> Scene {
    let mut scene = framed_teapot(64, 48, 1);
    scene.objects[0].displacement = Some(desc);
    scene
}

/// NaN where u > 1/2, infinity where v > 1/2 (and u <= 1/2), 0 elsewhere:
/// the user's WGSL (NaN and infinity from bit patterns, which no compiler
/// may fold away) and its Rust twin.
const NAN_OR_INFINITY_WGSL: &str = "fn displacement_user(u: f32, v: f32) -> f32 {
    let nan = bitcast<f32>(select(0u, 0x7fc00000u, u > 0.5));
    let infinity_or_zero = bitcast<f32>(select(0u, 0x7f800000u, v > 0.5));
    if (u > 0.5) {
        return nan;
    }
    return infinity_or_zero;
}";

fn nan_or_infinity(u: f32, v: f32) -> f32 {
    if u > 0.5 {
        f32::NAN
    } else if v > 0.5 {
        f32::INFINITY
    } else {
        0.0
    }
}

#[gpu_test]
fn a_user_function_returning_nan_or_infinity_counts_as_displacement() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let scene = displaced_teapot(DisplacementDesc {
        source: "wgsl".into(),
        scale: 0.1,
        bound: Some(0.1),
        tiling: 1.0,
        wgsl: Some(NAN_OR_INFINITY_WGSL.into()),
        file: None,
        parameters: Default::default(),
    });
    let mut prepared = PreparedScene::load(&scene).expect("scene prepares");
    assert!(prepared.set_height_twin(0, CpuHeight::new(nan_or_infinity)));
    assert_counted(&mut renderer, &prepared, 0);
}

/// Sines stay within their scale, so the points displaced by 1e38 are
/// finite; a narrow field of view projects some beyond `f32`.
#[gpu_test]
fn a_displacement_beyond_the_projection_counts_as_camera() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let mut scene = displaced_teapot(DisplacementDesc {
        source: "sines".into(),
        scale: 1e38,
        bound: None,
        tiling: 1.0,
        wgsl: None,
        file: None,
        parameters: Default::default(),
    });
    if let Some(camera) = &mut scene.camera {
        camera.fov_y_degrees = 10.0;
    }
    let prepared = PreparedScene::load(&scene).expect("scene prepares");
    assert_counted(&mut renderer, &prepared, 2);
}

/// A valid scene (its control points are finite at close) whose displaced
/// points the motion scales beyond `f32`: the GPU's `motion_close` loses
/// them, so the transform is their source.
#[gpu_test]
fn a_motion_beyond_f32_counts_as_transform() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let mut scene = displaced_teapot(DisplacementDesc {
        source: "sines".into(),
        scale: 1e30,
        bound: None,
        tiling: 1.0,
        wgsl: None,
        file: None,
        parameters: Default::default(),
    });
    scene.objects[0].transform_close = Some(Transform {
        scale: Scale::Uniform(1e10),
        ..Transform::default()
    });
    let prepared = PreparedScene::load(&scene).expect("scene prepares");
    assert!(prepared.objects[0].motion.is_some());
    let gpu_frame = renderer.render(&prepared).expect("GPU render");
    let cpu_frame = reference::try_render(&prepared).expect("CPU render");
    eprintln!("GPU stats: {:?}", gpu_frame.stats);
    eprintln!("CPU stats: {:?}", cpu_frame.stats);
    let (g, c) = (counts(&gpu_frame.stats), counts(&cpu_frame.stats));
    assert_eq!((g[0], c[0]), (0, 0), "GPU {g:?}, CPU {c:?}");
    assert!(g[1] > 0 && c[1] > 0, "GPU {g:?}, CPU {c:?}");
    assert_counts_close("transform points", g[1], c[1]);
    // Points displaced little stay finite at close but some project beyond f32.
    assert_counts_close("camera points", g[2], c[2]);
}
