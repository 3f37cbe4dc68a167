//! Reyes frames under both strategies and policies, for the strategy table.

use std::path::PathBuf;
use std::time::Duration;

use reyes::gpu::{GpuOptions, GpuRenderer};
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::scene::{CameraDesc, Scene};
use scheduler::{Policy, RunReport, Strategy};

use crate::BenchError;
use crate::strategies::{Measured, StrategyRow};
use crate::timing::TimeSource;

/// The Killeroo, read from the shared data folder beside the workspace.
pub fn killeroo_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/killeroo.bpt")
}

fn framed(mut scene: Scene, model: &Model, width: u32, height: u32) -> Scene {
    scene.resolution.width = width;
    scene.resolution.height = height;
    scene.spp = 1;
    let (lo, hi) = model.bounds();
    scene.camera = Some(CameraDesc::framing(lo, hi, width as f32 / height as f32));
    scene
}

fn render_error(e: impl std::fmt::Display) -> BenchError {
    BenchError::Config(format!("Reyes: {e}"))
}

/// The teapot (and the Killeroo, when `../shared/data/killeroo.bpt` exists)
/// at 800x600, spp 1, under both policies, each timed with both strategies:
/// one warm-up frame per renderer, then `runs` frames, alternating. The two
/// strategies' images must be identical: the frame does not depend on the
/// order in which items run.
pub fn measure_frames(runs: u32) -> Result<Vec<StrategyRow>, BenchError> {
    let gpu = reyes::gpu::create_gpu().map_err(render_error)?;
    let mut models = vec![("teapot", Scene::default_teapot(), Model::teapot())];
    let killeroo = killeroo_path();
    if killeroo.exists() {
        let model = Model::load(&killeroo).map_err(render_error)?;
        models.push((
            "killeroo",
            Scene::for_model(killeroo.to_string_lossy(), &model),
            model,
        ));
    } else {
        eprintln!("NOTICE: {} not found; no Killeroo rows", killeroo.display());
    }
    let mut rows = Vec::new();
    for (name, scene, model) in &models {
        let prepared =
            PreparedScene::load(&framed(scene.clone(), model, 800, 600)).map_err(render_error)?;
        for policy in [Policy::Priority, Policy::RoundRobin] {
            let mut renderers = Vec::new();
            let mut images = Vec::new();
            for strategy in [Strategy::Megakernel, Strategy::rounds()] {
                let options = GpuOptions {
                    strategy,
                    policy,
                    timeout: Duration::from_secs(300),
                    ..GpuOptions::default()
                };
                let mut renderer = GpuRenderer::new(&gpu, options).map_err(render_error)?;
                images.push(renderer.render(&prepared).map_err(render_error)?.image);
                renderers.push(renderer);
            }
            if images[0] != images[1] {
                return Err(BenchError::Config(format!(
                    "{name}, {policy:?}: the megakernel and rounds images differ"
                )));
            }
            let mut samples: [Vec<(Duration, RunReport)>; 2] = [Vec::new(), Vec::new()];
            let mut sources = [TimeSource::GpuTimestamps; 2];
            for _ in 0..runs {
                for (i, renderer) in renderers.iter_mut().enumerate() {
                    let frame = renderer.render(&prepared).map_err(render_error)?;
                    let (time, source) = match frame.timings.megakernel_gpu_ms {
                        Some(ms) => (ms, TimeSource::GpuTimestamps),
                        None => (frame.timings.megakernel_wall_ms, TimeSource::WallClock),
                    };
                    if source == TimeSource::WallClock {
                        sources[i] = source;
                    }
                    let report = frame.report.unwrap_or_default();
                    samples[i].push((Duration::from_secs_f64(time / 1e3), report));
                }
            }
            rows.push(StrategyRow {
                workload: format!("reyes {name} 800x600"),
                policy,
                megakernel: Measured::from_samples(&samples[0], sources[0]),
                rounds: Measured::from_samples(&samples[1], sources[1]),
            });
        }
    }
    Ok(rows)
}
