//! The graph of the tree sum and a checked GPU run: every node's sum, and
//! every join's firing, compared with the CPU exactly.

use std::error::Error;

use scheduler::{
    Atomic, CompileOptions, Executor, ExecutorConfig, Gpu, Graph, Procedure, ProcedureId, Resource,
    Retry, RunError, RunReport, Seeds, Strategy,
};

use super::cpu::subtree_sums;
use super::wgsl::{LIBRARY, REFIT_BODY, SPLIT_BODY};
use super::{MAX_FAN, Node, Refit, TreeParams, children};
use crate::Checked;

/// The resources of the graph, which a run writes (or zeroes) first.
pub const RESOURCES: [&str; 3] = ["nodes", "fires", "counters"];

/// Words per node in `nodes`: its sum, key, shape (depth and level << 8)
/// and whether it is done (1).
pub const NODE_WORDS: u32 = 4;

/// The graph of [`graph`], with the handles of its procedures.
#[derive(Debug)]
pub struct TreeSumGraph {
    /// The graph, ready to compile.
    pub graph: Graph,
    /// The handle of `Split`.
    pub split: ProcedureId<Node>,
    /// The handle of `Refit`, the continuation of `Split`'s joins.
    pub refit: ProcedureId<Refit>,
}

/// A graph named `name` with the tree's node layout constants, its WGSL
/// library and the resources every tree-sum graph binds (`params`, `nodes`,
/// `fires`, `counters`).
pub(super) fn graph_with_resources(name: &str) -> Graph {
    let mut graph = Graph::new(name);
    graph
        .constant("NODE_WORDS", NODE_WORDS)
        .constant("NODE_SUM", 0u32)
        .constant("NODE_KEY", 1u32)
        .constant("NODE_SHAPE", 2u32)
        .constant("NODE_DONE", 3u32);
    graph.library(LIBRARY);
    graph.resource(Resource::storage_read::<[u32]>("params").min_len(3));
    graph.resource(Resource::storage::<[Atomic<u32>]>("nodes"));
    graph.resource(Resource::storage::<[Atomic<u32>]>("fires"));
    graph.resource(Resource::storage::<[Atomic<u32>]>("counters").min_len(3));
    graph
}

/// `Split` enqueues into itself (up to [`MAX_FAN`] children) and opens
/// joins whose continuation is `Refit`. `split_body` replaces `Split`'s
/// body (tests lose a child on purpose); `None` is the real one.
pub fn graph(split_body: Option<&str>) -> TreeSumGraph {
    let mut graph = graph_with_resources("tree sum");
    let split = graph.procedure(
        Procedure::of::<Node>("Split")
            .initial(true)
            .body(split_body.unwrap_or(SPLIT_BODY)),
    );
    let refit = graph.procedure(Procedure::of::<Refit>("Refit").body(REFIT_BODY));
    graph
        .connect_with_fan_out(&split, &split, MAX_FAN)
        .join(&split, &refit);
    TreeSumGraph {
        graph,
        split,
        refit,
    }
}

/// The compile options for `gpu`: its recommended features, the rest
/// default.
pub fn options(gpu: &Gpu) -> CompileOptions {
    CompileOptions::with_features(scheduler::recommended_features(&gpu.device))
}

/// Compiles [`graph`] with `options` (see [`options`]) and makes an
/// executor on `gpu` with `config`.
pub fn executor(
    gpu: &Gpu,
    options: &CompileOptions,
    config: &ExecutorConfig,
    split_body: Option<&str>,
) -> Result<(Executor, TreeSumGraph), Box<dyn Error>> {
    let tree = graph(split_body);
    let compiled = tree.graph.compile(options)?;
    let executor = Executor::new(&gpu.device, &gpu.queue, &compiled, config)?;
    Ok((executor, tree))
}

/// Writes the parameters and zeroes the resources for a tree of `nodes`
/// nodes.
pub fn prepare(executor: &mut Executor, params: &TreeParams, nodes: u64) -> Result<(), RunError> {
    executor.write("params", &params.words())?;
    executor.write(
        "nodes",
        &vec![0u32; (nodes * u64::from(NODE_WORDS)) as usize],
    )?;
    executor.write("fires", &vec![0u32; nodes as usize])?;
    executor.write("counters", &[0u32; 3])
}

/// The seed: the root, id 0.
pub fn seeds(tree: &TreeSumGraph, params: &TreeParams) -> Seeds {
    Seeds::new().add(
        &tree.split,
        &[Node {
            id: 0,
            key: params.root_key,
            shape: 0,
        }],
    )
}

