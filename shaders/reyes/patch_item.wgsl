// The work item of Bound, SplitU, SplitV and DiceShadeSample: one (piece of
// a) bicubic Bezier patch. Mirrors `reyes::gpu::graph::PatchItem`; the
// scheduler checks that both layouts agree.
struct PatchItem {
    // The 16 world-space control points, point `v * 4 + u` at words
    // `3 * (v * 4 + u) .. + 3`. Flat f32 words rather than vec3 because a
    // vec3 array would pad every point to 16 bytes.
    p: array<f32, 48>,
    // The piece's rectangle (u0, v0, u1, v1) in the input patch's parameters.
    uv: vec4<f32>,
    // Index into `objects` (albedo).
    object: u32,
    // Splits from the input patch to this piece (the depth guard's input).
    split_depth: u32,
    // Index of the input patch, whose control points rate dicing evaluates.
    input_patch: u32,
    // The spacings of the piece's four edges (dicing.wgsl), 8 bits each.
    edges: u32,
    // The grid Bound or Split chose: nu | nv << 8.
    grid: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}
