//! The one-procedure graph and a checked GPU run: the tally and the
//! scheduler's counters compared exactly with the CPU reference, with a
//! human-readable summary.

use std::error::Error;
use std::fmt::Write as _;

use scheduler::{
    Atomic, CompileOptions, Executor, ExecutorConfig, Gpu, Graph, Procedure, ProcedureId, Resource,
    Seeds,
};

use super::wgsl::{REFINE_BODY, WGSL_LIBRARY};
use super::{
    Bump, GRID, Interval, MAX_DEPTH, Problem, ROOT_WIDTH, TALLY_STRIDE, Tally, cpu_reference,
    dense_simpson, roots,
};
use crate::Checked;

/// The graph of [`graph`], with the handle of its procedure.
#[derive(Debug)]
pub struct QuadratureGraph {
    /// The graph, ready to compile.
    pub graph: Graph,
    /// The handle of `Refine`.
    pub refine: ProcedureId<Interval>,
}

/// The one-procedure graph: `Refine` enqueues into itself.
pub fn graph(problem: &Problem) -> QuadratureGraph {
    let mut graph = Graph::new("adaptive quadrature");
    graph
        .constant("ROOT_WIDTH", ROOT_WIDTH)
        .constant("MAX_DEPTH", MAX_DEPTH)
        .constant("THRESHOLD", problem.threshold)
        .constant("TALLY_STRIDE", TALLY_STRIDE);
    graph.library(WGSL_LIBRARY);
    // The typed resource declares `struct Bump` from the Rust type.
    graph.resource(Resource::storage_read::<[Bump]>("bumps"));
    graph.resource(
        Resource::storage::<[Atomic<u32>]>("tally")
            .min_len(u64::from(TALLY_STRIDE * (MAX_DEPTH + 1))),
    );
    let refine = graph.procedure(
        Procedure::of::<Interval>("Refine")
            .initial(true)
            .body(REFINE_BODY),
    );
    graph.connect_with_fan_out(&refine, &refine, 2);
    QuadratureGraph { graph, refine }
}

/// Builds the graph, runs it on `gpu` with `config`, and compares the tally
/// and the scheduler's counters with the CPU reference exactly.
pub fn run(
    gpu: &Gpu,
    problem: &Problem,
    config: &ExecutorConfig,
) -> Result<Checked, Box<dyn Error>> {
    problem.assert_in_range();
    let QuadratureGraph { graph, refine } = graph(problem);
    let compiled = graph.compile(&CompileOptions::with_features(
        scheduler::recommended_features(&gpu.device),
    ))?;
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, config)?;

    // The executor creates, fills and reads the typed resources' buffers.
    executor.write("bumps", &problem.bumps)?;
    let tally_words = (TALLY_STRIDE * (MAX_DEPTH + 1)) as usize;
    executor.write("tally", &vec![0u32; tally_words])?;
    let roots = roots(problem);
    let report = executor.run(&Seeds::new().add(&refine, &roots), &[])?;
    let words = executor.read::<u32>("tally")?;
    let mut gpu_tally = Tally::new();
    for (d, chunk) in words.chunks_exact(TALLY_STRIDE as usize).enumerate() {
        gpu_tally.accepted[d] = chunk[0];
        gpu_tally.forced[d] = chunk[1];
        gpu_tally.sums[d] = u64::from(chunk[2]) | u64::from(chunk[3]) << 32;
    }

    let (cpu_tally, processed) = cpu_reference(problem);
    let mut mismatches = Vec::new();
    for d in 0..=MAX_DEPTH as usize {
        let (g, c) = (&gpu_tally, &cpu_tally);
        if (g.accepted[d], g.forced[d], g.sums[d]) != (c.accepted[d], c.forced[d], c.sums[d]) {
            mismatches.push(format!(
                "depth {d}: GPU accepted {} (forced {}) sum {}, CPU accepted {} (forced {}) sum {}",
                g.accepted[d], g.forced[d], g.sums[d], c.accepted[d], c.forced[d], c.sums[d]
            ));
        }
    }
    let stats = report.procedure(&refine).ok_or("no Refine stats")?;
    if stats.executed != processed {
        mismatches.push(format!(
            "Refine executed {} intervals, the CPU processed {processed}",
            stats.executed
        ));
    }
    // Every split enqueues two children: processed = roots + 2 * splits.
    let splits = processed - cpu_tally.intervals();
    if stats.enqueued != 2 * splits {
        mismatches.push(format!(
            "Refine enqueued {} intervals, expected 2 x {splits} splits",
            stats.enqueued
        ));
    }

    let mut summary = String::new();
    let (gi, ci) = (gpu_tally.integral(), cpu_tally.integral());
    writeln!(
        summary,
        "{} bumps, threshold {}: {} accepted intervals ({} forced at depth {MAX_DEPTH}) of {} processed",
        problem.bumps.len(),
        problem.threshold,
        gpu_tally.intervals(),
        gpu_tally.forced.iter().sum::<u32>(),
        stats.executed
    )?;
    writeln!(summary, "accepted per depth: {:?}", gpu_tally.accepted)?;
    writeln!(summary, "integral: GPU {gi:.9}, CPU {ci:.9}")?;
    let dense = dense_simpson(problem);
    writeln!(
        summary,
        "dense Simpson over all {} points: {dense:.9} (adaptive relative error {:.2e}); continuous bumps: {:.9}",
        GRID + 1,
        (gi - dense).abs() / dense,
        problem.analytic_integral()
    )?;
    if gpu_tally == cpu_tally && gi != ci {
        mismatches.push(format!("equal tallies but integrals {gi} != {ci}"));
    }
    Ok(Checked {
        report,
        mismatches,
        summary,
    })
}
