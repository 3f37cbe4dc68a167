//! Adaptive quadrature whose estimates are combined bottom-up with joins
//! ([`scheduler::Graph::join`]): `Refine` either accepts an interval, writing
//! its contribution and its error estimate `|T_l + T_r - 2 T|` into the
//! `estimates` resource at the interval's id, or splits it, opening a join
//! whose continuation `Combine` adds the two halves' estimates once their
//! whole refinement has finished. Each root interval's entry then holds the
//! value and error estimate of its whole refinement, compared exactly with
//! the CPU's ([`root_estimates`](super::root_estimates)).

use std::error::Error;

use scheduler::{
    Atomic, CompileOptions, ExecutorConfig, Gpu, Graph, Procedure, ProcedureId, Resource, Seeds,
    Strategy,
};

use super::cpu::{cpu_reference, root_estimates, roots};
use super::wgsl::WGSL_LIBRARY;
use super::{Bump, MAX_DEPTH, Problem, ROOT_WIDTH};
use crate::Checked;

/// An interval as [`Interval`](super::Interval), with the id of its entry in
/// `estimates`.
#[scheduler::item]
#[derive(Debug)]
#[expect(
    missing_docs,
    reason = "field docs would become WGSL comments in the generated module; the struct's doc describes the fields"
)]
pub struct Span {
    pub a: u32,
    pub depth: u32,
    pub fa: u32,
    pub fm: u32,
    pub fb: u32,
    pub id: u32,
}

/// A join's record: the split interval's id and its halves' ids
/// `first` and `first + 1`.
#[scheduler::item]
#[derive(Debug)]
#[expect(
    missing_docs,
    reason = "field docs would become WGSL comments in the generated module; the struct's doc describes the fields"
)]
pub struct Combine {
    pub id: u32,
    pub first: u32,
}

/// Words per entry of `estimates`: the value and the error estimate, each
/// 64 bits as (low, high).
const ESTIMATE_WORDS: u32 = 4;

