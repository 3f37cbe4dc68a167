//! The two-procedure graph, `Visit` and `Expand`, and the queue capacities
//! it runs with.

use scheduler::{Atomic, Capacities, Graph, Procedure, ProcedureId, Resource};

use super::{COUNTER_WORDS, EXPAND_THREADS, Hop, Problem};

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
    /// The graph, ready to compile.
    pub graph: Graph,
    /// The handle of `Visit`.
    pub visit: ProcedureId<Hop>,
    /// The handle of `Expand`.
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
