//! The Mandelbrot set by Mariani–Silver subdivision (`workloads::mandelbrot`,
//! the workload of `scheduler/examples/mandelbrot.rs`) against a flat
//! dispatch of the same per-pixel function: one thread per pixel, one
//! dispatch, every pixel iterated.
//!
//! The megakernel renders the image with the workload's graph (`Tile` checks
//! borders and fills, splits or hands squares to `Block`), under the
//! persistent megakernel and under the Rounds strategy; every variant's image
//! is verified exactly: the flat dispatch's against the CPU brute force, the
//! subdivision's against the CPU subdivision (and its counters against the
//! CPU's tile counts), after the warm-up and after the last timed run. The
//! CPU computes under the arithmetic the driver used: a driver may fuse the
//! escape loop's multiply-adds, so the warm-up's counts are matched with
//! the plain reference or else with the one fused variant that explains
//! them (`workloads::mandelbrot::Contraction`), each shader on its own, and
//! the last run must give that variant's counts again. The
//! `mk checked` row is the default megakernel compiled in checked mode
//! (every index into `counts` guarded): the cost of checked mode.

use std::time::Duration;

use scheduler::{CompileOptions, ConstantValue, ExecutorConfig, Gpu, Strategy, wgpu};

use crate::BenchError;
use crate::flat::{BoundKernel, Timestamps, dispatch_timed};
use crate::timing::{TimeSource, Timings};

pub use workloads::mandelbrot::{
    Contraction, ESCAPE_WGSL, Mandelbrot, Matched, Subdivision, UNWRITTEN, View, cpu_brute_force,
    cpu_mariani_silver, match_brute_force,
};

/// Threads per workgroup of the flat kernel (8 × 8 pixels).
pub const FLAT_TILE: u32 = 8;

/// The flat kernel's entry point; the constants and the workload's
/// `escape_count` go in front.
const FLAT_MANDELBROT_WGSL: &str = "
@group(0) @binding(0) var<storage, read_write> counts: array<u32>;

@compute @workgroup_size(8, 8)
fn flat_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.y * WIDTH + gid.x;
    if (gid.x < WIDTH && i < arrayLength(&counts)) {
        counts[i] = escape_count(gid.x, gid.y);
    }
}
";

/// What to measure.
#[derive(Clone, Debug, serde::Serialize)]
pub struct MandelbrotConfig {
    /// Side of the square image (a power of two, at least 64).
    pub size: u32,
    /// Most iterations per pixel.
    pub max_iter: u32,
    /// Timed runs per variant (after one verified warm-up run).
    pub runs: u32,
    /// Megakernel workgroup counts, one row each per chunk count.
    pub workgroups: Vec<u32>,
    /// Chunks per batch to compile with, one row per variant each.
    pub chunks: Vec<u32>,
    /// Most workgroups per round dispatch, one Rounds row each per chunk
    /// count.
    pub rounds_workgroups: Vec<u32>,
}

/// One measured variant.
#[derive(Clone, Debug, serde::Serialize)]
pub struct MandelbrotRow {
    /// `flat`, `megakernel` or `rounds`.
    pub variant: String,
    /// Workgroups per dispatch (the flat grid's for the flat dispatch).
    pub workgroups: u32,
    /// Chunks per batch (`None` for the flat dispatch).
    pub chunks: Option<u32>,
    /// Timed runs.
    pub timings: Timings,
    /// The flat dispatch's median time over this row's (above 1: faster).
    pub ratio_to_flat: f64,
    /// `Tile` items executed (`None` for the flat dispatch).
    pub tiles: Option<u64>,
    /// `Block` items executed.
    pub blocks: Option<u64>,
    /// Pixels whose escape count was iterated.
    pub escape_pixels: u64,
    /// Iterations of the per-pixel loop, summed.
    pub iterations: u64,
    /// Submissions per run (megakernel dispatches or batches of rounds).
    pub dispatches: Option<u32>,
    /// The multiply-adds the driver fused in this variant's shader, as the
    /// check found them (`None` when nothing was fused).
    pub fused: Option<String>,
}

/// Everything one Mandelbrot comparison measured.
#[derive(Clone, Debug, serde::Serialize)]
pub struct MandelbrotReport {
    /// The configuration.
    pub config: MandelbrotConfig,
    /// Pixels where Mariani–Silver differs from brute force (on the CPU).
    pub differ_from_brute_force: usize,
    /// The rows, flat first.
    pub rows: Vec<MandelbrotRow>,
}

/// The flat dispatch: the workload's `escape_count` for every pixel.
#[derive(Debug)]
pub struct FlatMandelbrot {
    device: wgpu::Device,
    queue: wgpu::Queue,
    view: View,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    counts: wgpu::Buffer,
    timestamps: Option<Timestamps>,
}

