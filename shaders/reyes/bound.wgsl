// Body of `Bound` (16 threads per input patch, one per control point).
// The item names the input patch; its control points come from the patch
// store, placed in world space (load_patch, dicing.wgsl), and Bound routes
// it on as a PatchItem of the whole parameter square at split depth 0.
// Each thread projects its control point and publishes its outcode (of the
// ball the object's displacement bound, motion and lens blur grow it to), its pixel position and
// the bound's growth on screen in scratch; after the barrier thread 0
// reduces them in the reference's order (reyes::reference::bound::bound),
// measures the patch's edges and its grid (rate dicing: dicing.wgsl) and
// routes the patch. A one-sided, still, sharp and undisplaced patch whose
// every control point's share of the back-face test holds is culled
// (reyes::reference::bound::back_facing).
// Scratch: 5 words per point (outcode, px, py, growth in pixels, 1 when
// the point's share of the back-face test holds).
let POINT_SCRATCH = 5u;
let object = objects[item.object];
let may_cull_back = object.front != 0.0 && object.moving == 0u && frame.aperture == 0.0 && object.displace_kind == DISPLACE_NONE;
if (valid) {
    var p = load_patch(item.input_patch, object);
    let bound = object.displace_bound;
    let radius = clip_radius(bound);
    let point = patch_point(&p, thread);
    let clip = to_clip(point);
    let pixel = to_pixel(clip);
    let w = POINT_SCRATCH * thread;
    scratch_store_u32(slot, w, window_outcode(clip, cull_clip_radius(object, point, clip, radius)));
    scratch_store_f32(slot, w + 1u, pixel.x);
    scratch_store_f32(slot, w + 2u, pixel.y);
    scratch_store_f32(slot, w + 3u, pixel_growth(clip, bound, radius));
    var back = false;
    if (may_cull_back) {
        back = back_facing_at(&p, thread, object.front);
    }
    scratch_store_u32(slot, w + 4u, select(0u, 1u, back));
}
workgroupBarrier();
if (valid && thread == 0u) {
    atomicAdd(&stats[STAT_INPUT_PATCHES], 1u);
    var p = load_patch(item.input_patch, object);
    var flags = FLAGS_IDENTITY;
    var screen: ScreenPiece;
    var growth = 0.0;
    var back = may_cull_back;
    for (var i = 0u; i < 16u; i += 1u) {
        back = back && scratch_load_u32(slot, POINT_SCRATCH * i + 4u) != 0u;
        let code = scratch_load_u32(slot, POINT_SCRATCH * i);
        flags = merge_flags(flags, code);
        if ((code & UNPROJECTABLE) == 0u) {
            screen.projectable |= 1u << i;
        }
        screen.pixels[i] = vec2<f32>(scratch_load_f32(slot, POINT_SCRATCH * i + 1u), scratch_load_f32(slot, POINT_SCRATCH * i + 2u));
        screen.growths[i] = scratch_load_f32(slot, POINT_SCRATCH * i + 3u);
        growth = max(growth, screen.growths[i]);
    }
    var pixels = screen.pixels;
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
    var piece: PatchItem;
    piece.p = p;
    piece.uv = vec4<f32>(0.0, 0.0, 1.0, 1.0);
    piece.object = item.object;
    piece.split_depth = 0u;
    piece.input_patch = item.input_patch;
    piece.edges = EDGES_UNFIXED;
    if (frame.dicing == DICING_RATE) {
        piece.edges = input_edges(&screen, object.micropolygon_side);
    }
    let grid = piece_grid(&screen, piece.edges, piece.uv, object.micropolygon_side);
    piece.grid = grid.x | (grid.y << 8u);
    if (back) {
        route(DECIDE_CULL, piece);
    } else {
        route(decide(flags, size, growth, u2, v2, u3, v3, 0u, grid, object.dice_threshold), piece);
    }
}
