// Body of `SplitU` and `SplitV` (4 threads per piece, one per row for SplitU,
// one per column for SplitV). reyes::gpu::graph prepends
// `let along_u = true;` (SplitU) or `false` (SplitV).
// De Casteljau at the middle along u or v, then the bound test of both
// halves in this procedure. Every thread splits the whole piece (4 cubic
// splits: cheaper than sharing 96 words through scratch); thread t projects
// line t of each half (with the screen growth of the object's displacement
// bound, and outcodes grown also by its motion and lens blur) and computes
// the u/v extent terms of row t and column t. Thread h (0 or 1) reduces half h in the reference's order and
// routes it.
// Scratch: words 0..4, per thread, the merged outcodes of its line in half 0
// (low 16 bits) and half 1 (high 16 bits); from word 4, 7 words per (half h,
// thread t) at 4 + 7 * (h * 4 + t): bbox lo.x, lo.y, hi.x, hi.y, growth
// (pixels), u term, v term. Thread h also projects all 16 points of half
// h to measure its edges and its grid (rate dicing: dicing.wgsl).
var halves: array<array<f32, 48>, 2>;
let object = objects[item.object];
let bound = object.displace_bound;
let radius = clip_radius(bound);
if (valid) {
    var p = item.p;
    var lo_half: array<f32, 48>;
    var hi_half: array<f32, 48>;
    split_patch(&p, along_u, &lo_half, &hi_half);
    halves[0] = lo_half;
    halves[1] = hi_half;
    var packed = 0u;
    for (var h = 0u; h < 2u; h += 1u) {
        var q = halves[h];
        var flags = FLAGS_IDENTITY;
        var lo = vec2<f32>(0.0);
        var hi = vec2<f32>(0.0);
        // From 0, as the reference folds it.
        var growth = 0.0;
        for (var k = 0u; k < 4u; k += 1u) {
            let point = patch_point(&q, line_index(along_u, thread, k));
            let clip = to_clip(point);
            flags = merge_flags(flags, window_outcode(clip, cull_clip_radius(object, point, clip, radius)));
            growth = max(growth, pixel_growth(clip, bound, radius));
            let pixel = to_pixel(clip).xy;
            if (k == 0u) {
                lo = pixel;
                hi = pixel;
            } else {
                lo = min(lo, pixel);
                hi = max(hi, pixel);
            }
        }
        packed |= flags << (16u * h);
        let w = 4u + 7u * (h * 4u + thread);
        scratch_store_f32(slot, w, lo.x);
        scratch_store_f32(slot, w + 1u, lo.y);
        scratch_store_f32(slot, w + 2u, hi.x);
        scratch_store_f32(slot, w + 3u, hi.y);
        scratch_store_f32(slot, w + 4u, growth);
    }
    scratch_store_u32(slot, thread, packed);
}
workgroupBarrier();
// Each half's merged outcodes; thread h keeps half h's for the reduction.
var merged = array<u32, 2>(FLAGS_IDENTITY, FLAGS_IDENTITY);
if (valid) {
    // Each half's extents are measured in pixels, or in world space when the
    // half cannot be projected; every thread now knows which.
    for (var h = 0u; h < 2u; h += 1u) {
        var flags = FLAGS_IDENTITY;
        for (var t = 0u; t < 4u; t += 1u) {
            flags = merge_flags(flags, (scratch_load_u32(slot, t) >> (16u * h)) & 0xffffu);
        }
        merged[h] = flags;
        var q = halves[h];
        let r0 = patch_point(&q, thread * 4u);
        let r3 = patch_point(&q, thread * 4u + 3u);
        let c0 = patch_point(&q, thread);
        let c3 = patch_point(&q, 12u + thread);
        var u_term = 0.0;
        var v_term = 0.0;
        if ((flags & UNPROJECTABLE) != 0u) {
            u_term = dist3(r0, r3);
            v_term = dist3(c0, c3);
        } else {
            u_term = dist2(to_pixel2(r0), to_pixel2(r3));
            v_term = dist2(to_pixel2(c0), to_pixel2(c3));
        }
        let w = 4u + 7u * (h * 4u + thread);
        scratch_store_f32(slot, w + 5u, u_term);
        scratch_store_f32(slot, w + 6u, v_term);
    }
}
workgroupBarrier();
if (valid && thread < 2u) {
    let h = thread;
    let flags = merged[h];
    var lo = vec2<f32>(0.0);
    var hi = vec2<f32>(0.0);
    var growth = 0.0;
    var u_ext = 0.0;
    var v_ext = 0.0;
    for (var t = 0u; t < 4u; t += 1u) {
        let w = 4u + 7u * (h * 4u + t);
        let t_lo = vec2<f32>(scratch_load_f32(slot, w), scratch_load_f32(slot, w + 1u));
        let t_hi = vec2<f32>(scratch_load_f32(slot, w + 2u), scratch_load_f32(slot, w + 3u));
        if (t == 0u) {
            lo = t_lo;
            hi = t_hi;
        } else {
            lo = min(lo, t_lo);
            hi = max(hi, t_hi);
        }
        growth = max(growth, scratch_load_f32(slot, w + 4u));
        // Summed in row/column order 0..3, as the reference does.
        u_ext += scratch_load_f32(slot, w + 5u);
        v_ext += scratch_load_f32(slot, w + 6u);
    }
    let size = max_ignoring_nan(hi.x - lo.x, hi.y - lo.y);
    let depth = item.split_depth + 1u;
    var q = halves[h];
    var screen: ScreenPiece;
    for (var k = 0u; k < 16u; k += 1u) {
        let clip = to_clip(patch_point(&q, k));
        screen.pixels[k] = to_pixel(clip).xy;
        if (!(clip.w <= NEAR_EPS || clip.z < 0.0)) {
            screen.projectable |= 1u << k;
            screen.growths[k] = pixel_growth(clip, bound, radius);
        }
    }
    var piece = item;
    piece.p = q;
    piece.uv = split_uv(item.uv, along_u, h);
    piece.split_depth = depth;
    if (frame.dicing == DICING_RATE) {
        piece.edges = split_edges(item.edges, along_u, h, &screen, piece.uv, object.micropolygon_side);
    }
    let grid = piece_grid(&screen, piece.edges, piece.uv, object.micropolygon_side);
    piece.grid = grid.x | (grid.y << 8u);
    route(decide(flags, size, growth, u_ext, v_ext, u_ext, v_ext, depth, grid, object.dice_threshold), piece);
}
