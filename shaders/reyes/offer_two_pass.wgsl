// The depth test of a device without 64-bit atomics (reyes::gpu::graph
// chooses this file, offer.wgsl or offer_second_depth.wgsl by the frame's
// variant). It keeps the key of offer.wgsl, (depth bits << 32) | colour, as
// two 32-bit words per sample (x = low word = colour, y = high word =
// depth: the resolve's view of a key), over two runs of the megakernel:
// - DEPTH_PASS keeps the nearest depth in the high word;
// - COLOUR_PASS keeps, in the low word, the least colour among the offers
//   at exactly that depth.
// Both runs compute the same depths (the same code on the same inputs), so
// the framebuffer ends as one 64-bit atomicMin of the keys leaves it,
// whatever the order of the offers. A batch run again changes nothing.
fn offer(x: u32, y: u32, s: u32, depth: f32, color: u32) {
    let index = (y * frame.width + x) * frame.spp + s;
    let bits = bitcast<u32>(key_depth(depth));
    if (depth_test_pass == DEPTH_PASS) {
        atomicMin(&framebuffer[2u * index + 1u], bits);
    } else if (atomicLoad(&framebuffer[2u * index + 1u]) == bits) {
        atomicMin(&framebuffer[2u * index], color);
    }
}
