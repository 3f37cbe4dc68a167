//! The 32-bit depth test ([`DepthTest::TwoPass32`]), which devices without
//! 64-bit atomics run (wgpu's GL backend among them), against the 64-bit
//! one on the same device: each keeps per sample the least key
//! `depth << 32 | colour`, so the two frames must be equal bit for bit,
//! counters included. The scenes cover what could tell them apart:
//! surfaces hiding each other across batches of input patches (a depth and
//! colour pass per batch would leave a hidden surface's colour), screen
//! tiles, motion blur with displacement, shadow maps rendered by depth
//! passes, and the depth output (one pass).

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::displacement::DisplacementDesc;
use reyes::gpu::{DepthTest, GpuOptions, GpuRendered};
use reyes::prepare::PreparedScene;
use reyes::scene::{LightShadow, Scene, ShadowMaps};
use tests::reyes_support::{COLD_COMPILE_TIMEOUT, framed_teapot, gpu_turn, renderer};

/// Asserts that `two_pass` is `wide`'s frame: the same floats, coverage and
/// counters (but the time).
fn assert_same_frame(what: &str, wide: &GpuRendered, two_pass: &GpuRendered) {
    let differing = wide
        .linear
        .as_raw()
        .iter()
        .zip(two_pass.linear.as_raw())
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differing, 0, "{what}: channels that differ");
    assert!(wide.coverage == two_pass.coverage, "{what}: coverage");
    assert!(
        wide.covered_samples == two_pass.covered_samples,
        "{what}: covered samples"
    );
    let timeless = |frame: &GpuRendered| {
        let mut stats = frame.stats.clone();
        stats.frame_time_ms = None;
        for pass in &mut stats.passes {
            pass.frame_time_ms = None;
        }
        stats
    };
    assert_eq!(timeless(wide), timeless(two_pass), "{what}: counters");
    assert_eq!(wide.tiles, two_pass.tiles, "{what}: tiles");
    assert_eq!(wide.batches, two_pass.batches, "{what}: batches");
    // Not a frame of nothing: the comparison would hold trivially.
    let covered = wide.coverage.iter().filter(|&&c| c).count();
    assert!(
        covered > wide.coverage.len() / 20,
        "{what}: {covered} pixels covered"
    );
}

/// The teapot moving and displaced, sampled in time and lens.
fn blurred_displaced_teapot() -> Scene {
    let mut scene = framed_teapot(96, 72, 4);
    scene.sampling = reyes::modes::Sampling::Interleave;
    let teapot = &mut scene.objects[0];
    teapot.displacement = Some(DisplacementDesc {
        source: "sines".to_owned(),
        scale: 0.05,
        bound: None,
        tiling: 2.0,
        wgsl: None,
        file: None,
        parameters: Default::default(),
    });
    let mut close = teapot.transform;
    close.translate += Vec3::new(0.4, 0.0, 0.1);
    teapot.transform_close = Some(close);
    scene
}

/// docs/scenes/shadows-teapot.toml, small: a distant light and a spotlight
/// whose shadow maps the renderer renders before the frame.
fn shadowed_teapot() -> Scene {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/scenes/shadows-teapot.toml");
    let mut scene = Scene::load(&path).expect("the shadow scene loads");
    scene.resolution.width = 160;
    scene.resolution.height = 90;
    scene.spp = 4;
    for light in &mut scene.lights {
        if let Some(LightShadow {
            maps: ShadowMaps::Automatic { map_size },
            ..
        }) = &mut light.shadow
        {
            *map_size = 256;
        }
    }
    assert!(
        scene.lights.iter().filter(|l| l.shadow.is_some()).count() == 2,
        "both lights cast shadows"
    );
    scene
}

/// Renders `scenes` with the 64-bit test and the two-pass test (renderers
/// made with `options`), and compares each pair of frames.
fn compare(gpu: &scheduler::Gpu, options: GpuOptions, scenes: Vec<(&str, Scene)>) {
    let wide_atomics = gpu
        .device
        .features()
        .contains(reyes::gpu::graph::WIDE_ATOMICS);
    let mut wide = renderer(gpu, options.clone());
    let mut two_pass = renderer(
        gpu,
        GpuOptions {
            two_pass_depth_test: true,
            ..options
        },
    );
    for (what, scene) in scenes {
        let prepared = PreparedScene::load(&scene).expect("the scene prepares");
        let frames = [&mut wide, &mut two_pass]
            .map(|renderer| renderer.render(&prepared).expect("the frame renders"));
        assert_eq!(
            two_pass.variant().depth_test,
            DepthTest::TwoPass32,
            "{what}"
        );
        if wide_atomics {
            assert_eq!(wide.variant().depth_test, DepthTest::Key64, "{what}");
        }
        eprintln!(
            "{what}: {} batches, {} tiles, megakernel {:.0} ms (64-bit test) and {:.0} ms (two passes)",
            frames[0].batches,
            frames[0].tiles,
            frames[0].timings.megakernel_wall_ms,
            frames[1].timings.megakernel_wall_ms
        );
        assert_same_frame(what, &frames[0], &frames[1]);
    }
}

#[gpu_test]
fn the_two_pass_depth_test_gives_the_frame_of_the_64_bit_test() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let options = GpuOptions {
        timeout: COLD_COMPILE_TIMEOUT,
        // Eight batches of the teapot's 32 patches: its spout and lid hide
        // parts of its body drawn in other batches.
        max_batch_patches: Some(4),
        ..GpuOptions::default()
    };
    let teapot = framed_teapot(96, 72, 4);
    let mut depth = teapot.clone();
    depth.aov = reyes::Aov::Z;
    compare(
        gpu,
        options.clone(),
        vec![
            ("teapot in batches of 4 patches", teapot),
            ("depth output", depth),
            ("moving displaced teapot", blurred_displaced_teapot()),
            ("two shadowed lights", shadowed_teapot()),
        ],
    );
    let tiled = GpuOptions {
        max_tile_samples: Some(192 * 144 * 4 / 3),
        ..options
    };
    compare(
        gpu,
        tiled,
        vec![("teapot in screen tiles", framed_teapot(192, 144, 4))],
    );
}