/// The flat kernel's whole module for `view`.
pub fn flat_wgsl(view: &View) -> String {
    let constants: String = view
        .constants()
        .iter()
        .map(|&(name, value): &(&str, ConstantValue)| {
            let literal = value.wgsl_literal().expect("finite view constants");
            format!("const {name}: {} = {literal};\n", value.wgsl_type())
        })
        .collect();
    format!("{constants}{ESCAPE_WGSL}{FLAT_MANDELBROT_WGSL}")
}

impl FlatMandelbrot {
    /// Creates the pipeline and the output buffer (not timed).
    pub fn new(gpu: &Gpu, view: View) -> Result<Self, BenchError> {
        let device = &gpu.device;
        let BoundKernel {
            pipeline,
            out: counts,
            bind_group,
        } = BoundKernel::new(
            device,
            "flat mandelbrot",
            flat_wgsl(&view),
            view.width * view.height,
        )?;
        Ok(Self {
            device: device.clone(),
            queue: gpu.queue.clone(),
            view,
            pipeline,
            bind_group,
            counts,
            timestamps: Timestamps::new(device, &gpu.queue),
        })
    }

    /// How [`Self::run`] times a run.
    pub fn time_source(&self) -> TimeSource {
        if self.timestamps.is_some() {
            TimeSource::GpuTimestamps
        } else {
            TimeSource::WallClock
        }
    }

    /// Runs the dispatch once: its time and the host wall time.
    pub fn run(&self) -> Result<(Duration, Duration), BenchError> {
        dispatch_timed(
            &self.device,
            &self.queue,
            &self.pipeline,
            &self.bind_group,
            [self.view.width / FLAT_TILE, self.view.height / FLAT_TILE, 1],
            self.timestamps.as_ref(),
        )
    }

    /// The last run's counts.
    pub fn counts(&self) -> Result<Vec<u32>, BenchError> {
        crate::verify::read_out(&self.device, &self.queue, &self.counts)
    }
}

/// Matches a flat dispatch's counts with `plain`, the plain CPU brute force,
/// or else with the brute force under the contraction that explains them.
/// When none does, the error is the mismatch with `plain`.
fn match_flat(
    view: &View,
    counts: &[u32],
    plain: &[u32],
    variant: &str,
) -> Result<Matched<Vec<u32>>, BenchError> {
    match_brute_force(view, counts, plain).or_else(|unexplained| {
        crate::verify::compare(counts, plain, variant)?;
        Err(BenchError::Counters {
            variant: variant.to_owned(),
            detail: unexplained.to_string(),
        })
    })
}

/// Matches a subdivision's counts and counters with `plain`, the plain CPU
/// subdivision, or else with the subdivision under the contraction that
/// explains them. When none does, the error is the first disagreement with
/// `plain`: the pixels, or else the counters.
pub fn match_scheduled(
    mandelbrot: &Mandelbrot,
    report: &scheduler::RunReport,
    counts: &[u32],
    plain: &Subdivision,
    variant: &str,
) -> Result<Matched<Subdivision>, BenchError> {
    mandelbrot
        .check(report, counts, plain)
        .or_else(|unexplained| {
            crate::verify::compare(counts, &plain.counts, variant)?;
            Err(BenchError::Counters {
                variant: variant.to_owned(),
                detail: unexplained.mismatches.join("; "),
            })
        })
}

/// `Some` description of what `contraction` fused, `None` when nothing.
fn fused(contraction: Contraction) -> Option<String> {
    (!contraction.is_plain()).then(|| contraction.to_string())
}

fn boxed(error: Box<dyn std::error::Error>) -> BenchError {
    BenchError::Config(format!("the Mandelbrot graph: {error}"))
}

/// One scheduled variant: strategy, workgroups, chunks per batch, and
/// whether it is compiled in checked mode.
type Scheduled = (Strategy, u32, u32, bool);

