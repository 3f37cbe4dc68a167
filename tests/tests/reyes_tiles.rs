//! Screen tiles: a frame whose sample framebuffer exceeds the device's
//! limits (or `GpuOptions::max_tile_samples`) is rendered tile by tile
//! through cropped cameras and pasted together. Tiled frames are compared
//! with the untiled frame and with the CPU reference (`reyes::reference`).
//! They are bit-identical: a tile places every grid point and sample in
//! the full image's pixels (only integer pixel and stratum indices are
//! shifted by its origin), so it splits, dices and samples as the whole
//! frame does, and culls only what lies outside its window.

use std::time::Duration;

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::gpu::renderer::{TILE_ALIGN, plan_tiles};
use reyes::gpu::{GpuOptions, GpuRendered, GpuRenderer, RenderError};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Sampling, Transform};
use tests::reyes_support::{
    Agreement, agreement, as_reference, assert_counts_close, assert_identical, framed_teapot,
    gpu_turn, renderer,
};

/// Run time limit of one megakernel run: it includes llvmpipe's lazy
/// compile of the megakernel on a cold shader cache (over a minute on two
/// cores).
const TIMEOUT: Duration = Duration::from_secs(600);

/// A renderer whose tiles hold at most `max_tile_samples` samples (`None`:
/// the device's limit).
fn capped(gpu: &scheduler::Gpu, max_tile_samples: Option<u64>) -> GpuRenderer<'_> {
    renderer(
        gpu,
        GpuOptions {
            timeout: TIMEOUT,
            max_tile_samples,
            ..GpuOptions::default()
        },
    )
}

/// The teapot of the other GPU tests at `width x height` and `spp`; it
/// crosses the tile borders of the small frames below. Its pixels average
/// their own samples (a box over one pixel), so that the tiles render no
/// margin and the tile counts below are `plan_tiles`' own; filters that
/// reach beyond a pixel are tiled in `reyes_filters_gpu.rs`.
fn teapot(width: u32, height: u32, spp: u32) -> PreparedScene {
    let mut scene = framed_teapot(width, height, spp);
    scene.pixel_filter = reyes::filter::PixelFilter::PIXEL_BOX;
    PreparedScene::load(&scene).expect("scene prepares")
}

/// The thresholds the GPU-vs-CPU tests use for the teapot.
fn assert_agrees(what: &str, a: &Agreement) {
    eprintln!("{what}: {a:?}");
    assert!(
        a.coverage >= 0.15,
        "{what}: coverage {:.3} < 15%",
        a.coverage
    );
    a.assert_at_least(what, 0.995, 0.99);
}

#[gpu_test]
fn tiled_frames_match_the_untiled_frame() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let (width, height, spp) = (200, 150, 4);
    let scene = teapot(width, height, spp);
    let untiled = capped(gpu, None).render(&scene).expect("untiled render");
    assert_eq!(untiled.tiles, 1);
    // A cap that the frame just fits changes nothing.
    let samples = u64::from(width * height * spp);
    let fitting = capped(gpu, Some(samples))
        .render(&scene)
        .expect("render at the cap");
    assert_eq!(fitting.tiles, 1);
    assert!(
        fitting.image.as_raw() == untiled.image.as_raw(),
        "a frame that fits one tile rendered differently"
    );
    let reference = as_reference(&untiled);
    let align = u64::from(TILE_ALIGN);
    // Three full-width bands (64, 64 and 22 rows), then 2 x 3 tiles of
    // 128 or 72 columns and 64 or 22 rows: partial tiles at both edges.
    for (cap, tiles) in [(200 * align, 3), (128 * align, 6)] {
        let cap = cap * u64::from(spp);
        let plan = plan_tiles(width, height, cap / u64::from(spp)).expect("a plan");
        assert_eq!(plan.len(), tiles, "{plan:?}");
        let tiled = capped(gpu, Some(cap)).render(&scene).expect("tiled render");
        eprintln!("{tiles} tiles: {:?}", tiled.stats);
        eprintln!("untiled: {:?}", untiled.stats);
        assert_eq!(tiled.tiles, tiles as u32);
        let what = format!("{tiles} tiles vs untiled");
        assert_agrees(&what, &agreement(&tiled, &reference));
        assert_identical(&what, &tiled, &untiled);
        let (t, u) = (&tiled.stats, &untiled.stats);
        assert_eq!(t.input_patches, u.input_patches);
        assert!(t.micropolygons >= t.grids_diced && t.micropolygons <= 256 * t.grids_diced);
        assert_eq!(t.depth_guard_drops, 0);
        // Every sample is tested by the micropolygons over it, in whichever
        // tile holds it; grids over a tile border are diced in each tile.
        assert_counts_close("samples hit", t.samples_hit, u.samples_hit);
        assert_counts_close("samples tested", t.samples_tested, u.samples_tested);
        assert!(t.grids_diced >= u.grids_diced, "{t:?}");
        assert!(
            t.grids_diced <= 2 * u.grids_diced,
            "{tiles} tiles dice {} grids, the untiled frame {}",
            t.grids_diced,
            u.grids_diced
        );
        assert!(
            (t.largest_micropolygon_px - u.largest_micropolygon_px).abs() <= 0.05,
            "largest micropolygon {} vs {}",
            t.largest_micropolygon_px,
            u.largest_micropolygon_px
        );
    }
}

