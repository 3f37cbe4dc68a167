//! Motion blur and depth of field: the 5D sampling modes timed side by side
//! on the benchmark scene (a model spinning about its vertical axis during
//! the shutter), for `blur-bench`.

use std::time::Duration;

use reyes::gpu::{GpuOptions, GpuRenderer};
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::scene::{CameraDesc, Sampling, Scene, Transform};

use crate::BenchError;
use crate::reyes_strategies::killeroo_path;
use crate::timing::median;

/// What blurs in a configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlurConfig {
    /// Degrees the model spins about its vertical (z) axis during the shutter.
    pub spin_degrees: f32,
    /// Lens radius as a fraction of the model's bounding-box diagonal (0: pinhole).
    pub aperture_fraction: f32,
    /// Degrees the camera pans about its up axis during the shutter
    /// (camera motion; see `reyes::scene::CameraDesc::moved`).
    pub pan_degrees: f32,
    /// A mixed scene: a still copy of the model stands beside the spinning
    /// one, so that grids with very different motion share the frame.
    pub still_copy: bool,
}

impl BlurConfig {
    /// A short label: `spin 30`, `dof 0.02`, `spin 30 + dof 0.02`, `pan 5`.
    pub fn label(&self) -> String {
        let parts: Vec<String> = [
            ("spin", self.spin_degrees),
            ("pan", self.pan_degrees),
            ("dof", self.aperture_fraction),
        ]
        .into_iter()
        .filter(|&(_, amount)| amount != 0.0)
        .map(|(what, amount)| format!("{what} {amount}"))
        .collect();
        let label = if parts.is_empty() {
            "still".into()
        } else {
            parts.join(" + ")
        };
        if self.still_copy {
            format!("{label}, beside a still copy")
        } else {
            label
        }
    }
}

/// One measured cell: a mode on a configuration.
#[derive(Debug, Clone)]
pub struct BlurRow {
    /// The configuration.
    pub config: BlurConfig,
    /// Samples per pixel.
    pub spp: u32,
    /// The sampling mode.
    pub mode: Sampling,
    /// Median frame time (GPU timestamps when the adapter has them, else wall).
    pub median: Duration,
    /// Every run's time.
    pub runs: Vec<Duration>,
    /// Samples tested and hit in one frame.
    pub tested: u64,
    /// See `tested`.
    pub hit: u64,
    /// Samples looked up and skipped without a test in one frame
    /// (`RenderStats::samples_skipped`).
    pub skipped: u64,
    /// Grids Adaptive sent to Interleave UVT (and Interleave's own grids).
    pub interleave_grids: u64,
    /// Grids diced.
    pub grids: u64,
    /// Screen tiles per frame.
    pub tiles: u32,
    /// Most runs any one frame of the cell repeated (llvmpipe cut a loop, or
    /// a queue overflowed). Only a frame's last run is timed, so a cell with
    /// retries understates what its frames cost.
    pub retries: u32,
}

impl BlurRow {
    /// Samples hit per sample tested.
    pub fn efficiency(&self) -> f64 {
        self.hit as f64 / self.tested.max(1) as f64
    }
}

/// The benchmark model: the Killeroo from `../shared/data` (or the teapot).
pub fn load_model(name: &str) -> Result<(String, Model), BenchError> {
    let error = |e: reyes::load::LoadError| BenchError::Config(format!("{name}: {e}"));
    match name {
        "teapot" => Ok(("teapot".into(), Model::teapot())),
        "killeroo" => {
            let path = killeroo_path();
            Ok((
                path.to_string_lossy().into_owned(),
                Model::load(&path).map_err(error)?,
            ))
        }
        other => Ok((other.into(), Model::load(other).map_err(error)?)),
    }
}

/// The benchmark scene: `model` framed at `width x height`, seen from
/// above (the eye raised to 60 degrees over the model's centre), spinning,
/// panned and defocused as `config` says, focused on the model's centre.
pub fn scene(
    model_name: &str,
    model: &Model,
    config: BlurConfig,
    width: u32,
    height: u32,
    spp: u32,
    mode: Sampling,
) -> Scene {
    let mut scene = Scene::for_model(model_name, model);
    scene.resolution.width = width;
    scene.resolution.height = height;
    scene.spp = spp;
    scene.sampling = mode;
    let (lo, mut hi) = model.bounds();
    // The still copy stands one model width further along x.
    let offset = glam::Vec3::new(1.2 * (hi.x - lo.x), 0.0, 0.0);
    if config.still_copy {
        let mut copy = scene.objects[0].clone();
        copy.transform.translate += offset;
        scene.objects.push(copy);
        hi += offset;
    }
    let framed = CameraDesc::framing(lo, hi, width as f32 / height as f32);
    let distance = framed.eye.distance(framed.target);
    let elevation = 60f32.to_radians();
    let across = (framed.eye - framed.target).with_z(0.0).normalize_or_zero();
    scene.camera = Some(CameraDesc {
        eye: framed.target
            + (across * elevation.cos() + glam::Vec3::Z * elevation.sin()) * distance,
        ..framed
    });
    if config.pan_degrees != 0.0 {
        scene.camera_close = scene
            .camera
            .map(|camera| camera.moved(glam::Vec3::ZERO, config.pan_degrees));
    }
    scene.lens.aperture = config.aperture_fraction * (hi - lo).length();
    if config.spin_degrees != 0.0 {
        let open = scene.objects[0].transform;
        scene.objects[0].transform_close = Some(Transform {
            rotate_degrees: open.rotate_degrees + glam::Vec3::new(0.0, 0.0, config.spin_degrees),
            ..open
        });
    }
    scene
}

