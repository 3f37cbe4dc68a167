//! The encoding against its formulas, computed here in f64.

use image::Rgba;

use super::*;

/// The sRGB transfer function in f64 (IEC 61966-2-1), continued above 1.
fn srgb(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// `round(x)` to a code, asserting that `x` is not so close to a half
/// that f32 and f64 could round it differently.
fn nearest_code(x: f64) -> u8 {
    let distance = (x - x.floor() - 0.5).abs();
    assert!(distance > 1e-3, "{x} is too close to a half for this test");
    x.round().clamp(0.0, 255.0) as u8
}

fn no_dither(exposure: Exposure) -> Encoding {
    Encoding {
        exposure,
        quantize: Quantize::NO_DITHER,
    }
}

#[test]
fn defaults_are_renderman_s() {
    assert_eq!(
        Exposure::default(),
        Exposure {
            gain: 1.0,
            gamma: 1.0
        }
    );
    let q = Quantize::default();
    assert_eq!(
        (q.one, q.min, q.max, q.dither_amplitude),
        (255.0, 0.0, 255.0, 0.5)
    );
    assert_eq!(Exposure::default().problem(), None);
    assert_eq!(q.problem(), None);
}

#[test]
fn gain_two_doubles_the_linear_value_before_encoding() {
    let doubled = no_dither(Exposure {
        gain: 2.0,
        gamma: 1.0,
    });
    for c in [0.1f32, 0.18, 0.2, 0.3, 0.45] {
        let want = nearest_code(255.0 * srgb(2.0 * f64::from(c)));
        assert_eq!(doubled.color_code(c, 3, 4, 0), want, "c = {c}");
        assert_eq!(
            Encoding::PLAIN.color_code(2.0 * c, 3, 4, 0),
            want,
            "c = {c}"
        );
    }
    // Above 1 it clips at `max`.
    assert_eq!(doubled.color_code(0.6, 0, 0, 1), 255);
}

#[test]
fn gamma_raises_to_one_over_gamma() {
    let gamma = no_dither(Exposure {
        gain: 1.0,
        gamma: 2.2,
    });
    for c in [0.02f32, 0.1, 0.18, 0.5, 0.8] {
        let want = nearest_code(255.0 * srgb(f64::from(c).powf(1.0 / 2.2)));
        assert_eq!(gamma.color_code(c, 0, 0, 2), want, "c = {c}");
    }
}

#[test]
fn the_default_encoding_without_dither_is_the_old_srgb8() {
    // Gain 1, gamma 1, one 255 and no dither: exactly
    // `crate::color::linear_to_srgb8`, what the resolve wrote before.
    for i in 0..=4096 {
        let c = i as f32 / 4000.0 - 0.01;
        assert_eq!(
            Encoding::PLAIN.color_code(c, 0, 0, 0),
            crate::color::linear_to_srgb8(c),
            "c = {c}"
        );
    }
}

#[test]
fn min_max_and_one_shape_the_codes() {
    let q = Quantize {
        one: 100.0,
        min: 10.0,
        max: 200.0,
        dither_amplitude: 0.0,
    };
    assert_eq!(q.code(0.0, 0.0), 10);
    assert_eq!(q.code(0.5, 0.0), 50);
    assert_eq!(q.code(1.5, 0.0), 150, "above `one`, up to `max`");
    assert_eq!(q.code(9.0, 0.0), 200);
    assert_eq!(q.code(f32::NAN, 0.0), 10);
    assert_eq!(q.code(0.305, 0.0), 31, "halves round up");
}

/// A flat field of linear value `c` at `width x height`, encoded.
fn flat(encoding: &Encoding, c: f32, width: u32, height: u32) -> RgbaImage {
    let linear = Rgba32FImage::from_pixel(width, height, Rgba([c, c, c, 1.0]));
    encoding.encode(&linear, [0, 0])
}

#[test]
fn dither_keeps_the_mean_between_two_codes() {
    // sRGB(c) * 255 = 100.3: codes 100 and 101, 101 with probability 0.3.
    let target = 100.3f64;
    let c = ((target / 255.0 + 0.055) / 1.055).powf(2.4) as f32;
    let x = 255.0 * srgb(f64::from(c));
    let (lo, hi) = (x.floor() as u8, x.ceil() as u8);
    assert_eq!((lo, hi), (100, 101));
    let encoding = Encoding::default();
    let image = flat(&encoding, c, 256, 256);
    for channel in 0..3 {
        let values: Vec<u8> = image.pixels().map(|p| p[channel]).collect();
        assert!(
            values.iter().all(|&v| v == lo || v == hi),
            "channel {channel}: a value outside {lo}..={hi}"
        );
        let mean = values.iter().map(|&v| f64::from(v)).sum::<f64>() / values.len() as f64;
        assert!(
            (mean - x).abs() < 0.01,
            "channel {channel}: mean {mean}, one * c = {x}"
        );
    }
    assert!(image.pixels().all(|p| p[3] == 255), "alpha stays 255");
    // Without dither every pixel is the rounded value.
    let plain = flat(&Encoding::PLAIN, c, 64, 64);
    assert!(plain.pixels().all(|p| p.0[0..3] == [lo, lo, lo]));
}

#[test]
fn dither_is_uniform_in_minus_one_one() {
    let n = 1 << 16;
    let values: Vec<f32> = (0..n).map(|i| dither(i % 256, i / 256, i % 4)).collect();
    assert!(values.iter().all(|r| (-1.0..1.0).contains(r)));
    let mean = values.iter().map(|&r| f64::from(r)).sum::<f64>() / f64::from(n);
    // The mean of n uniform values on [-1, 1) has a standard deviation of
    // sqrt(1/3 / n) = 0.0023.
    assert!(mean.abs() < 0.01, "mean {mean}");
    let below: usize = values.iter().filter(|&&r| r < -0.5).count();
    let share = below as f64 / f64::from(n);
    assert!((share - 0.25).abs() < 0.01, "share below -0.5: {share}");
}

#[test]
fn a_tile_encodes_as_its_part_of_the_frame() {
    // 600 x 500 takes several bands on a machine with several threads.
    let (width, height) = (600, 500);
    let linear = Rgba32FImage::from_fn(width, height, |x, y| {
        let v = ((x * 7 + y * 13) % 97) as f32 / 97.0;
        Rgba([v, 1.0 - v, 0.5 * v, 1.0])
    });
    let encoding = Encoding::default();
    let frame = encoding.encode(&linear, [0, 0]);
    let (x0, y0, tw, th) = (128, 64, 200, 150);
    let tile_linear = image::imageops::crop_imm(&linear, x0, y0, tw, th).to_image();
    let tile = encoding.encode(&tile_linear, [x0, y0]);
    for (x, y, pixel) in tile.enumerate_pixels() {
        assert_eq!(pixel, frame.get_pixel(x0 + x, y0 + y), "({x}, {y})");
    }
    // And pixel by pixel, as one thread would.
    for (x, y, pixel) in frame.enumerate_pixels().step_by(997) {
        let p = linear.get_pixel(x, y);
        for c in 0..3 {
            assert_eq!(pixel[c], encoding.color_code(p[c], x, y, c as u32));
        }
    }
}

#[test]
fn problems_name_the_value_and_the_range() {
    let bad_exposures = [
        (-1.0, 1.0, "gain -1 is outside [0, inf)"),
        (f32::NAN, 1.0, "gain NaN"),
        (1.0, 0.0, "gamma 0 is outside (0, inf)"),
        (1.0, f32::INFINITY, "gamma inf"),
    ];
    for (gain, gamma, want) in bad_exposures {
        let problem = Exposure { gain, gamma }.problem().expect("refused");
        assert!(problem.contains(want), "{problem}");
    }
    let q = Quantize::default();
    let bad_quantizes = [
        (Quantize { one: 0.0, ..q }, "one 0 is outside (0, 65535]"),
        (
            Quantize { min: -1.0, ..q },
            "min -1 is not a whole number in [0, 255]",
        ),
        (Quantize { max: 256.0, ..q }, "max 256"),
        (Quantize { max: 2.5, ..q }, "max 2.5"),
        (
            Quantize {
                min: 9.0,
                max: 8.0,
                ..q
            },
            "min 9 is above max 8",
        ),
        (
            Quantize {
                dither_amplitude: -0.5,
                ..q
            },
            "dither -0.5 is outside [0, 255]",
        ),
        (
            Quantize {
                dither_amplitude: f32::NAN,
                ..q
            },
            "dither NaN",
        ),
    ];
    for (quantize, want) in bad_quantizes {
        let problem = quantize.problem().expect("refused");
        assert!(problem.contains(want), "{problem}");
    }
}