/// With motion blur and depth of field every sample carries a time and a
/// lens position from tables indexed by absolute pixel coordinates (the
/// per-pixel table repeats every 64 x 64 pixels; Interleave UVT's tiles
/// and their permutations follow absolute pixels), and jitter is
/// hashed from them too: a spinning, defocused, jittered teapot renders
/// bit for bit alike tiled and untiled in every mode.
#[gpu_test]
fn tiled_frames_with_motion_and_depth_of_field_match_the_untiled_frame() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let (width, height, spp) = (200, 150, 4);
    let mut scene = framed_teapot(width, height, spp);
    // No filter margin: the tile counts below are `plan_tiles`' own.
    scene.pixel_filter = reyes::filter::PixelFilter::PIXEL_BOX;
    for object in &mut scene.objects {
        object.transform_close = Some(Transform {
            rotate_degrees: Vec3::new(0.0, 0.0, 10.0),
            ..object.transform
        });
    }
    scene.lens.aperture = 0.1;
    scene.jitter = true;
    let cap = 128 * u64::from(TILE_ALIGN) * u64::from(spp);
    let (mut whole, mut tiled) = (capped(gpu, None), capped(gpu, Some(cap)));
    // Interleave UVT with 3 x 3 tiles too: tile origins (multiples of 64
    // pixels) are not multiples of 3, so its tiles must follow absolute
    // pixel coordinates.
    for (mode, interleave_tile) in [
        (Sampling::Bbox, 2),
        (Sampling::Simple, 2),
        (Sampling::Interleave, 2),
        (Sampling::Interleave, 3),
        (Sampling::Interval, 2),
        (Sampling::Adaptive, 4),
    ] {
        scene.sampling = mode;
        scene.interleave_tile = interleave_tile;
        let mode = format!("{mode:?}, K = {interleave_tile}");
        let prepared = PreparedScene::load(&scene).expect("scene prepares");
        assert!(prepared.samples_time_and_lens());
        let untiled = whole.render(&prepared).expect("untiled render");
        let tiles = tiled.render(&prepared).expect("tiled render");
        assert_eq!((untiled.tiles, tiles.tiles), (1, 6));
        let a = agreement(&tiles, &as_reference(&untiled));
        eprintln!("{mode}: {a:?}");
        assert!(a.coverage >= 0.15, "{mode}: coverage {:.3}", a.coverage);
        a.assert_at_least(&mode, 0.995, 0.99);
        assert_identical(&mode, &tiles, &untiled);
        assert_counts_close(
            "samples hit",
            tiles.stats.samples_hit,
            untiled.stats.samples_hit,
        );
    }
}

/// 800 x 600 at 64 spp needs a 234 MiB sample framebuffer, more than
/// lavapipe's 128 MiB per buffer: it renders in tiles and agrees with the
/// CPU reference.
#[gpu_test]
fn a_frame_over_the_device_limit_renders_in_tiles() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let scene = teapot(800, 600, 64);
    let limits = gpu.device.limits();
    let limit = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let needed = 8 * 800 * 600 * 64;
    let gpu_frame = capped(gpu, None)
        .render(&scene)
        .expect("tiled render of a frame over the device limit");
    eprintln!(
        "{} tiles, {:.0} ms; GPU stats: {:?}",
        gpu_frame.tiles, gpu_frame.timings.total_wall_ms, gpu_frame.stats
    );
    if needed > limit {
        assert!(gpu_frame.tiles > 1, "{needed} > {limit} but one tile");
    } else {
        eprintln!("NOTICE: this device holds {needed} bytes in one buffer; no tiling needed");
    }
    let cpu = reference::render(&scene);
    eprintln!("CPU stats: {:?}", cpu.stats);
    assert_agrees("tiled GPU vs CPU", &agreement(&gpu_frame, &cpu));
    let (g, c) = (&gpu_frame.stats, &cpu.stats);
    assert_eq!(g.input_patches, c.input_patches);
    assert_counts_close("samples hit", g.samples_hit, c.samples_hit);
    assert_counts_close("samples tested", g.samples_tested, c.samples_tested);
    assert!(g.grids_diced >= c.grids_diced * 99 / 100, "{g:?}");
    assert_eq!(gpu_frame.overflow_retries, 0);
}

#[gpu_test]
fn frames_that_tiling_cannot_fix_are_too_large() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let expect_too_large = |what: &str, result: Result<GpuRendered, RenderError>| match result {
        Err(e @ RenderError::TooLarge { needed, limit, .. }) => {
            eprintln!("{what}: {e}");
            assert!(needed > limit, "{what}: {needed} <= {limit}");
        }
        other => panic!("{what}: expected RenderError::TooLarge, got {other:?}"),
    };
    let spp = 4;
    let align = u64::from(TILE_ALIGN);
    // Not even one 64 x 64 tile fits the cap.
    let mut small = capped(gpu, Some(align * align * u64::from(spp) - 1));
    expect_too_large(
        "64x64 tile over the cap",
        small.render(&teapot(200, 150, spp)),
    );
    // The same renderer still renders a frame that fits.
    let frame = small
        .render(&teapot(64, 48, 1))
        .expect("a frame under the cap");
    assert_eq!(frame.tiles, 1);
    // A one-row image whose aligned 64-pixel piece of a row does not fit.
    let scene = teapot(5000, 1, spp);
    expect_too_large(
        "64-pixel row piece over the cap",
        capped(gpu, Some(align * u64::from(spp) - 1)).render(&scene),
    );
    // The whole RGBA image exceeds a device buffer.
    let scene = teapot(60_000, 60_000, spp);
    expect_too_large("image", capped(gpu, None).render(&scene));
}
