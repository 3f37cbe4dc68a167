//! The GPU renderer's outputs: the resolve reads back linear floats, which
//! the host encodes (Exposure, sRGB, Quantize with its dither) exactly as
//! the CPU reference does, whole or in screen tiles, and which an EXR holds
//! as they are. The formulas themselves are checked in
//! `reyes/src/quantize/tests.rs` and `reyes/tests/exposure.rs`.

use gpu_test::gpu_test;
use reyes::gpu::GpuOptions;
use reyes::prepare::PreparedScene;
use reyes::quantize::{Encoding, Exposure, Quantize};
use reyes::reference;
use reyes::scene::Scene;
use tests::reyes_support::{
    agreement, camera_down_z, framed_teapot, gpu_turn, patient_renderer, renderer,
};

/// The sRGB transfer function in f64 (IEC 61966-2-1).
fn srgb(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Asserts two images are equal, naming the first pixel that differs (an
/// image is too long to print whole).
fn assert_same<P>(
    a: &image::ImageBuffer<P, Vec<P::Subpixel>>,
    b: &image::ImageBuffer<P, Vec<P::Subpixel>>,
    what: &str,
) where
    P: image::Pixel + PartialEq + std::fmt::Debug,
{
    assert_eq!(a.dimensions(), b.dimensions(), "{what}: sizes");
    if let Some((x, y, p)) = a
        .enumerate_pixels()
        .find(|&(x, y, p)| p != b.get_pixel(x, y))
    {
        panic!(
            "{what}: pixel ({x}, {y}) is {p:?} and {:?}",
            b.get_pixel(x, y)
        );
    }
}

/// An empty frame whose every pixel is the grey background `c`: one
/// sample per pixel through a box over the pixel.
fn flat(c: f32, size: u32, exposure: Exposure, quantize: Quantize) -> PreparedScene {
    let mut scene = Scene {
        spp: 1,
        background: glam::Vec3::splat(c),
        lights: Vec::new(),
        pixel_filter: reyes::filter::PixelFilter::PIXEL_BOX,
        camera: Some(camera_down_z()),
        exposure,
        quantize,
        ..Scene::default()
    };
    scene.resolution.width = size;
    scene.resolution.height = size;
    PreparedScene::new(&scene, &[]).expect("the flat scene prepares")
}

#[gpu_test]
fn a_flat_field_encodes_as_on_the_cpu() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut r = renderer(gpu, GpuOptions::default());
    // sRGB(c) * 255 = 87.35: codes 87 and 88.
    let c = (((87.35f64 / 255.0 + 0.055) / 1.055).powf(2.4)) as f32;
    let x = 255.0 * srgb(f64::from(c));
    let scene = flat(c, 256, Exposure::default(), Quantize::default());
    let frame = r.render(&scene).expect("GPU render");
    assert!(
        frame.linear.pixels().all(|p| p.0 == [c, c, c, 1.0]),
        "the resolve keeps the background as it is"
    );
    let values: Vec<u8> = frame.image.pixels().map(|p| p[1]).collect();
    assert!(values.iter().all(|&v| v == 87 || v == 88));
    let mean = values.iter().map(|&v| f64::from(v)).sum::<f64>() / values.len() as f64;
    assert!((mean - x).abs() < 0.01, "mean {mean} vs one * c = {x}");
    assert_same(
        &frame.image,
        &reference::render(&scene).image,
        "GPU and CPU codes",
    );
    // Gain 2, no dither: the doubled value, rounded.
    let gained = flat(
        0.18,
        16,
        Exposure {
            gain: 2.0,
            gamma: 1.0,
        },
        Quantize::NO_DITHER,
    );
    let want = (255.0 * srgb(2.0 * 0.18f64)).round() as u8;
    let frame = r.render(&gained).expect("GPU render");
    assert!(frame.image.pixels().all(|p| p.0 == [want, want, want, 255]));
}

/// The 96 x 72 teapot, jittered, 4 samples per pixel, with an exposure
/// and a dither.
fn exposed_teapot(gain: f32) -> PreparedScene {
    let mut scene = framed_teapot(96, 72, 4);
    scene.jitter = true;
    scene.exposure = Exposure { gain, gamma: 1.4 };
    scene.quantize.dither_amplitude = 0.75;
    PreparedScene::load(&scene).expect("scene prepares")
}

#[gpu_test]
fn the_teapot_s_floats_match_the_reference_and_are_encoded_the_same() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut whole = patient_renderer(gpu);
    // 19,200 samples a tile: fewer than the frame's 27,648, more than the
    // smallest aligned tile with its filter's margin (66 x 66 x 4).
    let mut tiled = renderer(
        gpu,
        GpuOptions {
            max_tile_samples: Some(96 * 50 * 4),
            timeout: tests::reyes_support::COLD_COMPILE_TIMEOUT,
            ..GpuOptions::default()
        },
    );
    let scene = exposed_teapot(1.7);
    let frame = whole.render(&scene).expect("GPU render");
    let cpu = reference::render(&scene);
    agreement(&frame, &cpu).assert_at_least("exposed teapot", 0.995, 0.99);
    // The 8-bit image is the host's encoding of the floats read back.
    assert_same(
        &frame.image,
        &scene.encoding.encode(&frame.linear, [0, 0]),
        "the GPU's codes against the encoding of its floats",
    );
    // Equal floats give equal codes on both renderers. Many floats differ
    // in their last bits (the GPU contracts the filter's sums into fused
    // multiply-adds), so only about a sixth are equal here (1,072 of
    // 6,912 on lavapipe).
    let mut equal = 0;
    for (x, y, g) in frame.linear.enumerate_pixels() {
        let c = cpu.linear.get_pixel(x, y);
        if g == c {
            equal += 1;
            assert_eq!(frame.image.get_pixel(x, y), cpu.image.get_pixel(x, y));
        }
        for k in 0..3 {
            assert!((g[k] - c[k]).abs() < 0.05, "({x}, {y}): {g:?} vs {c:?}");
        }
    }
    let pixels = frame.linear.len() / 4;
    eprintln!("{equal} of {pixels} pixels have equal floats");
    assert!(equal * 10 > pixels, "only {equal} of {pixels} equal floats");
    // The EXR is the floats, whatever the exposure.
    let other = whole.render(&exposed_teapot(0.3)).expect("GPU render");
    assert_same(
        &other.linear,
        &frame.linear,
        "the exposure changed the floats",
    );
    assert!(other.image != frame.image, "the exposure changed no code");
    let dir = std::env::temp_dir().join(format!("reyes-output-gpu-{}", std::process::id()));
    let exr = dir.join("teapot.exr");
    reyes::output::write_rendered_image(&frame.image, &frame.linear, &exr).unwrap();
    let back = image::open(&exr).unwrap();
    assert_same(
        back.as_rgba32f().expect("the EXR holds Rgba32F"),
        &frame.linear,
        "the EXR against the floats",
    );
    std::fs::remove_dir_all(&dir).unwrap();
    // In tiles the dither follows absolute pixels: where a tile's floats
    // equal the whole frame's, so do the codes.
    let tiles = tiled.render(&scene).expect("tiled GPU render");
    assert!(tiles.tiles > 1, "{} tile(s)", tiles.tiles);
    let mut same = 0;
    for (x, y, t) in tiles.linear.enumerate_pixels() {
        if t == frame.linear.get_pixel(x, y) {
            same += 1;
            assert_eq!(tiles.image.get_pixel(x, y), frame.image.get_pixel(x, y));
        }
    }
    eprintln!("{same} of {pixels} pixels have the whole frame's floats in tiles");
    assert!(
        same * 2 > pixels,
        "only {same} of {pixels} equal floats in tiles"
    );
    assert_eq!(
        Encoding::default().quantize.dither_amplitude,
        0.5,
        "RenderMan's default"
    );
}
