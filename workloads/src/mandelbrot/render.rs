//! A compiled Mandelbrot graph with its executor for repeated renders, and a
//! checked render: every pixel and the scheduler's counters compared with
//! the CPU subdivision, with a human-readable summary.

use std::error::Error;
use std::fmt::Write as _;

use scheduler::{
    CompileOptions, CompiledGraph, Executor, ExecutorConfig, Gpu, ProcedureId, RunError, RunReport,
    Seeds, Strategy,
};

use super::{
    Block, MIN_SIZE, MandelbrotGraph, Subdivision, Tile, UNWRITTEN, View, cpu_brute_force,
    cpu_mariani_silver, graph,
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
    /// Every disagreement with the CPU, empty when the run is correct.
    pub mismatches: Vec<String>,
    /// Pixels where Mariani–Silver (on the CPU) differs from brute force.
    pub differ_from_brute_force: usize,
    /// A human-readable summary of the result.
    pub summary: String,
}

impl Mandelbrot {
    /// Every disagreement of a render's counts and report with the CPU
    /// subdivision `cpu` (none when the render is correct).
    pub fn compare(&self, report: &RunReport, counts: &[u32], cpu: &Subdivision) -> Vec<String> {
        let view = &self.view;
        let mut mismatches = Vec::new();
        let wrong: Vec<usize> = (0..view.pixels())
            .filter(|&i| counts[i] != cpu.counts[i])
            .collect();
        if !wrong.is_empty() {
            let width = view.width as usize;
            let examples: Vec<String> = wrong
                .iter()
                .take(8)
                .map(|&i| {
                    format!(
                        "({}, {}): GPU {}, CPU {}",
                        i % width,
                        i / width,
                        counts[i],
                        cpu.counts[i]
                    )
                })
                .collect();
            mismatches.push(format!(
                "{} of {} pixels differ, e.g. {}",
                wrong.len(),
                view.pixels(),
                examples.join("; ")
            ));
        }
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

/// Renders `view` once with the megakernel and checks it against the CPU.
pub fn run(gpu: &Gpu, view: &View, config: &ExecutorConfig) -> Result<Checked, Box<dyn Error>> {
    let options = CompileOptions::with_features(scheduler::recommended_features(&gpu.device));
    let mut mandelbrot = Mandelbrot::new(gpu, *view, &options, config)?;
    let report = mandelbrot.render(Strategy::Megakernel)?;
    let counts = mandelbrot.counts()?;

    let cpu = cpu_mariani_silver(view);
    let mismatches = mandelbrot.compare(&report, &counts, &cpu);
    let brute = cpu_brute_force(view);
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
        mismatches,
        differ_from_brute_force,
        summary,
    })
}
