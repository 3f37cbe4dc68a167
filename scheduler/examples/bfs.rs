//! Breadth-first search levels as a scheduler workload with two procedures:
//!
//! * `Visit` (one thread per item) claims a node for a level with `atomicMin`
//!   and, if that improved the node's level, enqueues one `Expand`;
//! * `Expand` (four threads per item, splitting the adjacency list) enqueues a
//!   `Visit` for every neighbour whose level would improve.
//!
//! Nothing orders the levels, so a node can be visited first at a level that
//! is too high and improved later; the final levels are still the exact BFS
//! distances (argued at [`expand_body`]) and are compared with a CPU BFS
//! element for element. The scheduler's own counters are checked against
//! counters the bodies keep: every improving visit enqueues exactly one
//! `Expand`, and `Visit` receives exactly the enqueues `Expand` made.
//!
//! Run with `cargo run --release -p scheduler --example bfs [seed] [nodes]`.

use std::collections::VecDeque;
use std::error::Error;
use std::fmt::Write as _;

use rand::{Rng, SeedableRng, rngs::StdRng};
use scheduler::{
    Atomic, Capacities, CompileOptions, Executor, ExecutorConfig, Gpu, Graph, Procedure,
    ProcedureId, Resource, RunReport, Seeds,
};

/// Level of a node no source reaches.
pub const UNREACHED: u32 = u32::MAX;
/// Threads that share one node's adjacency list in `Expand`.
pub const EXPAND_THREADS: u32 = 4;
/// Counter words the bodies keep (see [`Counters`]).
const COUNTER_WORDS: usize = 3;

/// A node with the level it is reached at; the item of both procedures.
#[scheduler::item]
#[derive(Debug)]
pub struct Hop {
    pub node: u32,
    pub level: u32,
}

/// An undirected graph in compressed sparse row form.
#[derive(Clone, Debug)]
pub struct Csr {
    /// `adjacency[row_start[v]..row_start[v + 1]]` are the neighbours of v.
    pub row_start: Vec<u32>,
    pub adjacency: Vec<u32>,
}

impl Csr {
    /// A random multigraph on `nodes` nodes with `nodes * degree / 2`
    /// undirected edges between uniformly drawn distinct endpoints (average
    /// degree `degree`; duplicate edges are kept, they are harmless).
    pub fn random(seed: u64, nodes: u32, degree: u32) -> Self {
        assert!(nodes >= 2);
        let mut rng = StdRng::seed_from_u64(seed);
        let edges = nodes as usize * degree as usize / 2;
        let mut pairs = Vec::with_capacity(edges);
        while pairs.len() < edges {
            let (u, v) = (rng.random_range(0..nodes), rng.random_range(0..nodes));
            if u != v {
                pairs.push((u, v));
            }
        }
        let mut lists = vec![Vec::new(); nodes as usize];
        for &(u, v) in &pairs {
            lists[u as usize].push(v);
            lists[v as usize].push(u);
        }
        let mut row_start = Vec::with_capacity(nodes as usize + 1);
        let mut adjacency = Vec::with_capacity(2 * edges);
        row_start.push(0);
        for list in &lists {
            adjacency.extend_from_slice(list);
            row_start.push(adjacency.len() as u32);
        }
        Self {
            row_start,
            adjacency,
        }
    }

    pub fn nodes(&self) -> u32 {
        self.row_start.len() as u32 - 1
    }

    pub fn neighbours(&self, v: u32) -> &[u32] {
        &self.adjacency
            [self.row_start[v as usize] as usize..self.row_start[v as usize + 1] as usize]
    }

    pub fn max_degree(&self) -> u32 {
        (0..self.nodes())
            .map(|v| self.neighbours(v).len() as u32)
            .max()
            .unwrap_or(0)
    }
}

/// One BFS problem: a graph and its sources (level 0).
#[derive(Clone, Debug)]
pub struct Problem {
    pub graph: Csr,
    pub sources: Vec<u32>,
}

impl Problem {
    /// A random graph of average degree 4 with `sources` random sources.
    pub fn random(seed: u64, nodes: u32, sources: usize) -> Self {
        let graph = Csr::random(seed, nodes, 4);
        let mut rng = StdRng::seed_from_u64(seed ^ 0x5eed);
        let sources = (0..sources).map(|_| rng.random_range(0..nodes)).collect();
        Self { graph, sources }
    }
}

/// The CPU reference: multi-source BFS.
pub fn cpu_levels(problem: &Problem) -> Vec<u32> {
    let mut levels = vec![UNREACHED; problem.graph.nodes() as usize];
    let mut frontier = VecDeque::new();
    for &s in &problem.sources {
        if levels[s as usize] != 0 {
            levels[s as usize] = 0;
            frontier.push_back(s);
        }
    }
    while let Some(u) = frontier.pop_front() {
        let next = levels[u as usize] + 1;
        for &v in problem.graph.neighbours(u) {
            if levels[v as usize] == UNREACHED {
                levels[v as usize] = next;
                frontier.push_back(v);
            }
        }
    }
    levels
}

