//! `noise-bench`: the noise of each 5D sampling mode, as the RMSE of a
//! 16-spp render against a converged render of the same scene, on the CPU
//! reference.
//!
//! ```text
//! cargo run --release -p benches --bin noise-bench -- [--model teapot|killeroo|FILE]
//!     [--width 160] [--height 120] [--spp 16] [--interleave-tile 2]
//!     [--images DIR]
//! ```
//!
//! The converged render has 256 samples per pixel: the scene rendered at
//! twice the width and height with 64 spp (the most a scene allowed when
//! this was written; 256 spp at the output size would now do), each
//! 2 x 2 block of pixels averaged in linear light, which is the box filter
//! of 256 samples over the output pixel. It uses Bounding box sampling,
//! whose samples each carry their own stratified time and lens position.
//! RMSE is in 8-bit sRGB levels over the three colour channels of every
//! pixel; blur configurations are those of `blur-bench`.
//!
//! With `--images DIR` it also writes, per blur configuration, the
//! converged render (`converged-BLUR.png`), each mode's render
//! (`BLUR-MODE.png`) and its per-pixel error against the converged one
//! (`error-BLUR-MODE.png`: each pixel's RMSE over its channels, 0 black,
//! [`ERROR_WHITE`] levels and more white).

use std::process::ExitCode;

use benches::blur::{BlurConfig, load_model, scene};
use clap::Parser;
use image::RgbaImage;
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::Sampling;

#[derive(Debug, Parser)]
#[command(about = "Noise of the 5D sampling modes against a 256-spp render")]
struct Args {
    /// `teapot`, `killeroo` (from ../shared/data), or a .bpt/.bez path.
    #[arg(long, default_value = "teapot")]
    model: String,
    /// Image width.
    #[arg(long, default_value_t = 160)]
    width: u32,
    /// Image height.
    #[arg(long, default_value_t = 120)]
    height: u32,
    /// Samples per pixel of the measured renders.
    #[arg(long, default_value_t = 16)]
    spp: u32,
    /// Side, in pixels, of Interleave UVT's tiles (Interleave and Adaptive).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(2..=4))]
    interleave_tile: u32,
    /// Write the renders and per-pixel error pictures to this directory.
    #[arg(long)]
    images: Option<std::path::PathBuf>,
}

/// The per-pixel error (8-bit sRGB levels) drawn white in the error pictures.
const ERROR_WHITE: f64 = 32.0;

/// The modes that sample time and lens.
const MODES: [Sampling; 5] = Sampling::TIME_AND_LENS;

fn configs() -> [BlurConfig; 3] {
    let config = |spin_degrees, aperture_fraction| BlurConfig {
        spin_degrees,
        aperture_fraction,
        pan_degrees: 0.0,
        still_copy: false,
    };
    [config(30.0, 0.0), config(0.0, 0.02), config(30.0, 0.02)]
}

fn srgb_to_linear(v: u8) -> f64 {
    let c = f64::from(v) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb_level(c: f64) -> f64 {
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    s * 255.0
}

/// The `width x height` image of sRGB levels whose pixels average (in
/// linear light) the 2 x 2 blocks of `fine`.
fn downsample(fine: &RgbaImage, width: u32, height: u32) -> Vec<[f64; 3]> {
    let mut out = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let mut sum = [0.0; 3];
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let p = fine.get_pixel(2 * x + dx, 2 * y + dy);
                for (c, total) in sum.iter_mut().enumerate() {
                    *total += srgb_to_linear(p[c]);
                }
            }
            out.push(sum.map(|s| linear_to_srgb_level(s / 4.0)));
        }
    }
    out
}

fn rmse(image: &RgbaImage, converged: &[[f64; 3]]) -> f64 {
    let mut sum = 0.0;
    for (p, q) in image.pixels().zip(converged) {
        for c in 0..3 {
            let d = f64::from(p[c]) - q[c];
            sum += d * d;
        }
    }
    (sum / (3 * converged.len()) as f64).sqrt()
}

/// The picture of each pixel's RMSE over its channels against `converged`.
fn error_image(image: &RgbaImage, converged: &[[f64; 3]]) -> image::GrayImage {
    let mut out = image::GrayImage::new(image.width(), image.height());
    for ((p, q), e) in image.pixels().zip(converged).zip(out.pixels_mut()) {
        let sum: f64 = (0..3).map(|c| (f64::from(p[c]) - q[c]).powi(2)).sum();
        let level = (sum / 3.0).sqrt() / ERROR_WHITE * 255.0;
        e[0] = level.clamp(0.0, 255.0) as u8;
    }
    out
}

/// A blur configuration's label as a file name part (`spin-30-dof-0.02`).
fn file_label(config: BlurConfig) -> String {
    config.label().replace(" + ", "-").replace(' ', "-")
}

fn render(
    name: &str,
    model: &Model,
    config: BlurConfig,
    size: (u32, u32),
    spp: u32,
    mode: Sampling,
    interleave_tile: u32,
) -> Result<reference::Rendered, String> {
    let mut scene = scene(name, model, config, size.0, size.1, spp, mode);
    scene.interleave_tile = interleave_tile;
    let prepared = PreparedScene::load(&scene).map_err(|e| e.to_string())?;
    reference::try_render(&prepared).map_err(|e| e.to_string())
}

fn run(args: &Args) -> Result<(), String> {
    let (name, model) = load_model(&args.model).map_err(|e| e.to_string())?;
    let (width, height) = (args.width, args.height);
    println!(
        "{name}, {width} x {height}, {} spp vs 256 spp (CPU reference)",
        args.spp
    );
    println!(
        "{:<18} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "blur", "bbox", "simple", "interleave", "interval", "adaptive"
    );
    for config in configs() {
        let fine = render(
            &name,
            &model,
            config,
            (2 * width, 2 * height),
            64,
            Sampling::Bbox,
            args.interleave_tile,
        )?;
        let converged = downsample(&fine.image, width, height);
        if let Some(dir) = &args.images {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            let mut image = RgbaImage::new(width, height);
            for (p, q) in image.pixels_mut().zip(&converged) {
                *p = image::Rgba(
                    [q[0], q[1], q[2], 255.0].map(|v| v.round().clamp(0.0, 255.0) as u8),
                );
            }
            let path = dir.join(format!("converged-{}.png", file_label(config)));
            image
                .save(&path)
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
        let mut line = format!("{:<18}", config.label());
        for mode in MODES {
            let rendered = render(
                &name,
                &model,
                config,
                (width, height),
                args.spp,
                mode,
                args.interleave_tile,
            )?;
            line += &format!(" {:>10.3}", rmse(&rendered.image, &converged));
            if let Some(dir) = &args.images {
                let stem = format!("{}-{}", file_label(config), mode.name());
                let path = dir.join(format!("{stem}.png"));
                rendered
                    .image
                    .save(&path)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                let path = dir.join(format!("error-{stem}.png"));
                error_image(&rendered.image, &converged)
                    .save(&path)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
            }
        }
        println!("{line}");
    }
    Ok(())
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("noise-bench: {e}");
            ExitCode::FAILURE
        }
    }
}
