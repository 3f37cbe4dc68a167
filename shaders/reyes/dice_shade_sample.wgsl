// Body of `DiceShadeSample` (256 threads per piece). Thread t evaluates grid
// point (t % 16, t / 16) at s = i / 15, t = j / 15 (position, exact normal,
// shading, projection) and stores it in scratch; after the barrier threads
// 0..225 each rasterize micropolygon (t % 15, t / 15) as the two triangles
// (a, b, c) and (a, c, d), or its nearest sample.
// Scratch: 7 words per grid point (px, py, depth, clip w, r, g, b).
if (valid) {
    var p = item.p;
    let i = thread % GRID_POINTS;
    let j = thread / GRID_POINTS;
    let s = f32(i) / f32(GRID_QUADS);
    let t = f32(j) / f32(GRID_QUADS);
    let position = tensor(&p, bernstein(s), bernstein(t));
    let normal = surface_normal(&p, s, t, position, frame.eye);
    let color = shade(position, normal, objects[item.object].xyz);
    let clip = to_clip(position);
    let pixel = to_pixel(clip);
    let w = 7u * thread;
    scratch_store_f32(slot, w, pixel.x);
    scratch_store_f32(slot, w + 1u, pixel.y);
    scratch_store_f32(slot, w + 2u, pixel.z);
    scratch_store_f32(slot, w + 3u, clip.w);
    scratch_store_f32(slot, w + 4u, color.x);
    scratch_store_f32(slot, w + 5u, color.y);
    scratch_store_f32(slot, w + 6u, color.z);
}
workgroupBarrier();
if (valid && thread < GRID_QUADS * GRID_QUADS) {
    let i = thread % GRID_QUADS;
    let j = thread / GRID_QUADS;
    // Corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1).
    let wa = 7u * (j * GRID_POINTS + i);
    let wb = wa + 7u;
    let wd = wa + 7u * GRID_POINTS;
    let wc = wd + 7u;
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
    if (frame.sampling == SAMPLING_NEAREST) {
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
