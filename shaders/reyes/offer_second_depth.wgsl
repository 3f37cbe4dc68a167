
// The depth test of a frame of the midpoint depth filter (the z output
// with `Hider "hidden" "depthfilter" "midpoint"`; reyes::gpu::graph chooses
// this file or offer.wgsl by the frame's variant). Such a frame keeps no
// colour: the framebuffer is two 32-bit words per sample, the resolve's
// view of a key (x = low word, y = high word), here x = the bits of the
// second-nearest depth, y = the bits of the nearest. 32-bit atomic minima
// return the old value (64-bit ones need not): the depth that loses to the
// nearest (the old one or this one) is offered to the second word, so
// whatever the order of the offers it ends with the least depth greater
// than the nearest. An offer equal to the nearest is not passed on, so a
// batch run again changes nothing
// (reyes::reference::framebuffer::Framebuffer::offer).
fn offer(x: u32, y: u32, s: u32, depth: f32, color: u32) {
    let index = (y * frame.width + x) * frame.spp + s;
    let bits = bitcast<u32>(key_depth(depth));
    let old = atomicMin(&framebuffer[2u * index + 1u], bits);
    if (old != bits) {
        atomicMin(&framebuffer[2u * index], max(old, bits));
    }
}
