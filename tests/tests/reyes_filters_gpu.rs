//! Pixel filters on the GPU: the resolve shader filters as the CPU
//! reference does for each of RenderMan's filters (at 1 and 16 samples per
//! pixel, whole and in screen tiles), and a frame rendered in
//! screen tiles, each with the margin its filter reaches beyond it, equals
//! the frame rendered whole bit for bit (as `reyes_tiles.rs` explains). The filters themselves are
//! checked against their definitions in `reyes/tests/pixel_filters.rs`.

use gpu_test::gpu_test;
use reyes::filter::{FilterKind, PixelFilter};
use reyes::gpu::GpuOptions;
use reyes::prepare::PreparedScene;
use reyes::reference;
use tests::reyes_support::{
    agreement, as_reference, assert_identical, framed_teapot, gpu_turn, renderer, tiled_renderer,
};

/// The jittered teapot at 192 x 144, `spp` samples per pixel, with `filter`.
fn teapot(filter: PixelFilter, spp: u32) -> PreparedScene {
    let mut scene = framed_teapot(192, 144, spp);
    scene.jitter = true;
    scene.pixel_filter = filter;
    PreparedScene::load(&scene).expect("scene prepares")
}

#[gpu_test]
fn every_filter_matches_the_reference_whole_and_in_tiles() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut whole = renderer(gpu, GpuOptions::default());
    for spp in [1, 16] {
        // 192 x 64 pixels at most: the frame needs several tiles once a
        // margin is added.
        let mut tiled = tiled_renderer(gpu, 192 * 64 * u64::from(spp));
        for (filter, xwidth, ywidth) in [
            (FilterKind::Box, 1.0, 1.0),
            (FilterKind::Triangle, 2.0, 2.0),
            (FilterKind::Gaussian, 2.0, 2.0),
            (FilterKind::CatmullRom, 3.0, 3.0),
            (FilterKind::Sinc, 4.0, 3.0),
        ] {
            let filter = PixelFilter {
                filter,
                xwidth,
                ywidth,
            };
            let scene = teapot(filter, spp);
            let what = format!("{} {xwidth}x{ywidth} at spp {spp}", filter.filter.name());
            let gpu_whole = whole.render(&scene).expect("GPU render");
            assert_eq!(gpu_whole.tiles, 1);
            let cpu = reference::render(&scene);
            let a = agreement(&gpu_whole, &cpu);
            eprintln!("{what}, GPU against the reference: {a:?}");
            a.assert_at_least(&what, 0.995, 0.99);
            let gpu_tiled = tiled.render(&scene).expect("tiled GPU render");
            assert!(gpu_tiled.tiles > 1, "{what}: {} tile(s)", gpu_tiled.tiles);
            let what = format!("{what} in {} tiles", gpu_tiled.tiles);
            let r = agreement(&gpu_tiled, &cpu);
            eprintln!("{what} against the reference: {r:?}");
            r.assert_at_least(&what, 0.995, 0.99);
            let t = agreement(&gpu_tiled, &as_reference(&gpu_whole));
            eprintln!("{what} against the whole frame: {t:?}");
            t.assert_at_least(&what, 0.995, 0.995);
            // Bit for bit: without the margins the pixels along the tiles'
            // borders lose their neighbours' samples (by up to 25/255 at 4
            // samples per pixel).
            assert_identical(&what, &gpu_tiled, &gpu_whole);
        }
    }
}

/// The default filter is RenderMan's gaussian 2 x 2, and it blurs: an edge
/// pixel differs from the box filter's.
#[gpu_test]
fn the_default_filter_is_renderman_s_gaussian() {
    assert_eq!(
        reyes::scene::Scene::default().pixel_filter,
        PixelFilter {
            filter: FilterKind::Gaussian,
            xwidth: 2.0,
            ywidth: 2.0
        }
    );
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut r = renderer(gpu, GpuOptions::default());
    let gaussian = r
        .render(&teapot(PixelFilter::default(), 4))
        .expect("render");
    let boxed = r
        .render(&teapot(PixelFilter::PIXEL_BOX, 4))
        .expect("render");
    let differ = gaussian
        .image
        .pixels()
        .zip(boxed.image.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > 1000, "only {differ} pixels differ");
}