/// Counters the bodies keep, read back after the run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Visits whose `atomicMin` lowered the node's level (each enqueued an `Expand`).
    pub improving_visits: u32,
    /// `Visit`s that `Expand` enqueued.
    pub visit_enqueues: u32,
    /// `Expand`s that found their level already beaten and did nothing.
    pub stale_expands: u32,
}

const VISIT_BODY: &str = "
if (valid) {
    let old = atomicMin(&levels[item.node], item.level);
    if (item.level < old) {
        atomicAdd(&counters[0], 1u);
        enqueue_Expand(item);
    }
}
";

/// The body of `Expand`. Why the final levels are exact: levels only ever
/// hold lengths of real paths, so none drops below the BFS distance. By
/// induction on the distance d, some visit of u at d - 1 improved u (the
/// first such visit must, as nothing lower is possible) and enqueued
/// `Expand(u, d - 1)`; u's level stays d - 1 afterwards, so that `Expand` is
/// not stale and, for every neighbour v, either v already holds d or it
/// enqueues `Visit(v, d)`, which lowers v to d. A stale `Expand` may be
/// skipped because the visit that beat it enqueued an `Expand` of its own.
fn expand_body() -> String {
    format!(
        "
if (valid) {{
    if (atomicLoad(&levels[item.node]) == item.level) {{
        let next = item.level + 1u;
        let end = row_start[item.node + 1u];
        for (var e = row_start[item.node] + thread; e < end; e += {EXPAND_THREADS}u) {{
            let v = adjacency[e];
            if (next < atomicLoad(&levels[v])) {{
                atomicAdd(&counters[1], 1u);
                enqueue_Visit(Hop(v, next));
            }}
        }}
    }} else if (thread == 0u) {{
        atomicAdd(&counters[2], 1u);
    }}
}}
"
    )
}

/// The graph of [`graph`], with the handles of its procedures.
#[derive(Debug)]
pub struct BfsGraph {
    pub graph: Graph,
    pub visit: ProcedureId<Hop>,
    pub expand: ProcedureId<Hop>,
}

/// The two-procedure graph. `Expand`'s fan-out into `Visit` is the largest
/// degree: one item enqueues at most one visit per neighbour.
pub fn graph(problem: &Problem) -> BfsGraph {
    let mut graph = Graph::new("bfs levels");
    let nodes = u64::from(problem.graph.nodes());
    graph.resource(Resource::storage_read::<[u32]>("row_start").min_len(nodes + 1));
    graph.resource(Resource::storage_read::<[u32]>("adjacency"));
    graph.resource(Resource::storage::<[Atomic<u32>]>("levels").min_len(nodes));
    graph.resource(Resource::storage::<[Atomic<u32>]>("counters").min_len(COUNTER_WORDS as u64));
    let visit = graph.procedure(Procedure::of::<Hop>("Visit").initial(true).body(VISIT_BODY));
    let expand = graph.procedure(
        Procedure::of::<Hop>("Expand")
            .threads_per_item(EXPAND_THREADS)
            .body(expand_body()),
    );
    graph.connect(&visit, &expand);
    graph.connect_with_fan_out(&expand, &visit, problem.graph.max_degree().max(1));
    BfsGraph {
        graph,
        visit,
        expand,
    }
}

/// Generous queue capacities. No small bound holds in the worst case (a node
/// is expanded once per improvement of its level, and each expansion enqueues
/// up to its degree in visits), but re-visits are rare: about one node in ten
/// improves twice. Twice the items a perfect BFS would enqueue leaves ample
/// room, and an overflow would be reported as an error, never ignored.
pub fn capacities(problem: &Problem) -> Capacities {
    let edges = problem.graph.adjacency.len() as u32;
    let nodes = problem.graph.nodes();
    Capacities::uniform(1 << 16)
        .with(
            "Visit",
            (2 * (edges + problem.sources.len() as u32)).max(1 << 16),
        )
        .with("Expand", (2 * nodes).max(1 << 16))
}

/// A checked run: the report and every disagreement with the CPU (none when
/// the run is correct).
#[derive(Debug)]
pub struct Checked {
    pub report: RunReport,
    pub mismatches: Vec<String>,
    /// A human-readable summary of the result.
    pub summary: String,
}

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

fn main() -> Result<(), Box<dyn Error>> {
    let arg = |i: usize, default: u64| -> Result<u64, Box<dyn Error>> {
        Ok(std::env::args()
            .nth(i)
            .map(|s| s.parse())
            .transpose()?
            .unwrap_or(default))
    };
    let seed = arg(1, 7)?;
    let nodes = u32::try_from(arg(2, 20_000)?)?;
    let gpu = Gpu::new(&Default::default())?;
    println!("device: {}", gpu.describe());
    let problem = Problem::random(seed, nodes, 3);
    let config = ExecutorConfig {
        capacities: capacities(&problem),
        ..Default::default()
    };
    let checked = run(&gpu, &problem, &config)?;
    println!("{}", checked.report);
    print!("{}", checked.summary);
    if checked.mismatches.is_empty() {
        println!("OK");
        Ok(())
    } else {
        for m in &checked.mismatches {
            eprintln!("MISMATCH: {m}");
        }
        std::process::exit(1);
    }
}
