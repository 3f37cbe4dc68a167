// ---- benches: body of the `Spawn` procedure (shaders/benches/spawn_tree_body.wgsl) ----
// Heap-numbered binary tree: item i does its work, writes out[i] and spawns
// 2i+1 and 2i+2 when they are below BENCH_ITEMS, so the ids 0..BENCH_ITEMS-1
// each run exactly once starting from the single root 0.
if (valid) {
    out[item.id] = bench_work(item.id);
    let left = 2u * item.id + 1u;
    if (left < BENCH_ITEMS) {
        enqueue_Spawn(SpawnItem(left, item.depth + 1u, item.id, 0u, 0u, 0u, 0u, 0u));
    }
    if (left + 1u < BENCH_ITEMS) {
        enqueue_Spawn(SpawnItem(left + 1u, item.depth + 1u, item.id, 0u, 0u, 0u, 0u, 0u));
    }
}
