//! Sample counts above 64 (`k x k` up to 16 x 16 = 256 samples per pixel):
//! the GPU agrees with the CPU reference at 100, 144 and 256 spp, still and
//! blurred, both count every sample of a pixel inside the teapot, and a
//! 256-spp frame whose sample framebuffer exceeds the tile limit renders in
//! screen tiles like the untiled frame, or is refused when not even one
//! tile fits.

use std::time::Duration;

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::gpu::renderer::TILE_ALIGN;
use reyes::gpu::{GpuOptions, GpuRendered, RenderError};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Sampling, Scene, Transform};
use tests::reyes_support::{
    agreement, as_reference, assert_counts_close, framed_teapot, gpu_turn, renderer,
};

/// Run time limit of one megakernel run, llvmpipe's lazy compile of the
/// megakernel on a cold shader cache included.
const TIMEOUT: Duration = Duration::from_secs(600);

/// The sample counts above the former cap of 64 that the tests render.
const HIGH_SPP: [u32; 3] = [100, 144, 256];

/// A renderer whose screen tiles hold at most `max_tile_samples` samples
/// (`None`: the device's limit).
fn capped(gpu: &scheduler::Gpu, max_tile_samples: Option<u64>) -> reyes::gpu::GpuRenderer<'_> {
    renderer(
        gpu,
        GpuOptions {
            timeout: TIMEOUT,
            max_tile_samples,
            ..GpuOptions::default()
        },
    )
}

/// The pixels with every one of their `spp` samples covered, on the GPU
/// and on the CPU: some, as many on both (within 1%), and no pixel counts
/// more than `spp`. A count kept in a byte reads 256 as 0.
fn assert_full_pixels(what: &str, spp: u32, gpu: &GpuRendered, cpu: &reference::Rendered) {
    let full = |counts: &[u16]| {
        assert!(counts.iter().all(|&c| u32::from(c) <= spp), "{what}");
        counts.iter().filter(|&&c| u32::from(c) == spp).count() as u64
    };
    let (g, c) = (full(&gpu.covered_samples), full(&cpu.covered_samples));
    eprintln!("{what}: {g} pixels fully covered on the GPU, {c} on the CPU");
    assert!(c >= 100, "{what}: only {c} pixels fully covered");
    assert_counts_close(&format!("{what}: full pixels"), g, c);
}

/// Renders `scene` on the GPU and the CPU and checks that they agree.
fn assert_matches_reference(what: &str, renderer: &mut reyes::gpu::GpuRenderer<'_>, scene: &Scene) {
    let prepared = PreparedScene::load(scene).expect("scene prepares");
    let g = renderer.render(&prepared).expect("GPU render");
    let c = reference::render(&prepared);
    let a = agreement(&g, &c);
    eprintln!("{what}: {a:?}");
    assert!(a.coverage >= 0.1, "{what}: coverage {:.3}", a.coverage);
    a.assert_at_least(what, 0.99, 0.98);
    assert_counts_close(
        &format!("{what}: samples hit"),
        g.stats.samples_hit,
        c.stats.samples_hit,
    );
    assert_full_pixels(what, scene.spp, &g, &c);
}

#[gpu_test]
fn high_sample_counts_match_the_cpu_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = capped(gpu, None);
    for spp in HIGH_SPP {
        let scene = framed_teapot(64, 48, spp);
        assert_matches_reference(&format!("still, {spp} spp"), &mut renderer, &scene);
    }
}

/// The tables sized by the sample count (Interleave UVT's `spp * K^2`
/// tuples, its inverse permutations and slots, the per-pixel table,
/// INTERVAL's strata) at the largest counts, under motion and a lens.
#[gpu_test]
fn blurred_high_sample_counts_match_the_cpu_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = capped(gpu, None);
    for (spp, sampling, tile) in [(256, Sampling::Interleave, 2), (144, Sampling::Adaptive, 3)] {
        let mut scene = framed_teapot(64, 48, spp);
        for object in &mut scene.objects {
            object.transform_close = Some(Transform {
                rotate_degrees: Vec3::new(0.0, 0.0, 20.0),
                ..object.transform
            });
        }
        scene.lens.aperture = 0.1;
        scene.sampling = sampling;
        scene.interleave_tile = tile;
        let what = format!("{sampling:?}, K = {tile}, {spp} spp");
        assert_matches_reference(&what, &mut renderer, &scene);
    }
}

/// 128 x 96 at 256 spp under a cap of one 64 x 64 tile's samples renders
/// in tiles and agrees with the untiled frame; under a cap one sample
/// short of that tile it is refused with the typed error.
#[gpu_test]
fn a_256_spp_frame_over_the_tile_limit_renders_in_tiles_or_is_refused() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let spp = 256;
    let mut scene = framed_teapot(128, 96, spp);
    // Each pixel averages its own samples: tiles render no margin.
    scene.pixel_filter = reyes::filter::PixelFilter::PIXEL_BOX;
    let prepared = PreparedScene::load(&scene).expect("scene prepares");
    let tile = u64::from(TILE_ALIGN) * u64::from(TILE_ALIGN) * u64::from(spp);
    let untiled = capped(gpu, None).render(&prepared).expect("untiled");
    let tiled = capped(gpu, Some(tile)).render(&prepared).expect("tiled");
    assert_eq!((untiled.tiles, tiled.tiles), (1, 4));
    let a = agreement(&tiled, &as_reference(&untiled));
    eprintln!("tiled against untiled: {a:?}");
    a.assert_at_least("tiled, 256 spp", 0.995, 0.99);
    assert_counts_close(
        "samples hit",
        tiled.stats.samples_hit,
        untiled.stats.samples_hit,
    );
    match capped(gpu, Some(tile - 1)).render(&prepared) {
        Err(RenderError::TooLarge {
            needed,
            limit,
            spp: 256,
            ..
        }) => {
            assert_eq!((needed, limit), (8 * tile, 8 * (tile - 1)));
        }
        other => panic!("expected RenderError::TooLarge, got {other:?}"),
    }
}
