//! Small graphs shared by the scheduler's tests.

use scheduler::{Graph, ItemType, Procedure, Resource, item_type};

/// A two-word tree node.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Node {
    /// Depth in the tree.
    pub depth: u32,
    /// Node id.
    pub id: u32,
}

/// The WGSL twin of [`Node`].
pub fn node_type() -> ItemType {
    item_type!(Node, "struct Node { depth: u32, id: u32 }", [depth, id])
}

/// A complete binary tree of the given depth: `2^(depth + 1) - 1` items.
pub fn binary_tree(depth: u32) -> Graph {
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
pub fn hashing_tree(depth: u32) -> Graph {
    let mut graph = tree_graph(
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
    graph.resource(Resource::storage("out", "array<u32>"));
    graph
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
fn tree_graph(name: &str, body: String) -> Graph {
    let mut graph = Graph::new(name);
    graph.procedure(Procedure::new("Grow", node_type()).initial(true).body(body));
    graph.connect_with_fan_out("Grow", "Grow", 2);
    graph
}

/// Four threads per item cooperate through workgroup scratch with a barrier:
/// each thread stores `id * 4 + thread + 1`, then thread 0 sums the four
/// values into `out[id]`. Every thread reaches the barrier, with or without
/// an item.
pub fn scratch_sum() -> Graph {
    let mut graph = Graph::new("scratch sum");
    graph.resource(Resource::storage("out", "array<u32>"));
    graph.procedure(
        Procedure::new("Sum", node_type())
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
    graph
}

/// A cycle between two procedures with different thread counts and
/// priorities: Ping (1 thread) -> Pong (8 threads) -> Ping, until depth runs
/// out. Ping spawns `1 + id % 3` Pongs; Pong spawns one Ping.
pub fn ping_pong(max_depth: u32) -> Graph {
    let mut graph = Graph::new("ping pong");
    graph.library(&format!(
        "const MAX_DEPTH: u32 = {max_depth}u;
fn children_of(id: u32) -> u32 {{
    return 1u + id % 3u;
}}"
    ));
    graph.procedure(
        Procedure::new("Ping", node_type())
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
    graph.procedure(
        Procedure::new("Pong", node_type())
            .threads_per_item(8)
            .priority(2)
            .body(
                "if (valid && thread == 0u && item.depth < MAX_DEPTH) {
    enqueue_Ping(Node(item.depth + 1u, item.id + 7u));
}",
            ),
    );
    graph.connect_with_fan_out("Ping", "Pong", 3);
    graph.connect("Pong", "Ping");
    graph
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
