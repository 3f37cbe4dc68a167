//! `ste-bench`: sample test efficiency (samples hit per sample tested) of
//! every sampling mode on a still scene, beside the figures Fatahalian et
//! al. (2009) report, counted by the CPU reference (the GPU counts the
//! same samples: the GPU-against-CPU tests check it).
//!
//! ```text
//! cargo run --release -p benches --bin ste-bench -- [--models teapot,killeroo]
//!     [--width 400] [--height 300] [--spp 16] [--shading-rate 1]
//! ```
//!
//! Two efficiencies are printed: samples hit per sample tested (STE), and
//! per sample looked up (tested, or reached by a loop and skipped for its
//! stratum without a test: Interleave UVT's tile lookups, INTERVAL's
//! pixels). Fatahalian et al.'s rasterizers test every sample they look
//! up, so the second is the one to set beside their figures.
//!
//! The Bounding-box row is measured twice in this one run: with the quad
//! boxes clamped to sample strata that the renderer uses, and with the box
//! per triangle over whole pixels that it used before
//! (`ReferenceOptions::triangle_boxes`). Both render the same image; the
//! second only tests more samples. Interleave UVT is measured with tiles of
//! 2, 3 and 4 pixels. The bench fails if the two bounding-box rows render
//! different images. The scene is `blur-bench`'s, still: the model seen
//! from above at the given size. The Killeroo is read from
//! `../shared/data/killeroo.bpt` and skipped with a notice when absent.

use std::process::ExitCode;

use benches::blur::{BlurConfig, load_model, scene};
use clap::Parser;
use reyes::prepare::PreparedScene;
use reyes::reference::{self, ReferenceOptions};
use reyes::scene::Sampling;

#[derive(Debug, Parser)]
#[command(about = "Sample test efficiency of the sampling modes on a still scene (CPU reference)")]
struct Args {
    /// Models: `teapot`, `killeroo` (from ../shared/data), or .bpt/.bez paths.
    #[arg(long, value_delimiter = ',', default_values_t = ["teapot".to_owned(), "killeroo".to_owned()])]
    models: Vec<String>,
    /// Image width.
    #[arg(long, default_value_t = 400)]
    width: u32,
    /// Image height.
    #[arg(long, default_value_t = 300)]
    height: u32,
    /// Samples per pixel.
    #[arg(long, default_value_t = 16)]
    spp: u32,
    /// Shading rate (micropolygon area in pixels).
    #[arg(long, default_value_t = 1.0)]
    shading_rate: f32,
}

/// One measured row: a mode, its Interleave tile, and whether it used the
/// old per-triangle boxes.
struct Row {
    label: String,
    paper: &'static str,
    sampling: Sampling,
    tile: u32,
    triangle_boxes: bool,
}

fn rows() -> Vec<Row> {
    let row = |label: &str, paper, sampling, tile, triangle_boxes| Row {
        label: label.to_owned(),
        paper,
        sampling,
        tile,
        triangle_boxes,
    };
    vec![
        row(
            "Bounding box, quad boxes on strata",
            "26% (NOMOTION)",
            Sampling::Bbox,
            2,
            false,
        ),
        row(
            "Bounding box, a box per triangle (before)",
            "",
            Sampling::Bbox,
            2,
            true,
        ),
        row("Simple UVT", "", Sampling::Simple, 2, false),
        row(
            "Interleave UVT, 2x2 tiles",
            "5% (INTERLEAVEUVT)",
            Sampling::Interleave,
            2,
            false,
        ),
        row(
            "Interleave UVT, 3x3 tiles",
            "",
            Sampling::Interleave,
            3,
            false,
        ),
        row(
            "Interleave UVT, 4x4 tiles",
            "",
            Sampling::Interleave,
            4,
            false,
        ),
        row("INTERVAL", "10% (INTERVAL)", Sampling::Interval, 2, false),
        row("Adaptive", "", Sampling::Adaptive, 2, false),
        row("Nearest", "", Sampling::Nearest, 2, false),
    ]
}

fn run(args: &Args) -> Result<(), String> {
    let still = BlurConfig {
        spin_degrees: 0.0,
        aperture_fraction: 0.0,
        pan_degrees: 0.0,
        still_copy: false,
    };
    println!(
        "Still scene, {} x {}, {} spp, shading rate {} (CPU reference)\n",
        args.width, args.height, args.spp, args.shading_rate
    );
    println!(
        "| Model | Mode | Samples tested | Samples skipped | Samples hit | STE | STE of lookups | CPU time | Fatahalian et al. |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|---|");
    for name in &args.models {
        let label = name;
        let (path, model) = match load_model(name) {
            Ok(loaded) => loaded,
            Err(error) => {
                eprintln!("skipping {name}: {error}");
                continue;
            }
        };
        // The image of the first row (quad boxes), which the old boxes must
        // render alike.
        let mut quad_image = None;
        for row in rows() {
            let mut scene = scene(
                &path,
                &model,
                still,
                args.width,
                args.height,
                args.spp,
                row.sampling,
            );
            scene.shading_rate = args.shading_rate;
            scene.interleave_tile = row.tile;
            let prepared = PreparedScene::load(&scene).map_err(|e| e.to_string())?;
            let options = ReferenceOptions {
                triangle_boxes: row.triangle_boxes,
                ..ReferenceOptions::unbounded_work()
            };
            let rendered =
                reference::try_render_with(&prepared, &options).map_err(|e| e.to_string())?;
            if row.sampling == Sampling::Bbox {
                match &quad_image {
                    None => quad_image = Some(rendered.image.clone()),
                    Some(image) if *image != rendered.image => {
                        return Err(format!(
                            "{label}: {} renders another image than the quad boxes",
                            row.label
                        ));
                    }
                    Some(_) => {}
                }
            }
            let stats = rendered.stats;
            println!(
                "| {label} | {} | {} | {} | {} | {:.1}% | {:.1}% | {:.2} s | {} |",
                row.label,
                stats.samples_tested,
                stats.samples_skipped,
                stats.samples_hit,
                100.0 * stats.sample_test_efficiency(),
                100.0 * stats.sample_lookup_efficiency(),
                stats.frame_time_ms.unwrap_or(0.0) / 1000.0,
                row.paper
            );
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("ste-bench: {error}");
            ExitCode::FAILURE
        }
    }
}
