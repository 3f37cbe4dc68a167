// Body of `DiceShadeSample` (256 threads per piece). Thread t owns grid point
// (t % 16, t / 16) at s = i / 15, t = j / 15.
//
// Phase 1: the position and the exact shading normal of the undisplaced
// surface; a displaced object's point also moves along the exact normal
// by height(u, v) * scale. Both go to scratch.
// Phase 2: the shading normal (displaced objects: from the displaced
// neighbours, reyes::reference::displace, falling back to the exact one),
// shading and projection.
// With time and lens (frame.time_lens), phase 2 also positions the point
// at shutter close and gathers the grid's largest motion and circle of
// confusion for Adaptive sampling.
// Phase 3: threads 0..225 each rasterize micropolygon (t % 15, t / 15) as the
// two triangles (a, b, c) and (a, c, d) (raster5d.wgsl with time and lens),
// or its nearest sample.
// Scratch: words 0..768 the (displaced) positions (x, y, z per point), words
// 768..1536 the exact shading normals (x, y, z), which phase 2 replaces
// (each thread its own, after reading it) by the point's close (px, py,
// depth); from word POINT_BASE, 8 words per point (px, py, depth, clip w,
// r, g, b, clip w at close).
// llvmpipe turns every workgroupBarrier into a coroutine suspension, whose
// compile cost grows with the state that lives across it, so the phases
// hand their results over in scratch, and every object takes one path.
let NORMAL_BASE = 3u * GRID_POINTS * GRID_POINTS;
let POINT_BASE = 6u * GRID_POINTS * GRID_POINTS;
if (valid) {
    var p = item.p;
    let object = objects[item.object];
    let i = thread % GRID_POINTS;
    let j = thread / GRID_POINTS;
    let s = f32(i) / f32(GRID_QUADS);
    let t = f32(j) / f32(GRID_QUADS);
    let position = tensor(&p, bernstein(s), bernstein(t));
    var moved = position;
    if (object.displace_kind != DISPLACE_NONE) {
        let u = lerp_param(item.uv.x, item.uv.z, s);
        let v = lerp_param(item.uv.y, item.uv.w, t);
        let offset = displacement_height(object, u, v) * object.displace_scale;
        if (abs(offset) > object.displace_bound * DISPLACEMENT_BOUND_SLACK) {
            atomicAdd(&stats[STAT_DISPLACEMENT_BOUND_EXCEEDED], 1u);
        }
        moved = position + displacement_normal(&p, s, t) * offset;
    }
    store_vec3(slot, 3u * thread, moved);
    store_vec3(slot, NORMAL_BASE + 3u * thread, surface_normal(&p, s, t, position, frame.eye));
}
if (valid && thread == 0u) {
    atomicStore(&grid_extent[0], 0u);
    atomicStore(&grid_extent[1], 0u);
}
workgroupBarrier();
if (valid) {
    let object = objects[item.object];
    let i = thread % GRID_POINTS;
    let j = thread / GRID_POINTS;
    let moved = displaced_point(slot, i, j);
    var normal = vec3<f32>(0.0);
    if (object.displace_kind != DISPLACE_NONE) {
        normal = grid_normal(slot, i, j);
        if (dot3(normal, frame.eye - moved) < 0.0) {
            normal = -normal;
        }
    }
    if (all(normal == vec3<f32>(0.0))) {
        // Undisplaced, or degenerate (a collapsed patch edge): the exact normal.
        normal = load_vec3(slot, NORMAL_BASE + 3u * thread);
    }
    let w = POINT_BASE + 8u * thread;
    store_grid_point(slot, w, moved, shade(moved, normal, object.albedo.xyz));
    if (frame.time_lens != 0u) {
        var close_position = moved;
        if (object.moving != 0u) {
            close_position = motion_close(object, moved);
        }
        let clip = to_clip(close_position);
        let close = to_pixel(clip);
        // Own words only: no other thread reads this point's normal.
        store_vec3(slot, NORMAL_BASE + 3u * thread, close);
        scratch_store_f32(slot, w + 7u, clip.w);
        let open = vec2<f32>(scratch_load_f32(slot, w), scratch_load_f32(slot, w + 1u));
        let motion = dist2(open, close.xy);
        let blur = max(abs(coc(scratch_load_f32(slot, w + 3u))), abs(coc(clip.w)));
        // NaN extents (a point behind the eye) are ignored, as f32::max does.
        if (!is_nan_f32(motion)) {
            atomicMax(&grid_extent[0], bitcast<u32>(motion));
        }
        if (!is_nan_f32(blur)) {
            atomicMax(&grid_extent[1], bitcast<u32>(blur));
        }
    }
}
workgroupBarrier();
if (valid && thread < GRID_QUADS * GRID_QUADS) {
    let i = thread % GRID_QUADS;
    let j = thread / GRID_QUADS;
    // Corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1).
    let wa = POINT_BASE + 8u * (j * GRID_POINTS + i);
    let wb = wa + 8u;
    let wd = wa + 8u * GRID_POINTS;
    let wc = wd + 8u;
    let a = vec4<f32>(scratch_load_f32(slot, wa), scratch_load_f32(slot, wa + 1u), scratch_load_f32(slot, wa + 2u), scratch_load_f32(slot, wa + 3u));
    let b = vec4<f32>(scratch_load_f32(slot, wb), scratch_load_f32(slot, wb + 1u), scratch_load_f32(slot, wb + 2u), scratch_load_f32(slot, wb + 3u));
    let c = vec4<f32>(scratch_load_f32(slot, wc), scratch_load_f32(slot, wc + 1u), scratch_load_f32(slot, wc + 2u), scratch_load_f32(slot, wc + 3u));
    let d = vec4<f32>(scratch_load_f32(slot, wd), scratch_load_f32(slot, wd + 1u), scratch_load_f32(slot, wd + 2u), scratch_load_f32(slot, wd + 3u));
    let ca = vec3<f32>(scratch_load_f32(slot, wa + 4u), scratch_load_f32(slot, wa + 5u), scratch_load_f32(slot, wa + 6u));
    let cb = vec3<f32>(scratch_load_f32(slot, wb + 4u), scratch_load_f32(slot, wb + 5u), scratch_load_f32(slot, wb + 6u));
    let cc = vec3<f32>(scratch_load_f32(slot, wc + 4u), scratch_load_f32(slot, wc + 5u), scratch_load_f32(slot, wc + 6u));
    let cd = vec3<f32>(scratch_load_f32(slot, wd + 4u), scratch_load_f32(slot, wd + 5u), scratch_load_f32(slot, wd + 6u));

    // Largest micropolygon: positive floats order like their bits; NaN
    // sizes are ignored as f32::max does in the reference.
    let lo = min(min(a.xy, b.xy), min(c.xy, d.xy));
    let hi = max(max(a.xy, b.xy), max(c.xy, d.xy));
    let size = max_ignoring_nan(hi.x - lo.x, hi.y - lo.y);
    if (!is_nan_f32(size)) {
        atomicMax(&stats[STAT_LARGEST_MICROPOLYGON], bitcast<u32>(size));
    }

    let color = pack_rgb10((((ca + cb) + cc) + cd) * 0.25);
    var counts = SampleCounts(0u, 0u);
    if (frame.time_lens != 0u) {
        let mode = mode_for_grid(bitcast<f32>(atomicLoad(&grid_extent[0])), bitcast<f32>(atomicLoad(&grid_extent[1])));
        if (thread == 0u && mode == SAMPLING_INTERLEAVE) {
            atomicAdd(&stats[STAT_INTERLEAVE_GRIDS], 1u);
        }
        let na = NORMAL_BASE + 3u * (j * GRID_POINTS + i);
        let nb = na + 3u;
        let nd = na + 3u * GRID_POINTS;
        let nc = nd + 3u;
        let ma = moving_point(a.xyz, a.w, load_vec3(slot, na), scratch_load_f32(slot, wa + 7u));
        let mb = moving_point(b.xyz, b.w, load_vec3(slot, nb), scratch_load_f32(slot, wb + 7u));
        let mc = moving_point(c.xyz, c.w, load_vec3(slot, nc), scratch_load_f32(slot, wc + 7u));
        let md = moving_point(d.xyz, d.w, load_vec3(slot, nd), scratch_load_f32(slot, wd + 7u));
        raster_triangle_5d(mode, ma, mb, mc, color, &counts);
        raster_triangle_5d(mode, ma, mc, md, color, &counts);
    } else if (frame.sampling == SAMPLING_NEAREST) {
        raster_nearest(a, b, c, d, color, &counts);
    } else {
        raster_triangle(a, b, c, color, &counts);
        raster_triangle(a, c, d, color, &counts);
    }
    stat_add64(STAT_SAMPLES_TESTED, counts.tested);
    stat_add64(STAT_SAMPLES_HIT, counts.hit);
}
if (valid && thread == 0u) {
    atomicAdd(&stats[STAT_GRIDS_DICED], 1u);
    stat_add64(STAT_MICROPOLYGONS, GRID_QUADS * GRID_QUADS);
}