/// Runs the tree sum of `params` under `strategy` on an executor of
/// [`executor`], in up to `attempts` attempts (a retry zeroes the
/// resources: after a join pool overflow, say, or a loop llvmpipe cut
/// short), and compares it with the CPU.
pub fn run(
    executor: &mut Executor,
    tree: &TreeSumGraph,
    params: &TreeParams,
    strategy: Strategy,
    attempts: u32,
) -> Result<Checked, Box<dyn Error>> {
    let nodes = subtree_sums(params).1.nodes;
    prepare(executor, params, nodes)?;
    let retry = Retry::with_context(attempts, |context| {
        for name in RESOURCES {
            // The buffers exist (`prepare` wrote them), so clearing succeeds.
            let _ = context.clear(name);
        }
    });
    let report = executor.run_with_retry(strategy, &seeds(tree, params), &[], retry)?;
    check(executor, tree, params, report)
}

/// Compares a finished run's resources and join counts with the CPU:
/// every node's sum, every inner node's continuation fired exactly once,
/// after all its children.
pub fn check(
    executor: &Executor,
    tree: &TreeSumGraph,
    params: &TreeParams,
    report: RunReport,
) -> Result<Checked, Box<dyn Error>> {
    let words = executor.read::<u32>("nodes")?;
    let fires = executor.read::<u32>("fires")?;
    let counters = executor.read::<u32>("counters")?;
    let (mut mismatches, summary) = compare(params, &words, &fires, &counters);
    let totals = subtree_sums(params).1;
    let joins = report.join(&tree.refit).cloned().unwrap_or_default();
    if (joins.opened, joins.fired, joins.outstanding) != (totals.inner, totals.inner, 0) {
        mismatches.push(format!(
            "joins opened {}, fired {}, outstanding {}; the CPU's tree has {} inner nodes",
            joins.opened, joins.fired, joins.outstanding, totals.inner
        ));
    }
    Ok(Checked {
        report,
        mismatches,
        summary,
    })
}

/// Compares the resources a run left (`nodes` words, `fires`, `counters`)
/// with the CPU: every node's sum, every inner node summed exactly once,
/// after all its children. Returns the disagreements and a summary.
pub fn compare(
    params: &TreeParams,
    words: &[u32],
    fires: &[u32],
    counters: &[u32],
) -> (Vec<String>, String) {
    let (expected, totals) = subtree_sums(params);
    let field = |offset: usize| -> Vec<u32> {
        words
            .chunks_exact(NODE_WORDS as usize)
            .map(|node| node[offset])
            .collect()
    };
    let (sums, keys, shapes, done) = (field(0), field(1), field(2), field(3));
    let mut mismatches = Vec::new();
    let used = u64::from(counters[0]) + 1;
    if used != totals.nodes {
        mismatches.push(format!(
            "{used} node ids handed out, the CPU's tree has {} nodes",
            totals.nodes
        ));
    }
    if counters[1] != 0 {
        mismatches.push(format!(
            "{} children were unfinished when their continuation ran",
            counters[1]
        ));
    }
    if counters[2] != 0 {
        mismatches.push(format!("{} ids beyond the resources", counters[2]));
    }
    let mut wrong = 0usize;
    let nodes = used.min(totals.nodes).min(sums.len() as u64) as usize;
    for id in 0..nodes {
        let (depth, level) = (shapes[id] & 0xff, shapes[id] >> 8);
        let shape = (keys[id], depth, level);
        let inner = children(params, keys[id], depth, level) > 0;
        let problems = [
            (expected.get(&shape) != Some(&sums[id]), "sum"),
            (done[id] != 1, "not done"),
            (fires[id] != u32::from(inner), "fires"),
        ];
        for (bad, what) in problems {
            if bad {
                wrong += 1;
                if wrong <= 8 {
                    mismatches.push(format!(
                        "node {id} (key {:#x}, depth {depth}, level {level}): {what}: sum {} (CPU {:?}), done {}, fired {} time(s)",
                        keys[id],
                        sums[id],
                        expected.get(&shape),
                        done[id],
                        fires[id]
                    ));
                }
            }
        }
    }
    if wrong > 8 {
        mismatches.push(format!("... {wrong} problems in all"));
    }
    if sums.first() != Some(&totals.root_sum) {
        mismatches.push(format!(
            "root sum {:?}, CPU {}",
            sums.first(),
            totals.root_sum
        ));
    }
    let summary = format!(
        "tree of depth {} (fan-out up to {}): {} nodes, {} joins, root sum {} (CPU {})\n",
        totals.depth,
        params.fan,
        totals.nodes,
        totals.inner,
        sums.first().copied().unwrap_or_default(),
        totals.root_sum
    );
    (mismatches, summary)
}
