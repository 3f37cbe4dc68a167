// ---- benches: flat dispatch (shaders/benches/flat.wgsl) ----
// One thread per item id, no scheduling at all: the floor the megakernel is
// compared against. Needs hash.wgsl and the spliced constants in front.

@group(0) @binding(0) var<storage, read_write> out: array<u32>;

@compute @workgroup_size(256)
fn flat_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let id = gid.x;
    if (id < BENCH_ITEMS) {
        out[id] = bench_work(id);
    }
}