fn render_error(e: impl std::fmt::Display) -> BenchError {
    BenchError::Config(format!("Reyes: {e}"))
}

/// Times every mode of `scenes` (one prepared scene per mode, all of one
/// configuration), interleaving the modes run by run so that drift hits them
/// alike. The first frame of each mode gives its counts; with `warm_up` it
/// is not timed and `runs` more frames follow, without it it is the first
/// of the `runs` timed frames (the times are the megakernel's GPU
/// timestamps, which exclude pipeline creation, so a cold first frame only
/// matters to drivers that compile lazily). A mode whose frame fails (on
/// llvmpipe: a loop the driver cut short, for the largest boxes) gets its
/// error instead of a row, and the others go on.
pub fn measure(
    renderer: &mut GpuRenderer<'_>,
    scenes: &[(Sampling, PreparedScene)],
    config: BlurConfig,
    runs: u32,
    warm_up: bool,
) -> Vec<(Sampling, Result<BlurRow, String>)> {
    let mut rows: Vec<(Sampling, Result<BlurRow, String>)> = Vec::new();
    // Frames per mode: the first gives the counts (and is timed unless it
    // warms up).
    let frames = if warm_up { runs + 1 } else { runs.max(1) };
    for (mode, prepared) in scenes {
        let rendered = renderer.render(prepared);
        progress(config, prepared.spp, *mode, (1, frames), &rendered);
        let row = rendered
            .map(|frame| BlurRow {
                config,
                spp: prepared.spp,
                mode: *mode,
                median: Duration::ZERO,
                runs: if warm_up {
                    Vec::new()
                } else {
                    vec![frame_time(&frame)]
                },
                tested: frame.stats.samples_tested,
                hit: frame.stats.samples_hit,
                skipped: frame.stats.samples_skipped,
                interleave_grids: frame.stats.interleave_grids,
                grids: frame.stats.grids_diced,
                tiles: frame.tiles,
                retries: retries(&frame),
            })
            .map_err(|e| e.to_string());
        rows.push((*mode, row));
    }
    for frame in 2..=frames {
        // Each round starts with the next mode, so that no mode always
        // follows the same one (a frame can slow the next on a shared CPU).
        let count = rows.len();
        for turn in 0..count {
            let i = (turn + frame as usize) % count;
            let (mode, prepared) = (&scenes[i].0, &scenes[i].1);
            let row = &mut rows[i].1;
            let Ok(measured) = row else { continue };
            let rendered = renderer.render(prepared);
            progress(config, prepared.spp, *mode, (frame, frames), &rendered);
            match rendered {
                Ok(frame) => {
                    measured.runs.push(frame_time(&frame));
                    measured.retries = measured.retries.max(retries(&frame));
                }
                Err(e) => *row = Err(e.to_string()),
            }
        }
    }
    for (_, row) in &mut rows {
        if let Ok(row) = row {
            let mut sorted = row.runs.clone();
            sorted.sort();
            row.median = median(&sorted);
        }
    }
    rows
}

/// One line on stderr per frame, because a frame of the slowest modes runs
/// for minutes on llvmpipe: `spin 30 spp 16 bbox: frame 1/6, 240037.1 ms`.
fn progress(
    config: BlurConfig,
    spp: u32,
    mode: Sampling,
    (frame, frames): (u32, u32),
    rendered: &Result<reyes::gpu::GpuRendered, reyes::gpu::RenderError>,
) {
    let outcome = match rendered {
        Ok(rendered) => {
            let ms = frame_time(rendered).as_secs_f64() * 1e3;
            match retries(rendered) {
                0 => format!("{ms:.1} ms"),
                n => format!("{ms:.1} ms (its last of {} runs)", n + 1),
            }
        }
        Err(e) => format!("failed: {e}"),
    };
    eprintln!(
        "{} spp {spp} {}: frame {frame}/{frames}, {outcome}",
        config.label(),
        mode.name()
    );
}

