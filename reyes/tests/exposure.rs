//! Exposure and Quantize (RenderMan's) on the CPU reference: the 8-bit
//! image is `clamp(round(one * sRGB((c * gain)^(1/gamma)) + dither * r),
//! min, max)` of the resolve's linear value `c`, the dither keeps the mean
//! and stays between two codes, and the EXR output holds the linear values
//! untouched. Expectations are computed here from the formulas, in f64.
//! `tests/tests/reyes_output_gpu.rs` checks the GPU renderer against the
//! same formulas and the reference.

mod files;

use std::path::Path;
use std::process::Command;

use files::{TempDir, run_command};
use reyes::prepare::PreparedScene;
use reyes::quantize::{Encoding, Exposure, Quantize};
use reyes::scene::Scene;

/// The sRGB transfer function in f64 (IEC 61966-2-1).
fn srgb(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The linear value whose sRGB encoding is `code / 255`.
fn linear_of_code(code: f64) -> f64 {
    let s = code / 255.0;
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// An empty frame of `width x height` whose every pixel is the background
/// `c` (grey), one sample per pixel through a box over the pixel, with
/// `extra` TOML lines (exposure, quantize).
fn flat_scene(c: f32, width: u32, height: u32, extra: &str) -> PreparedScene {
    let text = format!(
        "spp = 1\nbackground = [{c:?}, {c:?}, {c:?}]\nlights = []\n\
         pixel_filter = {{ filter = \"box\", xwidth = 1.0, ywidth = 1.0 }}\n{extra}\n\
         [resolution]\nwidth = {width}\nheight = {height}\n\
         [camera]\neye = [0.0, -10.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\n"
    );
    let scene = Scene::from_toml_str(&text).expect("the flat scene parses");
    PreparedScene::new(&scene, &[]).expect("the flat scene prepares")
}

/// The reference's 8-bit and linear images of a flat scene.
fn render_flat(c: f32, size: u32, extra: &str) -> reyes::Rendered {
    let rendered = reyes::reference::render(&flat_scene(c, size, size, extra));
    assert!(
        rendered.linear.pixels().all(|p| p.0 == [c, c, c, 1.0]),
        "the resolve keeps the background as it is"
    );
    rendered
}

/// `round(x)`, asserting `x` is not so close to a half that the renderer's
/// f32 could round it the other way.
fn nearest_code(x: f64) -> u8 {
    assert!(
        (x - x.floor() - 0.5).abs() > 1e-3,
        "{x} is too close to a half for this test"
    );
    x.round().clamp(0.0, 255.0) as u8
}

#[test]
fn gain_two_doubles_the_linear_value_before_encoding() {
    // Mid-grey: linear 0.18.
    let c = 0.18f32;
    let plain = render_flat(c, 8, "quantize = { dither = 0.0 }");
    let doubled = render_flat(
        c,
        8,
        "exposure = { gain = 2.0 }\nquantize = { dither = 0.0 }",
    );
    let want_plain = nearest_code(255.0 * srgb(f64::from(c)));
    let want_doubled = nearest_code(255.0 * srgb(2.0 * f64::from(c)));
    assert_ne!(want_plain, want_doubled);
    for (x, y, p) in doubled.image.enumerate_pixels() {
        assert_eq!(
            p.0,
            [want_doubled, want_doubled, want_doubled, 255],
            "({x}, {y})"
        );
        assert_eq!(plain.image.get_pixel(x, y)[0], want_plain);
    }
}

#[test]
fn gamma_raises_the_value_to_one_over_gamma() {
    let c = 0.3f32;
    let rendered = render_flat(
        c,
        8,
        "exposure = { gamma = 2.2 }\nquantize = { dither = 0.0 }",
    );
    let want = nearest_code(255.0 * srgb(f64::from(c).powf(1.0 / 2.2)));
    assert!(
        rendered
            .image
            .pixels()
            .all(|p| p.0 == [want, want, want, 255])
    );
}

#[test]
fn dither_keeps_the_mean_between_the_two_neighbouring_codes() {
    // One * sRGB(c) = 87.35, between codes 87 and 88.
    let c = linear_of_code(87.35) as f32;
    let x = 255.0 * srgb(f64::from(c));
    let (lo, hi) = (x.floor() as u8, x.ceil() as u8);
    assert_eq!((lo, hi), (87, 88));
    // The default quantization is RenderMan's: dither 0.5.
    let dithered = render_flat(c, 256, "");
    for channel in 0..3 {
        let values: Vec<u8> = dithered.image.pixels().map(|p| p[channel]).collect();
        assert!(
            values.iter().all(|&v| v == lo || v == hi),
            "channel {channel}: a code outside {lo}..={hi}"
        );
        let mean = values.iter().map(|&v| f64::from(v)).sum::<f64>() / values.len() as f64;
        eprintln!("channel {channel}: mean {mean}, one * c = {x}");
        assert!(
            (mean - x).abs() < 0.01,
            "channel {channel}: mean {mean} vs {x}"
        );
    }
    // Without dither: the rounded value everywhere.
    let plain = render_flat(c, 64, "quantize = { dither = 0.0 }");
    let rounded = nearest_code(x);
    assert!(
        plain
            .image
            .pixels()
            .all(|p| p.0 == [rounded, rounded, rounded, 255])
    );
    // The dither is the same on every run.
    assert_same(
        &render_flat(c, 256, "").image,
        &dithered.image,
        "a second run",
    );
}

#[test]
fn one_min_and_max_scale_and_clip_the_codes() {
    let c = 0.5f32;
    let rendered = render_flat(
        c,
        4,
        "quantize = { one = 100.0, min = 20.0, max = 60.0, dither = 0.0 }",
    );
    let want = nearest_code(100.0 * srgb(f64::from(c))).clamp(20, 60);
    assert_eq!(want, 60, "73.5 clipped to max");
    // Alpha is quantized too: one 100.
    assert!(rendered.image.pixels().all(|p| p.0 == [60, 60, 60, 60]));
    let dark = render_flat(0.0, 4, "quantize = { one = 100.0, min = 20.0, max = 60.0 }");
    assert!(dark.image.pixels().all(|p| p[0] == 20), "clipped to min");
}

#[test]
fn scene_keys_are_checked_and_name_the_range() {
    let cases = [
        (
            "exposure = { gain = -1.0 }",
            "invalid exposure: gain -1 is outside [0, inf)",
        ),
        (
            "exposure = { gamma = 0.0 }",
            "invalid exposure: gamma 0 is outside (0, inf)",
        ),
        (
            "quantize = { min = 10.0, max = 5.0 }",
            "invalid quantize: min 10 is above max 5",
        ),
        (
            "quantize = { max = 300.0 }",
            "invalid quantize: max 300 is not a whole number in [0, 255]",
        ),
        (
            "quantize = { dither = -1.0 }",
            "invalid quantize: dither -1 is outside [0, 255]",
        ),
        (
            "quantize = { one = 0.0 }",
            "invalid quantize: one 0 is outside (0, 65535]",
        ),
    ];
    for (line, want) in cases {
        // Reading a scene validates it.
        let error = Scene::from_toml_str(line).expect_err(line).to_string();
        assert!(error.contains(want), "{line}: {error}");
    }
    for unknown in [
        "exposure = { gian = 2.0 }",
        "quantize = { dither_amplitude = 1.0 }",
    ] {
        let error = Scene::from_toml_str(unknown)
            .expect_err(unknown)
            .to_string();
        assert!(error.contains("unknown field"), "{unknown}: {error}");
    }
    let scene = Scene::from_toml_str(
        "exposure = { gain = 2.0, gamma = 1.5 }\nquantize = { one = 200.0, min = 1.0, max = 250.0, dither = 0.25 }",
    )
    .unwrap();
    assert_eq!(
        scene.exposure,
        Exposure {
            gain: 2.0,
            gamma: 1.5
        }
    );
    assert_eq!(
        scene.quantize,
        Quantize {
            one: 200.0,
            min: 1.0,
            max: 250.0,
            dither_amplitude: 0.25
        }
    );
    // And back: the keys round-trip through the TOML writer.
    assert_eq!(
        Scene::from_toml_str(&scene.to_toml_string()).unwrap(),
        scene
    );
}

/// A tiny teapot scene with `extra` TOML lines, written to `dir`.
fn teapot_scene(dir: &Path, name: &str, extra: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    let text = format!(
        "spp = 4\njitter = true\n{extra}\n[resolution]\nwidth = 40\nheight = 30\n\n[[objects]]\nmodel = \"teapot\"\ncolor = [0.8, 0.36, 0.18]\n"
    );
    std::fs::write(&path, text).unwrap();
    path
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

/// `reyes render --cpu scene -o out` in `dir`.
fn render_cli(dir: &Path, scene: &Path, out: &str) {
    let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
    command
        .current_dir(dir)
        .args(["render", "--cpu", "--quiet"])
        .arg(scene)
        .args(["-o", out]);
    let (ok, stderr) = run_command(command);
    assert!(ok, "{stderr}");
}

#[test]
fn the_exr_holds_the_resolve_s_floats_whatever_the_exposure() {
    let temp = TempDir::new("exposure-exr");
    let dir = temp.path("");
    let plain = teapot_scene(&dir, "plain.toml", "");
    let exposed = teapot_scene(
        &dir,
        "exposed.toml",
        "exposure = { gain = 3.0, gamma = 1.8 }\nquantize = { dither = 0.25 }",
    );
    for (scene, stem) in [(&plain, "plain"), (&exposed, "exposed")] {
        render_cli(&dir, scene, &format!("{stem}.exr"));
        render_cli(&dir, scene, &format!("{stem}.png"));
    }
    let read_exr = |name: &str| {
        image::open(dir.join(name))
            .unwrap()
            .as_rgba32f()
            .expect("the EXR holds Rgba32F")
            .clone()
    };
    let exr = read_exr("plain.exr");
    assert_same(&exr, &read_exr("exposed.exr"), "exposure changed the EXR");
    // The float resolve of the same scene, in this process.
    let scene = Scene::load(&exposed).unwrap();
    let prepared = PreparedScene::load(&scene).unwrap();
    let reference = reyes::reference::render(&prepared);
    assert_same(&exr, &reference.linear, "the EXR against the float resolve");
    // Values no 8-bit image holds: neither multiples of 1/255 nor the
    // linear value of any sRGB code.
    let codes: Vec<f32> = (0..=255)
        .map(|k| linear_of_code(f64::from(k)) as f32)
        .collect();
    let off_grid = exr
        .pixels()
        .flat_map(|p| p.0[..3].to_vec())
        .filter(|&v| {
            let multiple = (v * 255.0 - (v * 255.0).round()).abs() > 1e-3;
            let decoded = codes.iter().all(|&k| (k - v).abs() > 1e-6);
            multiple && decoded
        })
        .count();
    assert!(
        off_grid > exr.len() / 8,
        "only {off_grid} values off the 8-bit grid"
    );
    // Each PNG is its scene's encoding of the floats.
    for (stem, encoding) in [
        ("plain", Encoding::default()),
        (
            "exposed",
            Encoding {
                exposure: Exposure {
                    gain: 3.0,
                    gamma: 1.8,
                },
                quantize: Quantize {
                    dither_amplitude: 0.25,
                    ..Quantize::default()
                },
            },
        ),
    ] {
        let png = image::open(dir.join(format!("{stem}.png")))
            .unwrap()
            .to_rgba8();
        assert_same(&png, &encoding.encode(&exr, [0, 0]), &format!("{stem}.png"));
    }
    assert_eq!(
        prepared.encoding.exposure,
        Exposure {
            gain: 3.0,
            gamma: 1.8
        }
    );
}
