//! A compiled Mandelbrot graph with its executor for repeated renders, and a
//! checked render: every pixel and the scheduler's counters compared with
//! the CPU subdivision under the arithmetic the driver used, with a
//! human-readable summary.

use std::error::Error;
use std::fmt::Write as _;

use scheduler::{
    CompileOptions, CompiledGraph, Executor, ExecutorConfig, Gpu, ProcedureId, RunError, RunReport,
    Seeds, Strategy,
};

use super::{
    Block, Contraction, MIN_SIZE, MandelbrotGraph, Matched, Subdivision, Tile, UNWRITTEN,
    Unexplained, View, cpu_brute_force_with, cpu_mariani_silver, graph, match_subdivision,
    pixel_mismatches,
};

/// A compiled graph and an executor, which owns the output buffer, for
/// repeated runs.
#[derive(Debug)]
pub struct Mandelbrot {
    /// What is rendered.
    pub view: View,
    /// The handle of `Tile`, for its statistics.
    pub tile: ProcedureId<Tile>,
    /// The handle of `Block`, for its statistics.
    pub block: ProcedureId<Block>,
    executor: Executor,
    seeds: Seeds,
}

impl Mandelbrot {
    /// Compiles the graph with `options` and creates the executor and buffers.
    pub fn new(
        gpu: &Gpu,
        view: View,
        options: &CompileOptions,
        config: &ExecutorConfig,
    ) -> Result<Self, Box<dyn Error>> {
        let MandelbrotGraph { graph, tile, block } = graph(&view);
        let compiled: CompiledGraph = graph.compile(options)?;
        let executor = Executor::new(&gpu.device, &gpu.queue, &compiled, config)?;
        let seeds = Seeds::new().add(&tile, &view.roots());
        Ok(Self {
            view,
            tile,
            block,
            executor,
            seeds,
        })
    }

    /// Fills the output with [`UNWRITTEN`] and renders the image once. The
    /// executor binds its own `counts` buffer, so the run names no binding.
    pub fn render(&mut self, strategy: Strategy) -> Result<RunReport, RunError> {
        let unwritten = vec![UNWRITTEN; self.view.pixels()];
        self.executor.write("counts", &unwritten)?;
        self.executor.run_with(strategy, &self.seeds, &[])
    }

    /// The escape counts of the last render, row by row.
    pub fn counts(&self) -> Result<Vec<u32>, RunError> {
        self.executor.read::<u32>("counts")
    }
}

/// A checked run: the report, the image and every disagreement with the CPU
/// (none when the run is correct).
#[derive(Debug)]
pub struct Checked {
    /// The scheduler's report of the run.
    pub report: RunReport,
    /// Escape count per pixel, row by row.
    pub counts: Vec<u32>,
    /// The multiply-adds the driver fused, as found by matching the counts
    /// ([`match_subdivision`]); `None` when no contraction explains them.
    pub contraction: Option<Contraction>,
    /// Every disagreement with the CPU, empty when the run is correct (with
    /// no contraction found, the disagreements with the plain reference).
    pub mismatches: Vec<String>,
    /// Pixels where Mariani–Silver (on the CPU) differs from brute force,
    /// both under the matched contraction.
    pub differ_from_brute_force: usize,
    /// A human-readable summary of the result.
    pub summary: String,
}

impl Mandelbrot {
    /// Every disagreement of a render's counts and report with the CPU
    /// subdivision `cpu` (none when the render is correct): exact, under
    /// whatever arithmetic `cpu` was computed with. [`Self::check`] finds
    /// the arithmetic the driver used.
    pub fn compare(&self, report: &RunReport, counts: &[u32], cpu: &Subdivision) -> Vec<String> {
        pixel_mismatches(&self.view, counts, &cpu.counts)
            .into_iter()
            .chain(self.counter_mismatches(report, cpu))
            .collect()
    }

