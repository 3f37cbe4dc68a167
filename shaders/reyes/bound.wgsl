// Body of `Bound` (16 threads per input patch, one per control point).
// Each thread projects its control point and publishes its outcode (of the
// ball the object's displacement bound, motion and lens blur grow it to), its pixel position and
// the bound's growth on screen in scratch; after the barrier thread 0
// reduces them in the reference's order (reyes::reference::bound::bound)
// and routes the patch.
// Scratch: 4 words per point (outcode, px, py, growth in pixels).
if (valid) {
    var p = item.p;
    let object = objects[item.object];
    let bound = object.displace_bound;
    let radius = clip_radius(bound);
    let point = patch_point(&p, thread);
    let clip = to_clip(point);
    let pixel = to_pixel(clip);
    let w = 4u * thread;
    scratch_store_u32(slot, w, outcode(clip, cull_clip_radius(object, point, clip, radius)));
    scratch_store_f32(slot, w + 1u, pixel.x);
    scratch_store_f32(slot, w + 2u, pixel.y);
    scratch_store_f32(slot, w + 3u, pixel_growth(clip, bound, radius));
}
workgroupBarrier();
if (valid && thread == 0u) {
    atomicAdd(&stats[STAT_INPUT_PATCHES], 1u);
    var p = item.p;
    var flags = FLAGS_IDENTITY;
    var pixels: array<vec2<f32>, 16>;
    var growth = 0.0;
    for (var i = 0u; i < 16u; i += 1u) {
        flags = merge_flags(flags, scratch_load_u32(slot, 4u * i));
        pixels[i] = vec2<f32>(scratch_load_f32(slot, 4u * i + 1u), scratch_load_f32(slot, 4u * i + 2u));
        growth = max(growth, scratch_load_f32(slot, 4u * i + 3u));
    }
    var lo = pixels[0];
    var hi = pixels[0];
    var u2 = 0.0;
    var v2 = 0.0;
    var u3 = 0.0;
    var v3 = 0.0;
    for (var i = 0u; i < 16u; i += 1u) {
        lo = min(lo, pixels[i]);
        hi = max(hi, pixels[i]);
    }
    // Extents: u sums the rows' end-to-end distances, v the columns'.
    for (var k = 0u; k < 4u; k += 1u) {
        u2 += dist2(pixels[k * 4u], pixels[k * 4u + 3u]);
        v2 += dist2(pixels[k], pixels[12u + k]);
        u3 += dist3(patch_point(&p, k * 4u), patch_point(&p, k * 4u + 3u));
        v3 += dist3(patch_point(&p, k), patch_point(&p, 12u + k));
    }
    let size = max_ignoring_nan(hi.x - lo.x, hi.y - lo.y);
    route(decide(flags, size, growth, u2, v2, u3, v3, item.split_depth), item);
}
