//! Small graphs shared by the scheduler's tests, each with the handles of its
//! procedures.

use std::ops::Deref;

use scheduler::{Graph, ItemType, Procedure, ProcedureId, Resource};

/// A two-word tree node. It derives `Pod` itself, so it derives `Item` alone
/// (the examples use `#[scheduler::item]`, which derives both).
#[repr(C)]
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable, scheduler::Item,
)]
pub struct Node {
    /// Depth in the tree.
    pub depth: u32,
    /// Node id.
    pub id: u32,
}

/// The item type of [`Node`], for procedures built with an explicit
/// `ItemType`.
pub fn node_type() -> ItemType {
    ItemType::of::<Node>()
}

/// A graph with the handles of its procedures; it dereferences to the graph.
#[derive(Clone, Debug)]
pub struct WithIds<I> {
    /// The graph.
    pub graph: Graph,
    /// Its procedures' handles.
    pub ids: I,
}

impl<I> Deref for WithIds<I> {
    type Target = Graph;

    fn deref(&self) -> &Graph {
        &self.graph
    }
}

/// The one procedure `Grow` of a tree graph.
pub type Tree = WithIds<ProcedureId<Node>>;

/// A complete binary tree of the given depth: `2^(depth + 1) - 1` items.
pub fn binary_tree(depth: u32) -> Tree {
    tree_graph("binary tree", grow_body(depth))
}

/// Rounds of the hash that [`hashing_tree`] runs per item.
pub const HASH_ROUNDS: u32 = 150;

/// The integer hash of [`hashing_tree`], on the CPU.
pub fn hash_rounds(id: u32) -> u32 {
    (0..HASH_ROUNDS).fold(id, |h, _| (h ^ (h >> 16)).wrapping_mul(0x045d_9f3b))
}

/// [`binary_tree`] whose items each also run a loop of [`HASH_ROUNDS`]
/// iterations and store the result in the resource `out[id]`.
pub fn hashing_tree(depth: u32) -> Tree {
    let mut tree = tree_graph(
        "hashing tree",
        format!(
            "if (valid) {{
    var h = item.id;
    for (var i = 0u; i < {HASH_ROUNDS}u; i += 1u) {{
        h = (h ^ (h >> 16u)) * 0x045d9f3bu;
    }}
    out[item.id] = h;
}}
{}",
            grow_body(depth)
        ),
    );
    tree.graph.resource(Resource::storage::<[u32]>("out"));
    tree
}

/// The body that gives each node above `depth` its two children.
fn grow_body(depth: u32) -> String {
    format!(
        "if (valid && item.depth < {depth}u) {{
    enqueue_Grow(Node(item.depth + 1u, item.id * 2u));
    enqueue_Grow(Node(item.depth + 1u, item.id * 2u + 1u));
}}"
    )
}

/// One initial procedure `Grow` with `body`, enqueueing into itself (two
/// children per item).
fn tree_graph(name: &str, body: String) -> Tree {
    let mut graph = Graph::new(name);
    let grow = graph.procedure(Procedure::of::<Node>("Grow").initial(true).body(body));
    graph.connect_with_fan_out(&grow, &grow, 2);
    WithIds { graph, ids: grow }
}

/// Four threads per item cooperate through workgroup scratch with a barrier:
/// each thread stores `id * 4 + thread + 1`, then thread 0 sums the four
/// values into `out[id]`. Every thread reaches the barrier, with or without
/// an item.
pub fn scratch_sum() -> WithIds<ProcedureId<Node>> {
    let mut graph = Graph::new("scratch sum");
    graph.resource(Resource::storage::<[u32]>("out"));
    let sum = graph.procedure(
        Procedure::of::<Node>("Sum")
            .initial(true)
            .threads_per_item(16)
            .scratch_bytes(64)
            .body(
                "if (valid) {
    scratch_store_u32(slot, thread, item.id * 16u + thread + 1u);
}
workgroupBarrier();
// The last thread sums, so that the words it reads were written by other
// groups of SIMD lanes too (llvmpipe runs 8 lanes at a time).
if (valid && thread == 15u) {
    var total = 0u;
    for (var t = 0u; t < 16u; t += 1u) {
        total += scratch_load_u32(slot, t);
    }
    out[item.id] = total;
}",
            ),
    );
    WithIds { graph, ids: sum }
}

/// The procedures of [`ping_pong`].
#[derive(Clone, Debug)]
pub struct PingPongIds {
    /// The initial procedure, one thread per item.
    pub ping: ProcedureId<Node>,
    /// Eight threads per item.
    pub pong: ProcedureId<Node>,
}

/// A cycle between two procedures with different thread counts and
/// priorities: Ping (1 thread) -> Pong (8 threads) -> Ping, until depth runs
/// out. Ping spawns `1 + id % 3` Pongs; Pong spawns one Ping.
pub fn ping_pong(max_depth: u32) -> WithIds<PingPongIds> {
    let mut graph = Graph::new("ping pong");
    graph.constant("MAX_DEPTH", max_depth);
    graph.library(
        "fn children_of(id: u32) -> u32 {
    return 1u + id % 3u;
}",
    );
    let ping = graph.procedure(
        Procedure::of::<Node>("Ping")
            .initial(true)
            .priority(1)
            .body(
                "if (valid && item.depth < MAX_DEPTH) {
    for (var k = 0u; k < children_of(item.id); k += 1u) {
        enqueue_Pong(Node(item.depth + 1u, item.id * 3u + k));
    }
}",
            ),
    );
    let pong = graph.procedure(
        Procedure::of::<Node>("Pong")
            .threads_per_item(8)
            .priority(2)
            .body(
                "if (valid && thread == 0u && item.depth < MAX_DEPTH) {
    enqueue_Ping(Node(item.depth + 1u, item.id + 7u));
}",
            ),
    );
    graph.connect_with_fan_out(&ping, &pong, 3);
    graph.connect(&pong, &ping);
    WithIds {
        graph,
        ids: PingPongIds { ping, pong },
    }
}

/// CPU count of items executed per procedure of [`ping_pong`] from `seeds`.
pub fn ping_pong_counts(max_depth: u32, seeds: &[Node]) -> (u64, u64) {
    let (mut pings, mut pongs) = (0u64, 0u64);
    let mut stack: Vec<(bool, Node)> = seeds.iter().map(|&n| (true, n)).collect();
    while let Some((is_ping, node)) = stack.pop() {
        if is_ping {
            pings += 1;
            if node.depth < max_depth {
                for k in 0..1 + node.id % 3 {
                    stack.push((
                        false,
                        Node {
                            depth: node.depth + 1,
                            id: node.id.wrapping_mul(3).wrapping_add(k),
                        },
                    ));
                }
            }
        } else {
            pongs += 1;
            if node.depth < max_depth {
                stack.push((
                    true,
                    Node {
                        depth: node.depth + 1,
                        id: node.id.wrapping_add(7),
                    },
                ));
            }
        }
    }
    (pings, pongs)
}