    /// Matches a render's counts and counters with `plain`, the plain
    /// [`cpu_mariani_silver`] of the view, or else with the subdivision
    /// under the contraction that explains them ([`match_subdivision`]).
    pub fn check(
        &self,
        report: &RunReport,
        counts: &[u32],
        plain: &Subdivision,
    ) -> Result<Matched<Subdivision>, Unexplained> {
        match_subdivision(&self.view, counts, plain, |cpu| {
            self.counter_mismatches(report, cpu)
        })
    }

    /// The disagreements of the scheduler's counters with the tile counts
    /// of `cpu`.
    fn counter_mismatches(&self, report: &RunReport, cpu: &Subdivision) -> Vec<String> {
        let mut mismatches = Vec::new();
        let mut expect = |what: &str, gpu: Option<u64>, cpu: u64| {
            if gpu != Some(cpu) {
                mismatches.push(format!("{what}: GPU {gpu:?}, CPU {cpu}"));
            }
        };
        let tile = report.procedure(&self.tile);
        let block = report.procedure(&self.block);
        expect("Tile executed", tile.map(|s| s.executed), cpu.tiles);
        expect(
            "Tile enqueued (4 per split)",
            tile.map(|s| s.enqueued),
            4 * cpu.split,
        );
        expect("Block executed", block.map(|s| s.executed), cpu.blocks);
        expect("Block enqueued", block.map(|s| s.enqueued), cpu.blocks);
        mismatches
    }
}

/// Renders `view` once with the megakernel and checks it against the CPU,
/// under the arithmetic the driver used ([`Mandelbrot::check`]).
pub fn run(gpu: &Gpu, view: &View, config: &ExecutorConfig) -> Result<Checked, Box<dyn Error>> {
    let options = CompileOptions::with_features(scheduler::recommended_features(&gpu.device));
    let mut mandelbrot = Mandelbrot::new(gpu, *view, &options, config)?;
    let report = mandelbrot.render(Strategy::Megakernel)?;
    let counts = mandelbrot.counts()?;

    let plain = cpu_mariani_silver(view);
    let (contraction, cpu, mismatches) = match mandelbrot.check(&report, &counts, &plain) {
        Ok(matched) => (Some(matched.contraction), matched.reference, Vec::new()),
        Err(unexplained) => (None, plain, unexplained.mismatches),
    };
    let brute = cpu_brute_force_with(view, contraction.unwrap_or_default());
    let differ_from_brute_force = (0..view.pixels())
        .filter(|&i| cpu.counts[i] != brute[i])
        .count();

    let mut summary = String::new();
    let inside = counts.iter().filter(|&&n| n == view.max_iter).count();
    writeln!(
        summary,
        "{}x{} pixels, at most {} iterations: {inside} pixels in the set",
        view.width, view.height, view.max_iter
    )?;
    match contraction {
        Some(c) if !c.is_plain() => writeln!(
            summary,
            "the driver fused: {c}; the CPU reference computes the same"
        )?,
        Some(_) => {}
        None => writeln!(
            summary,
            "no fusing of the escape loop's multiply-adds explains the counts: compared with \
             the plain CPU reference"
        )?,
    }
    writeln!(
        summary,
        "{} tiles: {} filled from their border, {} split, {} handed to blocks of {MIN_SIZE}x{MIN_SIZE}",
        cpu.tiles, cpu.filled, cpu.split, cpu.blocks
    )?;
    let brute_iterations: u64 = brute.iter().map(|&n| u64::from(n)).sum();
    writeln!(
        summary,
        "escape counts iterated for {} pixels, {} iterations ({:.1}% of brute force's {} pixels, {:.1}% of its {} iterations)",
        cpu.escape_pixels,
        cpu.iterations,
        100.0 * cpu.escape_pixels as f64 / view.pixels() as f64,
        view.pixels(),
        100.0 * cpu.iterations as f64 / brute_iterations as f64,
        brute_iterations
    )?;
    writeln!(
        summary,
        "pixels where Mariani-Silver differs from brute force: {differ_from_brute_force}"
    )?;
    Ok(Checked {
        report,
        counts,
        contraction,
        mismatches,
        differ_from_brute_force,
        summary,
    })
}
