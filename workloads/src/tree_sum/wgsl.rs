//! The WGSL of the tree sum: the shape functions (mirroring the Rust ones
//! in the parent module) and the two bodies.

/// The shape of the tree, as [`super::children`], [`super::child_key`],
/// [`super::child_level`] and [`super::value`] compute it.
pub(crate) const LIBRARY: &str = "
fn tree_hash(value: u32) -> u32 {
    var x = value;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

fn tree_children(key: u32, depth: u32, level: u32) -> u32 {
    if (depth >= params[0]) {
        return 0u;
    }
    let h = tree_hash(key);
    if (level == 0u) {
        return 1u + h % params[1];
    }
    if (level >= params[2]) {
        return 0u;
    }
    return h % (params[1] + 1u);
}

fn tree_child_key(key: u32, i: u32) -> u32 {
    return tree_hash(key * 31u + i + 1u);
}

fn tree_child_level(level: u32, i: u32) -> u32 {
    if (level == 0u && i == 0u) {
        return 0u;
    }
    return level + 1u;
}

fn tree_value(key: u32) -> u32 {
    return tree_hash(key ^ 0x5bd1e995u) % 1000u;
}
";

/// `Split`: record the node, and either sum a leaf or give the children ids
/// and open the join that sums them. `counters[0]` hands out ids (the root
/// is 0), `counters[2]` counts ids beyond the resources.
pub const SPLIT_BODY: &str = "if (valid) {
    let at = NODE_WORDS * item.id;
    atomicStore(&nodes[at + NODE_KEY], item.key);
    let depth = item.shape & 0xffu;
    let level = item.shape >> 8u;
    atomicStore(&nodes[at + NODE_SHAPE], item.shape);
    let n = tree_children(item.key, depth, level);
    if (n == 0u) {
        atomicStore(&nodes[at + NODE_SUM], tree_value(item.key));
        atomicStore(&nodes[at + NODE_DONE], 1u);
    } else {
        let first = atomicAdd(&counters[0], n) + 1u;
        if (first + n > arrayLength(&fires)) {
            atomicAdd(&counters[2], 1u);
        } else {
            // The children are enqueued even if the pool had no record left:
            // the run then still asks for every join, so the pool overflow it
            // reports carries the whole need.
            _ = join_open_Refit(Refit(item.id, item.key, first, n));
            for (var i = 0u; i < n; i += 1u) {
                enqueue_Split(Node(first + i, tree_child_key(item.key, i), (depth + 1u) | (tree_child_level(level, i) << 8u)));
            }
        }
    }
}";

/// `Refit`: every child has finished; sum them. `nodes` holds relaxed
/// atomics: they are coherent between workgroups on every device, and the
/// join orders them (docs/scheduler.md, "Joins"). `counters[1]` counts children
/// found unfinished, `fires` the continuations per node.
pub(crate) const REFIT_BODY: &str = "if (valid) {
    var total = tree_value(item.key);
    for (var i = 0u; i < item.count; i += 1u) {
        let child = NODE_WORDS * (item.first + i);
        if (atomicLoad(&nodes[child + NODE_DONE]) != 1u) {
            atomicAdd(&counters[1], 1u);
        }
        total += atomicLoad(&nodes[child + NODE_SUM]);
    }
    let at = NODE_WORDS * item.id;
    atomicStore(&nodes[at + NODE_SUM], total);
    atomicAdd(&fires[item.id], 1u);
    atomicStore(&nodes[at + NODE_DONE], 1u);
}";
