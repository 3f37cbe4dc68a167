
// The depth test of a frame's samples (reyes::gpu::graph chooses this file
// or offer_second_depth.wgsl by the frame's variant).

// Keeps the minimum (depth bits << 32 | colour) per sample.
fn offer(x: u32, y: u32, s: u32, depth: f32, color: u32) {
    let index = (y * frame.width + x) * frame.spp + s;
    let key = (u64(bitcast<u32>(key_depth(depth))) << 32u) | u64(color);
    atomicMin(&framebuffer[index], key);
}