/// Times one megakernel or Rounds variant: a verified warm-up, matched with
/// `plain` (the plain CPU subdivision) or the fused variant that explains
/// it, and `runs` timed runs, the last one verified against the warm-up's
/// variant. Returns the row without its ratio.
fn measure_scheduled(
    gpu: &Gpu,
    view: View,
    config: &MandelbrotConfig,
    (strategy, workgroups, chunks, checked): Scheduled,
    plain: &Subdivision,
) -> Result<MandelbrotRow, BenchError> {
    let mode = if checked { ", checked" } else { "" };
    let name = format!(
        "mandelbrot {strategy}, {workgroups} workgroups, {chunks} chunk(s) per batch{mode}"
    );
    let options = CompileOptions {
        chunks_per_batch: chunks,
        checked,
        ..CompileOptions::with_features(scheduler::recommended_features(&gpu.device))
    };
    let executor_config = ExecutorConfig {
        workgroups: Some(workgroups),
        ..workloads::mandelbrot::config(gpu, &view, chunks)
    };
    let mut mandelbrot = Mandelbrot::new(gpu, view, &options, &executor_config).map_err(boxed)?;
    let report = mandelbrot.render(strategy)?;
    let Matched {
        contraction,
        reference: cpu,
    } = match_scheduled(&mandelbrot, &report, &mandelbrot.counts()?, plain, &name)?;
    let variant = match (strategy, checked) {
        // The megakernel with every resource index guarded: its cost.
        (Strategy::Megakernel, true) => "mk checked".to_owned(),
        (_, true) => format!("{} checked", strategy.name()),
        (_, false) => strategy.name().to_owned(),
    };
    let mut source = TimeSource::GpuTimestamps;
    let mut times = Vec::with_capacity(config.runs as usize);
    let mut walls = Vec::with_capacity(config.runs as usize);
    let mut last = report;
    for _ in 0..config.runs {
        last = mandelbrot.render(strategy)?;
        times.push(last.gpu_time.unwrap_or_else(|| {
            source = TimeSource::WallClock;
            last.wall_time
        }));
        walls.push(last.wall_time);
    }
    // The same shader again: the warm-up's arithmetic, exactly.
    let counts = mandelbrot.counts()?;
    crate::verify::compare(&counts, &cpu.counts, &name)?;
    let problems = mandelbrot.compare(&last, &counts, &cpu);
    if !problems.is_empty() {
        return Err(BenchError::Counters {
            variant: name,
            detail: problems.join("; "),
        });
    }
    Ok(MandelbrotRow {
        variant,
        workgroups,
        chunks: Some(chunks),
        timings: Timings::new(times, &walls, source),
        ratio_to_flat: 0.0,
        tiles: Some(cpu.tiles),
        blocks: Some(cpu.blocks),
        escape_pixels: cpu.escape_pixels,
        iterations: cpu.iterations,
        dispatches: Some(last.dispatches),
        fused: fused(contraction),
    })
}

/// Runs the comparison. `progress` receives each finished row.
pub fn run_mandelbrot(
    gpu: &Gpu,
    config: &MandelbrotConfig,
    mut progress: impl FnMut(&MandelbrotRow),
) -> Result<MandelbrotReport, BenchError> {
    if config.runs == 0 {
        return Err(BenchError::Config(
            "at least one timed run is needed".into(),
        ));
    }
    if !config.size.is_power_of_two() || config.size < workloads::mandelbrot::ROOT_SIZE {
        return Err(BenchError::Config(format!(
            "the Mandelbrot size {} is not a power of two of at least {}",
            config.size,
            workloads::mandelbrot::ROOT_SIZE
        )));
    }
    let view = View::whole_set(config.size, config.max_iter);
    let brute = cpu_brute_force(&view);
    let cpu = cpu_mariani_silver(&view);
    let differ_from_brute_force = brute
        .iter()
        .zip(&cpu.counts)
        .filter(|(a, b)| a != b)
        .count();

    let flat = FlatMandelbrot::new(gpu, view)?;
    let flat_name = "mandelbrot flat dispatch";
    crate::verify::fill_sentinel(&gpu.queue, &flat.counts);
    flat.run()?;
    let Matched {
        contraction: flat_contraction,
        reference: flat_reference,
    } = match_flat(&view, &flat.counts()?, &brute, flat_name)?;
    let (times, walls): (Vec<_>, Vec<_>) = (0..config.runs)
        .map(|_| flat.run())
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    crate::verify::compare(&flat.counts()?, &flat_reference, flat_name)?;
    let flat_timings = Timings::new(times, &walls, flat.time_source());
    let flat_median = flat_timings.median;
    let row = MandelbrotRow {
        variant: "flat".to_owned(),
        workgroups: (config.size / FLAT_TILE).pow(2),
        chunks: None,
        timings: flat_timings,
        ratio_to_flat: 1.0,
        tiles: None,
        blocks: None,
        escape_pixels: view.pixels() as u64,
        iterations: flat_reference.iter().map(|&n| u64::from(n)).sum(),
        dispatches: Some(1),
        fused: fused(flat_contraction),
    };
    progress(&row);
    let mut rows = vec![row];

    for &chunks in &config.chunks {
        let variants = config
            .workgroups
            .iter()
            .map(|&w| (Strategy::Megakernel, w, false))
            .chain(
                config
                    .rounds_workgroups
                    .iter()
                    .map(|&w| (Strategy::rounds(), w, false)),
            )
            .chain([
                // Checked mode's cost: the default megakernel with every
                // index into `counts` guarded.
                (Strategy::Megakernel, scheduler::DEFAULT_WORKGROUPS, true),
            ]);
        for (strategy, workgroups, checked) in variants {
            let mut row = measure_scheduled(
                gpu,
                view,
                config,
                (strategy, workgroups, chunks, checked),
                &cpu,
            )?;
            row.ratio_to_flat =
                flat_median.as_secs_f64() / row.timings.median.as_secs_f64().max(1e-12);
            progress(&row);
            rows.push(row);
        }
    }
    Ok(MandelbrotReport {
        config: config.clone(),
        differ_from_brute_force,
        rows,
    })
}

