// ---- benches: per-item work (shaders/benches/hash.wgsl) ----
// Shared by the flat kernel and the megakernel library. The including code
// splices `const BENCH_WORK: u32` (hash iterations per item) and
// `const BENCH_ITEMS: u32` (items in the workload) in front of this file.
// The Rust reference in benches/src/workload.rs must stay bit-identical.

// One round of a 32-bit integer hash ("lowbias32", Chris Wellons).
fn bench_hash(v: u32) -> u32 {
    var x = v;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

// The per-item work: BENCH_WORK dependent hash rounds starting from the id.
fn bench_work(id: u32) -> u32 {
    var h = id;
    for (var i = 0u; i < BENCH_WORK; i += 1u) {
        h = bench_hash(h);
    }
    return h;
}
