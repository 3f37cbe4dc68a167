//! The Reyes GPU renderer on the teapot and the Killeroo.
//!
//! ```text
//! cargo run --release -p benches --bin reyes-bench -- [--frames 5] [--spp 1]
//! ```
//!
//! Prints one table measured in this one process: each model at 800x600 and
//! 1920x1080. Per row, one warm-up frame creates the pipelines, the executor
//! and the buffers (and uploads the scene); then the median of `--frames`
//! frames is reported: the megakernel's GPU time (timestamp queries) when
//! the device has them, and the host wall time of the whole frame (clear,
//! megakernel, resolve, image read-back). The statistics are those of the
//! last frame. The Killeroo is read from `<workspace>/../shared/data/`
//! and skipped with a notice when absent.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use reyes::gpu::{GpuOptions, GpuRendered, GpuRenderer};
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::scene::{CameraDesc, Scene};

#[derive(Debug, Parser)]
#[command(about = "Reyes GPU renderer: teapot and Killeroo at 800x600 and 1920x1080")]
struct Args {
    /// Timed frames per row (median reported), after one warm-up frame.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(5..))]
    frames: u32,
    /// Samples per pixel.
    #[arg(long, default_value_t = 1)]
    spp: u32,
}

fn killeroo_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/killeroo.bpt")
}

/// `scene` at `width x height`, framed again for that aspect ratio.
fn sized(mut scene: Scene, model: &Model, width: u32, height: u32, spp: u32) -> Scene {
    scene.resolution.width = width;
    scene.resolution.height = height;
    scene.spp = spp;
    let (lo, hi) = model.bounds();
    scene.camera = Some(CameraDesc::framing(lo, hi, width as f32 / height as f32));
    scene
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let gpu = reyes::gpu::create_gpu()?;
    println!("device: {}", gpu.describe());
    let mut models: Vec<(&str, Scene, Model)> =
        vec![("teapot", Scene::default_teapot(), Model::teapot())];
    let killeroo = killeroo_path();
    if killeroo.exists() {
        let model = Model::load(&killeroo)?;
        let scene = Scene::for_model(killeroo.to_string_lossy(), &model);
        models.push(("killeroo", scene, model));
    } else {
        println!(
            "NOTICE: {} not found; skipping the Killeroo rows",
            killeroo.display()
        );
    }
    let mut renderer = GpuRenderer::new(
        &gpu,
        GpuOptions {
            // Large frames on a software rasterizer take a while.
            timeout: Duration::from_secs(300),
            ..GpuOptions::default()
        },
    )?;
    let header = format!(
        "{:<10}{:>11}{:>9}{:>12}{:>12}{:>9}{:>9}{:>8}{:>8}{:>10}{:>13}{:>12}{:>10}",
        "model",
        "resolution",
        "patches",
        "GPU ms",
        "wall ms",
        "splits",
        "culled",
        "drops",
        "grids",
        "micropoly",
        "tested",
        "hit",
        "retries"
    );
    let mut rows = Vec::new();
    for (name, scene, model) in &models {
        for (width, height) in [(800, 600), (1920, 1080)] {
            let prepared =
                PreparedScene::load(&sized(scene.clone(), model, width, height, args.spp))?;
            // Warm-up: pipelines, executor, buffers, upload.
            renderer.render(&prepared)?;
            let mut gpu_ms = Vec::new();
            let mut wall_ms = Vec::new();
            let mut last: Option<GpuRendered> = None;
            for _ in 0..args.frames {
                let frame = renderer.render(&prepared)?;
                if let Some(ms) = frame.timings.megakernel_gpu_ms {
                    gpu_ms.push(ms);
                }
                wall_ms.push(frame.timings.total_wall_ms);
                last = Some(frame);
            }
            let last = last.expect("at least 5 frames");
            let s = &last.stats;
            let gpu = if gpu_ms.len() == args.frames as usize {
                format!("{:.1}", median(gpu_ms))
            } else {
                "-".to_owned()
            };
            let row = format!(
                "{:<10}{:>11}{:>9}{:>12}{:>12.1}{:>9}{:>9}{:>8}{:>8}{:>10}{:>13}{:>12}{:>10}",
                name,
                format!("{width}x{height}"),
                s.input_patches,
                gpu,
                median(wall_ms),
                s.splits,
                s.culled_patches,
                s.depth_guard_drops,
                s.grids_diced,
                s.micropolygons,
                s.samples_tested,
                s.samples_hit,
                last.overflow_retries + last.loop_retries,
            );
            eprintln!("{row}");
            rows.push(row);
        }
    }
    println!(
        "spp {}, median of {} frames after one warm-up; GPU ms = megakernel (timestamp queries), wall ms = whole frame incl. clear, resolve and read-back",
        args.spp, args.frames
    );
    println!("{header}");
    for row in rows {
        println!("{row}");
    }
    Ok(())
}