/// The table header.
pub fn format_mandelbrot_header() -> String {
    format!(
        "{:<11}{:>6}{:>7}  {:>11}{:>11}{:>11}{:>10}{:>8}  {:>7}{:>7}{:>11}{:>13}{:>6}  timer",
        "variant",
        "wg",
        "chunks",
        "median ms",
        "min ms",
        "max ms",
        "wall ms",
        "ratio",
        "tiles",
        "blocks",
        "escape px",
        "iterations",
        "disp",
    )
}

/// One table line.
pub fn format_mandelbrot_row(row: &MandelbrotRow) -> String {
    let ms = |d: Duration| format!("{:.3}", d.as_secs_f64() * 1e3);
    let or_dash = |v: Option<u64>| v.map_or("-".to_owned(), |v| v.to_string());
    format!(
        "{:<11}{:>6}{:>7}  {:>11}{:>11}{:>11}{:>10}{:>8.3}  {:>7}{:>7}{:>11}{:>13}{:>6}  {}",
        row.variant,
        row.workgroups,
        row.chunks.map_or("-".to_owned(), |c| c.to_string()),
        ms(row.timings.median),
        ms(row.timings.min),
        ms(row.timings.max),
        ms(row.timings.wall_median),
        row.ratio_to_flat,
        or_dash(row.tiles),
        or_dash(row.blocks),
        row.escape_pixels,
        row.iterations,
        row.dispatches.map_or("-".to_owned(), |d| d.to_string()),
        row.timings.source.label(),
    )
}

/// The whole table, then a line per row whose shader the driver fused.
pub fn format_mandelbrot_table(report: &MandelbrotReport) -> String {
    let mut s = format_mandelbrot_header();
    s.push('\n');
    for row in &report.rows {
        s.push_str(&format_mandelbrot_row(row));
        s.push('\n');
    }
    for row in &report.rows {
        if let Some(fused) = &row.fused {
            let chunks = row
                .chunks
                .map_or(String::new(), |c| format!(", {c} chunk(s)"));
            s.push_str(&format!(
                "the driver fused ({} {} wg{chunks}): {fused}; verified against the CPU fusing the same\n",
                row.variant, row.workgroups
            ));
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use scheduler::DeviceRequest;

    /// The flat dispatch and the subdivision, both strategies, at 128x128,
    /// each verified against the CPU inside `run_mandelbrot`.
    #[test]
    fn every_variant_matches_the_cpu() {
        if std::env::var("SKIP_GPU_TESTS").is_ok_and(|v| v == "1") {
            return;
        }
        let gpu = Gpu::new(&DeviceRequest::default())
            .expect("no GPU adapter (set SKIP_GPU_TESTS=1 to skip GPU tests)");
        let config = MandelbrotConfig {
            size: 128,
            max_iter: 64,
            runs: 1,
            workgroups: vec![scheduler::DEFAULT_WORKGROUPS, 3],
            chunks: vec![1, 4],
            rounds_workgroups: vec![scheduler::DEFAULT_WORKGROUPS],
        };
        let report = run_mandelbrot(&gpu, &config, |_| {}).unwrap();
        // Flat, then per chunk count: 2 megakernel rows, 1 Rounds row and
        // 1 checked megakernel row.
        assert_eq!(report.rows.len(), 9);
        assert_eq!(
            report
                .rows
                .iter()
                .filter(|r| r.variant == "mk checked")
                .count(),
            2
        );
        assert!(
            report
                .rows
                .iter()
                .all(|r| r.timings.median > Duration::ZERO)
        );
    }

    #[test]
    fn the_flat_module_declares_the_constants() {
        let wgsl = flat_wgsl(&View::whole_set(64, 10));
        assert!(wgsl.contains("const MAX_ITER: u32 = 10u;"));
        assert!(wgsl.contains("const STEP: f32 = 0.046875f;"));
        assert!(wgsl.contains("fn escape_count(px: u32, py: u32) -> u32"));
    }
}
