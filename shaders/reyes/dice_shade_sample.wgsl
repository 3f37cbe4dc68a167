// Body of the DiceShadeSample procedures (16, 64 or 256 threads per piece:
// reyes::dicing::GridClass). reyes::gpu::graph prepends
// `let DICE_THREADS = ..u;`. The piece's grid is nu x nv micropolygons
// (PatchItem::grid), (nu + 1) x (nv + 1) points; point k = j * (nu + 1) + i
// is at u = u0 + (u1 - u0) (i / nu), v likewise (reyes::reference::dice).
//
// Phase 1 (every thread, for points thread, thread + DICE_THREADS, ...):
// the point of the input patch (patch_position), displaced along the
// exact normal; its shading normal (exact, or for a displaced object from
// its displaced neighbours, evaluated here too); with rate dicing, a
// border point between two vertices of its edge moves to the nearer one
// (a corner: onto their chord);
// then shading and projection, at open and (time and lens) at close,
// gathering the grid's largest motion and circle of confusion for
// Adaptive sampling, and counting the point if a stage turned its position
// non-finite (reyes::nonfinite).
// Phase 2: thread t < nu * nv rasterizes micropolygon (t % nu, t / nu) as
// one quad of the two triangles (a, b, c) and (a, c, d) (quad.wgsl;
// raster5d.wgsl with time and lens), each sample blending its triangle's
// corner colours (smooth shading) or taking the micropolygon's mean
// colour (constant shading, the grids picture).
// Scratch: POINT_WORDS (9) words per point: the clip position (x, y, z,
// w), the packed colour, and the clip position at close. Phase 2 projects
// them (a corner that crosses the near or far plane during the shutter is
// seen while it is in view: raster5d.wgsl moving_point).
// llvmpipe turns every workgroupBarrier into a coroutine suspension whose
// compile cost grows with the state that lives across it: the phases hand
// their results over in scratch only.
let nu = item.grid & 0xffu;
let nv = (item.grid >> 8u) & 0xffu;
let columns = nu + 1u;
let points = columns * (nv + 1u);
if (valid) {
    let object = objects[item.object];
    var q = load_patch(item.input_patch, object);
    for (var k = thread; k < points; k += DICE_THREADS) {
        let i = k % columns;
        let j = k / columns;
        let u = grid_param(item.uv.x, item.uv.z, i, nu);
        let v = grid_param(item.uv.y, item.uv.w, j, nv);
        // displaced_point, with the bound check.
        let patch_point = patch_position(&q, u, v);
        var moved = patch_point;
        var normal = vec3<f32>(0.0);
        // The undisplaced surface's normal, for a displaced object (the
        // shading context's Ng; zero: the shading normal).
        var geometric_normal = vec3<f32>(0.0);
        if (VARIANT_DISPLACED) {
            if (object.displace_kind != DISPLACE_NONE) {
                moved = displaced_point(&q, object, item.input_patch, u, v);
                if (length(moved - patch_point) > object.displace_bound * DISPLACEMENT_BOUND_SLACK) {
                    atomicAdd(&stats[STAT_DISPLACEMENT_BOUND_EXCEEDED], 1u);
                }
                normal = displaced_grid_normal(&q, object, item.input_patch, item.uv, nu, nv, i, j);
                geometric_normal = surface_normal(&q, u, v, patch_point);
                if (dot3(normal, towards_eye(moved)) < 0.0) {
                    normal = -normal;
                }
            }
        }
        if (all(normal == vec3<f32>(0.0))) {
            // Undisplaced, or degenerate (a collapsed patch edge): the exact normal.
            normal = surface_normal(&q, u, v, tensor(&q, bernstein(u), bernstein(v)));
        }
        if (frame.dicing == DICING_RATE) {
            let chord = border_chord(nu, nv, item.edges, i, j, u, v);
            if (chord.f >= 0.0) {
                moved = displaced_point(&q, object, item.input_patch, chord.a.x, chord.a.y);
                if (chord.f > 0.0) {
                    let qb = displaced_point(&q, object, item.input_patch, chord.b.x, chord.b.y);
                    moved = chord_point(moved, qb, chord.f);
                }
            }
        }
        let w = POINT_WORDS * k;
        let clip = to_clip(moved);
        scratch_store_clip(slot, w, clip);
        // The stages that lost the point (reyes::nonfinite), counted below.
        var non_finite = dice_non_finite(patch_point, object.displace_kind != DISPLACE_NONE, moved) | camera_non_finite(moved, clip, to_pixel(clip));
        var color = vec3<f32>(0.0);
        switch frame.aov {
            case AOV_DEPTH: {
                color = depth_color(clip.w);
            }
            case AOV_NORMAL: {
                color = normal * 0.5 + vec3<f32>(0.5);
            }
            default: {
                let step = vec2<f32>((item.uv.z - item.uv.x) / f32(nu), (item.uv.w - item.uv.y) / f32(nv));
                let context = shading_context(&q, item.input_patch, object, moved, normal, geometric_normal, vec2<f32>(u, v), step);
                color = shade(context, object);
            }
        }
        scratch_store_u32(slot, w + 4u, pack_rgb10(color));
        if (VARIANT_BLURRED) {
            var close_position = moved;
            if (object.moving != 0u) {
                close_position = motion_close(object, moved);
            }
            let close_clip = to_clip(close_position);
            scratch_store_clip(slot, w + 5u, close_clip);
            non_finite |= close_non_finite(moved, close_position, close_clip, to_pixel(close_clip));
            let seen = moving_point(clip, close_clip);
            let motion = dist2(seen.open.xy, seen.close.xy);
            let blur = moving_blur(seen);
            // NaN extents (a point behind the eye) are ignored, as f32::max does.
            if (!is_nan_f32(motion)) {
                atomicMax(&grid_extent[2u * slot], bitcast<u32>(motion));
            }
            if (!is_nan_f32(blur)) {
                atomicMax(&grid_extent[2u * slot + 1u], bitcast<u32>(blur));
            }
        }
        count_non_finite(non_finite);
    }
}
workgroupBarrier();
if (valid && thread < nu * nv) {
    let i = thread % nu;
    let j = thread / nu;
    // Corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1).
    let wa = POINT_WORDS * (j * columns + i);
    let wb = wa + POINT_WORDS;
    let wd = wa + POINT_WORDS * columns;
    let wc = wd + POINT_WORDS;
    let a = grid_point(slot, wa);
    let b = grid_point(slot, wb);
    let c = grid_point(slot, wc);
    let d = grid_point(slot, wd);

    // Largest micropolygon: positive floats order like their bits; NaN
    // sizes are ignored as f32::max does in the reference.
    let lo = min(min(a.xy, b.xy), min(c.xy, d.xy));
    let hi = max(max(a.xy, b.xy), max(c.xy, d.xy));
    let size = max_ignoring_nan(hi.x - lo.x, hi.y - lo.y);
    if (!is_nan_f32(size)) {
        atomicMax(&stats[STAT_LARGEST_MICROPOLYGON], bitcast<u32>(size));
    }

    // The corners' colours (smooth shading), or one for the micropolygon.
    let ca = scratch_load_u32(slot, wa + 4u);
    let cb = scratch_load_u32(slot, wb + 4u);
    let cc = scratch_load_u32(slot, wc + 4u);
    let cd = scratch_load_u32(slot, wd + 4u);
    var color = average_rgb10(ca, cb, cc, cd);
    if (frame.aov == AOV_GRIDS) {
        color = grid_color(nu * nv, i, j);
    }
    var colors = vec4<u32>(color);
    if (frame.smooth_shading != 0u && frame.aov != AOV_GRIDS) {
        colors = vec4<u32>(ca, cb, cc, cd);
    }
    // A one-sided object's back-facing triangles are culled.
    let front = objects[item.object].front;
    var counts = SampleCounts(0u, 0u, 0u);
    if (VARIANT_BLURRED) {
        let mode = mode_for_grid(bitcast<f32>(atomicLoad(&grid_extent[2u * slot])), bitcast<f32>(atomicLoad(&grid_extent[2u * slot + 1u])));
        if (thread == 0u && mode == SAMPLING_INTERLEAVE) {
            atomicAdd(&stats[STAT_INTERLEAVE_GRIDS], 1u);
        }
        let ma = moving_point(grid_clip(slot, wa), grid_clip(slot, wa + 5u));
        let mb = moving_point(grid_clip(slot, wb), grid_clip(slot, wb + 5u));
        let mc = moving_point(grid_clip(slot, wc), grid_clip(slot, wc + 5u));
        let md = moving_point(grid_clip(slot, wd), grid_clip(slot, wd + 5u));
        // A face is culled only when it faces away at both ends of the
        // interval its corners are seen in (Fatahalian et al.): one that
        // turns towards the camera during the shutter is drawn.
        let at_open = vec2<bool>(drawn_face(ma.open.xy, mb.open.xy, mc.open.xy, front), drawn_face(ma.open.xy, mc.open.xy, md.open.xy, front));
        let at_close = vec2<bool>(drawn_face(ma.close.xy, mb.close.xy, mc.close.xy, front), drawn_face(ma.close.xy, mc.close.xy, md.close.xy, front));
        let drawn = at_open | at_close;
        raster_quad_5d(mode, ma, mb, mc, md, colors, drawn, &counts);
    } else {
        let drawn = vec2<bool>(drawn_face(a.xy, b.xy, c.xy, front), drawn_face(a.xy, c.xy, d.xy, front));
        let quad = still_quad(a, b, c, d, colors, drawn);
        if (frame.sampling == SAMPLING_NEAREST) {
            raster_nearest(a, b, c, d, quad, &counts);
        } else {
            raster_quad(quad, &counts);
        }
    }
    stat_add64(STAT_SAMPLES_TESTED, counts.tested);
    stat_add64(STAT_SAMPLES_HIT, counts.hit);
    stat_add64(STAT_SAMPLES_SKIPPED, counts.skipped);
}
if (valid && thread == 0u) {
    atomicAdd(&stats[STAT_GRIDS_DICED], 1u);
    stat_add64(STAT_MICROPOLYGONS, nu * nv);
    atomicAdd(&stats[STAT_GRIDS_BY_CLASS + grid_class(nu, nv)], 1u);
    stat_add64(STAT_DICE_THREADS, DICE_THREADS);
}
if (VARIANT_BLURRED) {
    // Every thread has read the grid's extents: clear them for the next
    // batch (workgroup memory starts zeroed).
    workgroupBarrier();
    if (valid && thread == 0u) {
        atomicStore(&grid_extent[2u * slot], 0u);
        atomicStore(&grid_extent[2u * slot + 1u], 0u);
    }
}