/// A frame's megakernel time: GPU timestamps when the adapter has them,
/// else wall time.
fn frame_time(frame: &reyes::gpu::GpuRendered) -> Duration {
    let ms = frame
        .timings
        .megakernel_gpu_ms
        .unwrap_or(frame.timings.megakernel_wall_ms);
    Duration::from_secs_f64(ms / 1e3)
}

/// Runs a frame repeated before it succeeded.
fn retries(frame: &reyes::gpu::GpuRendered) -> u32 {
    frame.loop_retries + frame.overflow_retries
}

/// A renderer with a generous timeout (bounding-box sampling of large blur
/// tests billions of samples on a CPU adapter).
pub fn renderer(gpu: &scheduler::Gpu) -> Result<GpuRenderer<'_>, BenchError> {
    GpuRenderer::new(
        gpu,
        GpuOptions {
            timeout: Duration::from_secs(1800),
            ..GpuOptions::default()
        },
    )
    .map_err(render_error)
}

/// The rows as a table: one line per (configuration, spp, mode).
pub fn format_rows(rows: &[(Sampling, Result<BlurRow, String>)]) -> String {
    let mut s = format!(
        "{:<22}{:>5}  {:<11}{:>12}{:>12}{:>14}{:>14}{:>11}{:>12}{:>6}{:>8}\n",
        "blur",
        "spp",
        "mode",
        "median ms",
        "min ms",
        "tested",
        "skipped",
        "STE",
        "ileave",
        "tiles",
        "retries"
    );
    for (mode, row) in rows {
        let row = match row {
            Ok(row) => row,
            Err(e) => {
                s += &format!("{:<22}{:>5}  {:<11}  failed: {e}\n", "", "", mode.name());
                continue;
            }
        };
        let min = row.runs.iter().min().copied().unwrap_or_default();
        s += &format!(
            "{:<22}{:>5}  {:<11}{:>12.1}{:>12.1}{:>14}{:>14}{:>11.5}{:>12}{:>6}{:>8}\n",
            row.config.label(),
            row.spp,
            row.mode.name(),
            row.median.as_secs_f64() * 1e3,
            min.as_secs_f64() * 1e3,
            row.tested,
            row.skipped,
            row.efficiency(),
            format!("{}/{}", row.interleave_grids, row.grids),
            row.tiles,
            row.retries,
        );
    }
    s
}

/// The measured row of `mode` among `rows`, if it has times.
fn row_of(rows: &[(Sampling, Result<BlurRow, String>)], mode: Sampling) -> Option<&BlurRow> {
    rows.iter()
        .find(|(m, _)| *m == mode)
        .and_then(|(_, r)| r.as_ref().ok())
}

/// The Adaptive acceptance check for one (configuration, spp): Adaptive's
/// median over the better of INTERVAL's and Interleave UVT's; `None` when
/// one of the three has no time.
pub fn adaptive_ratio(rows: &[(Sampling, Result<BlurRow, String>)]) -> Option<f64> {
    let time = |mode| row_of(rows, mode).map(|r| r.median);
    let best = time(Sampling::Interval)?.min(time(Sampling::Interleave)?);
    Some(time(Sampling::Adaptive)?.as_secs_f64() / best.as_secs_f64().max(1e-9))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(spin_degrees: f32, aperture_fraction: f32, pan_degrees: f32) -> BlurConfig {
        BlurConfig {
            spin_degrees,
            aperture_fraction,
            pan_degrees,
            still_copy: false,
        }
    }

    #[test]
    fn labels_name_what_blurs() {
        assert_eq!(config(30.0, 0.0, 0.0).label(), "spin 30");
        assert_eq!(config(0.0, 0.01, 0.0).label(), "dof 0.01");
        assert_eq!(config(30.0, 0.01, 0.0).label(), "spin 30 + dof 0.01");
        assert_eq!(config(0.0, 0.0, 5.0).label(), "pan 5");
        assert_eq!(config(0.0, 0.0, 0.0).label(), "still");
    }

    /// The spin moves the model, the pan moves the camera, the lens opens
    /// the aperture; each benchmark scene prepares.
    #[test]
    fn each_blur_moves_what_it_names() {
        let model = Model::teapot();
        for (config, spins, pans, lens) in [
            (config(30.0, 0.0, 0.0), true, false, false),
            (config(0.0, 0.01, 0.0), false, false, true),
            (config(0.0, 0.0, 5.0), false, true, false),
        ] {
            let scene = scene("teapot", &model, config, 200, 150, 16, Sampling::Adaptive);
            let what = config.label();
            assert_eq!(scene.objects[0].transform_close.is_some(), spins, "{what}");
            assert_eq!(scene.camera_close.is_some(), pans, "{what}");
            assert_eq!(scene.lens.aperture > 0.0, lens, "{what}");
            PreparedScene::new(&scene, std::slice::from_ref(&model)).expect(&what);
        }
    }
}