/// 64-bit pairs in `estimates`, and the integrand of the plain workload
/// (without its tally accumulator).
fn library() -> String {
    let integrand = WGSL_LIBRARY
        .split("// Adds `value`")
        .next()
        .unwrap_or(WGSL_LIBRARY);
    format!(
        "{integrand}
fn estimate_load(at: u32) -> vec2<u32> {{
    return vec2<u32>(atomicLoad(&estimates[at]), atomicLoad(&estimates[at + 1u]));
}}

fn estimate_store(at: u32, value: vec2<u32>) {{
    atomicStore(&estimates[at], value.x);
    atomicStore(&estimates[at + 1u], value.y);
}}

// The 64-bit sum of two (low, high) pairs.
fn add_pairs(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {{
    let low = a.x + b.x;
    return vec2<u32>(low, a.y + b.y + select(0u, 1u, low < a.x));
}}
"
    )
}

/// `Refine`: the decision of the plain workload; an accepted interval
/// writes its estimate, a split one opens the join that combines its halves.
const REFINE_BODY: &str = "
if (valid) {
    let h = ROOT_WIDTH >> item.depth;
    let q = h / 4u;
    let fl = f(item.a + q);
    let fr = f(item.a + 3u * q);
    let t = item.fa + 4u * item.fm + item.fb;
    let tl = item.fa + 4u * fl + item.fm;
    let tr = item.fm + 4u * fr + item.fb;
    let diff = i32(tl + tr) - 2i * i32(t);
    let ok = u32(abs(diff)) <= THRESHOLD;
    let at = ESTIMATE_WORDS * item.id;
    if (ok || item.depth == MAX_DEPTH) {
        estimate_store(at, vec2<u32>(8u * (tl + tr) - t, 0u));
        estimate_store(at + 2u, vec2<u32>(u32(abs(diff)), 0u));
    } else {
        let first = ROOTS + atomicAdd(&counters[0], 2u);
        if (ESTIMATE_WORDS * (first + 2u) > arrayLength(&estimates)) {
            atomicAdd(&counters[1], 1u);
        } else {
            _ = join_open_Combine(Combine(item.id, first));
            enqueue_Refine(Span(item.a, item.depth + 1u, item.fa, fl, item.fm, first));
            enqueue_Refine(Span(item.a + h / 2u, item.depth + 1u, item.fm, fr, item.fb, first + 1u));
        }
    }
}
";

/// `Combine`: both halves' refinements have finished; add their estimates.
const COMBINE_BODY: &str = "
if (valid) {
    let left = ESTIMATE_WORDS * item.first;
    let right = left + ESTIMATE_WORDS;
    let at = ESTIMATE_WORDS * item.id;
    estimate_store(at, add_pairs(estimate_load(left), estimate_load(right)));
    estimate_store(at + 2u, add_pairs(estimate_load(left + 2u), estimate_load(right + 2u)));
}
";

/// The graph of [`combined_graph`], with its handles.
#[derive(Debug)]
pub struct CombinedGraph {
    /// The graph, ready to compile.
    pub graph: Graph,
    /// The handle of `Refine`.
    pub refine: ProcedureId<Span>,
    /// The handle of `Combine`, the continuation of `Refine`'s joins.
    pub combine: ProcedureId<Combine>,
}

/// `Refine` enqueues into itself (two halves) and opens joins whose
/// continuation is `Combine`.
pub fn combined_graph(problem: &Problem) -> CombinedGraph {
    let mut graph = Graph::new("adaptive quadrature, combined bottom-up");
    graph
        .constant("ROOT_WIDTH", ROOT_WIDTH)
        .constant("MAX_DEPTH", MAX_DEPTH)
        .constant("THRESHOLD", problem.threshold)
        .constant("ROOTS", roots(problem).len() as u32)
        .constant("ESTIMATE_WORDS", ESTIMATE_WORDS);
    graph.library(&library());
    graph.resource(Resource::storage_read::<[Bump]>("bumps"));
    graph.resource(Resource::storage::<[Atomic<u32>]>("estimates"));
    graph.resource(Resource::storage::<[Atomic<u32>]>("counters").min_len(2));
    let refine = graph.procedure(
        Procedure::of::<Span>("Refine")
            .initial(true)
            .body(REFINE_BODY),
    );
    let combine = graph.procedure(Procedure::of::<Combine>("Combine").body(COMBINE_BODY));
    graph
        .connect_with_fan_out(&refine, &refine, 2)
        .join(&refine, &combine);
    CombinedGraph {
        graph,
        refine,
        combine,
    }
}

/// Runs the combined quadrature of `problem` on `gpu` under `strategy` and
/// compares every root's value and error estimate, and the joins' counts,
/// with the CPU exactly.
pub fn run_combined(
    gpu: &Gpu,
    problem: &Problem,
    config: &ExecutorConfig,
    strategy: Strategy,
) -> Result<Checked, Box<dyn Error>> {
    problem.assert_in_range();
    let CombinedGraph {
        graph,
        refine,
        combine,
    } = combined_graph(problem);
    let compiled = graph.compile(&CompileOptions::with_features(
        scheduler::recommended_features(&gpu.device),
    ))?;
    let mut executor = scheduler::Executor::new(&gpu.device, &gpu.queue, &compiled, config)?;
    let (tally, processed) = cpu_reference(problem);
    let splits = processed - tally.intervals();
    executor.write("bumps", &problem.bumps)?;
    executor.write(
        "estimates",
        &vec![0u32; (u64::from(ESTIMATE_WORDS) * processed) as usize],
    )?;
    executor.write("counters", &[0u32; 2])?;
    let seeds: Vec<Span> = roots(problem)
        .into_iter()
        .enumerate()
        .map(|(i, r)| Span {
            a: r.a,
            depth: r.depth,
            fa: r.fa,
            fm: r.fm,
            fb: r.fb,
            id: i as u32,
        })
        .collect();
    let report = executor.run_with(strategy, &Seeds::new().add(&refine, &seeds), &[])?;
    let words = executor.read::<u32>("estimates")?;
    let counters = executor.read::<u32>("counters")?;

    let pair = |at: usize| u64::from(words[at]) | u64::from(words[at + 1]) << 32;
    let mut mismatches = Vec::new();
    if counters[1] != 0 {
        mismatches.push(format!("{} splits found no room for ids", counters[1]));
    }
    if u64::from(counters[0]) != 2 * splits {
        mismatches.push(format!(
            "{} ids handed out for halves, the CPU split {splits} intervals",
            counters[0]
        ));
    }
    let expected = root_estimates(problem);
    let (mut value, mut error) = (0u64, 0u64);
    for (i, cpu) in expected.iter().enumerate() {
        let at = ESTIMATE_WORDS as usize * i;
        let gpu_estimate = (pair(at), pair(at + 2));
        value += gpu_estimate.0;
        error += gpu_estimate.1;
        if gpu_estimate != (cpu.value, cpu.error) && mismatches.len() < 8 {
            mismatches.push(format!(
                "root {i}: GPU value {} error {}, CPU value {} error {}",
                gpu_estimate.0, gpu_estimate.1, cpu.value, cpu.error
            ));
        }
    }
    let tally_value: u64 = tally.sums.iter().sum();
    if value != tally_value {
        mismatches.push(format!(
            "the roots add up to {value}, the CPU's tally to {tally_value}"
        ));
    }
    let joins = report.join(&combine).cloned().unwrap_or_default();
    if (joins.opened, joins.fired) != (splits, splits) {
        mismatches.push(format!(
            "joins opened {}, fired {}; the CPU split {splits} intervals",
            joins.opened, joins.fired
        ));
    }
    let summary = format!(
        "{} roots, {splits} splits combined bottom-up: value {value}, error estimate {error} (CPU {}, {})\n",
        expected.len(),
        tally_value,
        expected.iter().map(|e| e.error).sum::<u64>()
    );
    Ok(Checked {
        report,
        mismatches,
        summary,
    })
}
