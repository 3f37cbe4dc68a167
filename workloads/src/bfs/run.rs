//! A checked GPU run: the levels compared exactly with a CPU BFS and the
//! scheduler's counters with the bodies', with a human-readable summary.

use std::error::Error;
use std::fmt::Write as _;

use scheduler::{CompileOptions, Executor, ExecutorConfig, Gpu, Seeds};

use super::{BfsGraph, COUNTER_WORDS, Counters, Hop, Problem, UNREACHED, cpu_levels, graph};
use crate::Checked;

/// Builds the graph, runs it on `gpu` with `config`, and compares the levels
/// with a CPU BFS exactly and the scheduler's counters with the bodies'.
pub fn run(
    gpu: &Gpu,
    problem: &Problem,
    config: &ExecutorConfig,
) -> Result<Checked, Box<dyn Error>> {
    let BfsGraph {
        graph,
        visit,
        expand,
    } = graph(problem);
    let compiled = graph.compile(&CompileOptions::with_features(
        scheduler::recommended_features(&gpu.device),
    ))?;
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, config)?;

    // The executor creates, fills and reads the buffers of the typed
    // resources; the run binds them by themselves.
    let nodes = problem.graph.nodes() as usize;
    executor.write("row_start", &problem.graph.row_start)?;
    // A binding may not be empty, hence the padding word of an edgeless graph.
    let mut adjacency_words = problem.graph.adjacency.clone();
    if adjacency_words.is_empty() {
        adjacency_words.push(0);
    }
    executor.write("adjacency", &adjacency_words)?;
    executor.write("levels", &vec![UNREACHED; nodes])?;
    executor.write("counters", &[0u32; COUNTER_WORDS])?;

    let seeds: Vec<Hop> = problem
        .sources
        .iter()
        .map(|&node| Hop { node, level: 0 })
        .collect();
    let report = executor.run(&Seeds::new().add(&visit, &seeds), &[])?;
    let gpu_levels = executor.read::<u32>("levels")?;
    let words = executor.read::<u32>("counters")?;
    let counters = Counters {
        improving_visits: words[0],
        visit_enqueues: words[1],
        stale_expands: words[2],
    };

    let cpu = cpu_levels(problem);
    let mut mismatches = Vec::new();
    let wrong: Vec<usize> = (0..nodes).filter(|&v| gpu_levels[v] != cpu[v]).collect();
    if !wrong.is_empty() {
        let show = |l: u32| {
            if l == UNREACHED {
                "unreached".to_owned()
            } else {
                l.to_string()
            }
        };
        let examples: Vec<String> = wrong
            .iter()
            .take(8)
            .map(|&v| {
                format!(
                    "node {v}: GPU {}, CPU {}",
                    show(gpu_levels[v]),
                    show(cpu[v])
                )
            })
            .collect();
        mismatches.push(format!(
            "{} of {nodes} levels differ, e.g. {}",
            wrong.len(),
            examples.join("; ")
        ));
    }
    let visit = report.procedure(&visit).ok_or("no Visit stats")?;
    let expand = report.procedure(&expand).ok_or("no Expand stats")?;
    let mut expect = |what: &str, scheduler: u64, body: u64| {
        if scheduler != body {
            mismatches.push(format!(
                "{what}: the scheduler says {scheduler}, the bodies {body}"
            ));
        }
    };
    expect(
        "Expand enqueued (= improving visits)",
        expand.enqueued,
        counters.improving_visits.into(),
    );
    expect(
        "Expand executed (= enqueued)",
        expand.executed,
        expand.enqueued,
    );
    expect(
        "Visit enqueued (= enqueues by Expand)",
        visit.enqueued,
        counters.visit_enqueues.into(),
    );
    expect(
        "Visit executed (= seeded + enqueued)",
        visit.executed,
        visit.seeded + visit.enqueued,
    );
    let reached = cpu.iter().filter(|&&l| l != UNREACHED).count();
    // Each reached node improves at least once; the excess is re-visits.
    if u64::from(counters.improving_visits) < reached as u64 {
        mismatches.push(format!(
            "{} improving visits for {reached} reached nodes",
            counters.improving_visits
        ));
    }

    let mut summary = String::new();
    let depth = cpu
        .iter()
        .filter(|&&l| l != UNREACHED)
        .max()
        .copied()
        .unwrap_or(0);
    writeln!(
        summary,
        "{nodes} nodes, {} directed edges (max degree {}), {} source(s): {reached} reached, {depth} levels",
        problem.graph.adjacency.len(),
        problem.graph.max_degree(),
        problem.sources.len()
    )?;
    writeln!(
        summary,
        "{} improving visits ({} re-visits that lowered a level again), {} stale expands skipped",
        counters.improving_visits,
        u64::from(counters.improving_visits).saturating_sub(reached as u64),
        counters.stale_expands
    )?;
    Ok(Checked {
        report,
        mismatches,
        summary,
    })
}
