// Rasterization with motion blur and depth of field
// (reyes::reference::raster5d, operation for operation), on the quads of
// quad.wgsl: the sampling modes
// Bounding box, Simple UVT, Interleave UVT, INTERVAL and Adaptive. A
// sample's time and lens position come from the host-built tables
// (reyes::uvt::UvtTables) at frame.uvt_* in height_texels. Every loop is
// checked afterwards: one the driver cut short counts in STAT_LOOPS_CUT.

// A grid point over the part of the shutter during which it can be seen
// (reyes::reference::raster5d::MovingPoint): open and close are its
// projections at t_open and t_close.
struct Moving {
    open: vec3<f32>,
    close: vec3<f32>,
    coc_open: f32,
    coc_close: f32,
    t_open: f32,
    t_close: f32,
    usable: bool,
}

fn usable_end(p: vec3<f32>, w: f32) -> bool {
    return w > NEAR_EPS && p.z >= 0.0 && p.z <= 1.0;
}

// One plane of reyes::reference::raster5d::visible_span: `f0` and `f1` are
// a function of the clip position, linear in t and >= 0 on the visible
// side, at open and close.
fn clip_span(span: vec2<f32>, f0: f32, f1: f32) -> vec2<f32> {
    if (f0 >= 0.0 && f1 >= 0.0) {
        return span;
    }
    if (f0 < 0.0 && f1 < 0.0) {
        return vec2<f32>(1.0, 0.0);
    }
    let t = f0 / (f0 - f1);
    if (f0 < 0.0) {
        return vec2<f32>(max(span.x, t), span.y);
    }
    return vec2<f32>(span.x, min(span.y, t));
}

// The shutter times (lo, hi) at which the clip position moving linearly
// from c0 to c1 is in front of the near plane and not past the far plane;
// lo > hi when there are none.
fn visible_span(c0: vec4<f32>, c1: vec4<f32>) -> vec2<f32> {
    if (!(all(vec4<bool>(is_finite_f32(c0.x), is_finite_f32(c0.y), is_finite_f32(c0.z), is_finite_f32(c0.w)))
        && all(vec4<bool>(is_finite_f32(c1.x), is_finite_f32(c1.y), is_finite_f32(c1.z), is_finite_f32(c1.w))))) {
        return vec2<f32>(1.0, 0.0);
    }
    var span = vec2<f32>(0.0, 1.0);
    span = clip_span(span, c0.z, c1.z);
    span = clip_span(span, c0.w - c0.z, c1.w - c1.z);
    span = clip_span(span, c0.w - NEAR_EPS, c1.w - NEAR_EPS);
    return span;
}

// The clip position at shutter time t, exactly an end at 0 and 1.
fn clip_at(c0: vec4<f32>, c1: vec4<f32>, t: f32) -> vec4<f32> {
    if (t == 0.0) {
        return c0;
    }
    if (t == 1.0) {
        return c1;
    }
    return c0 + (c1 - c0) * t;
}

fn moving_point(clip_open: vec4<f32>, clip_close: vec4<f32>) -> Moving {
    let span = visible_span(clip_open, clip_close);
    let c0 = clip_at(clip_open, clip_close, span.x);
    let c1 = clip_at(clip_open, clip_close, span.y);
    var open = to_pixel(c0);
    var close = to_pixel(c1);
    // A clipped end lies on the near or far plane: rounding must not push
    // its depth out of [0, 1].
    if (span.x > 0.0) {
        open.z = clamp(open.z, 0.0, 1.0);
    }
    if (span.y < 1.0) {
        close.z = clamp(close.z, 0.0, 1.0);
    }
    let usable = span.x <= span.y && usable_end(open, c0.w) && usable_end(close, c1.w);
    return Moving(open, close, coc(c0.w), coc(c1.w), span.x, span.y, usable);
}

fn visible_at(m: Moving, t: f32) -> bool {
    return t >= m.t_open && t <= m.t_close;
}

// Where shutter time t lies between m.open (0) and m.close (1), clamped.
fn moving_param(m: Moving, t: f32) -> f32 {
    if (m.t_open == 0.0 && m.t_close == 1.0) {
        return t;
    }
    let length = m.t_close - m.t_open;
    if (length > 0.0) {
        return clamp((t - m.t_open) / length, 0.0, 1.0);
    }
    return 0.0;
}

fn moving_coc(m: Moving, t: f32) -> f32 {
    return m.coc_open + (m.coc_close - m.coc_open) * moving_param(m, t);
}

// Where a sample at time t through lens position `lens` sees the point.
fn moving_at(m: Moving, t: f32, lens: vec2<f32>) -> vec3<f32> {
    let s = moving_param(m, t);
    let p = m.open + (m.close - m.open) * s;
    let c = m.coc_open + (m.coc_close - m.coc_open) * s;
    return vec3<f32>(p.x + lens.x * c, p.y + lens.y * c, p.z);
}

fn moving_blur(m: Moving) -> f32 {
    return max(abs(m.coc_open), abs(m.coc_close));
}

// (t, lens.x, lens.y) of a time/lens record at float offset `at`.
fn uvt_record(at: u32) -> vec3<f32> {
    return vec3<f32>(height_texels[at], height_texels[at + 1u], height_texels[at + 2u]);
}

// Float offset of sample s of pixel (x, y) in the per-pixel table.
fn uvt_pixel_at(x: u32, y: u32, s: u32) -> u32 {
    let gx = x + frame.origin_x;
    let gy = y + frame.origin_y;
    return frame.uvt_pixel + 4u * (((gy % TABLE_SIDE) * TABLE_SIDE + gx % TABLE_SIDE) * frame.spp + s);
}

// The permutation Interleave tile (tx, ty) of the full image takes
// (reference InterleaveTiles::permutation): Sattlecker and Steinberger's
// tilenumber = ty * (width / K) + tx, permutation = (tilenumber + tx + ty)
// mod P.
fn tile_permutation(tx: u32, ty: u32) -> u32 {
    let tilenumber = ty * frame.interleave_row_tiles + tx;
    return (tilenumber + tx + ty) % frame.interleave_permutations;
}

// The Interleave slot of pixel (x, y) (reference UvtTables::interleave_slot).
fn interleave_slot(x: u32, y: u32) -> u32 {
    let gx = x + frame.origin_x;
    let gy = y + frame.origin_y;
    let tile = frame.interleave_tile;
    let offset = (gy % tile) * tile + gx % tile;
    let permutation = tile_permutation(gx / tile, gy / tile);
    return u32(height_texels[frame.uvt_slot_of_pixel + permutation * tile * tile + offset]);
}

// The time and lens of sample s of pixel (x, y) for the bounding box
// (reference UvtTables::pixel_tuple): the per-pixel table's, or under
// Adaptive the Interleave tuple the sample carries.
fn pixel_tuple(x: u32, y: u32, s: u32) -> vec3<f32> {
    if (frame.interleave_pixel_tuples == 0u) {
        return uvt_record(uvt_pixel_at(x, y, s));
    }
    let q = interleave_slot(x, y);
    let stratum = u32(height_texels[frame.uvt_slot_stratum + q * frame.spp + s]);
    let tile = frame.interleave_tile;
    return uvt_record(frame.uvt_interleave + 4u * (stratum * tile * tile + q));
}

// INTERVAL's sample of pixel (x, y) for time interval i: the sample whose
// time lies in stratum i and the float offset of its time/lens record
// (reference UvtTables::pixel_sample_in_stratum and pixel_tuple). Under
// Adaptive it is the sample carrying the pixel's slot's tuple of stratum
// i, so that grids sampled by INTERVAL and by Interleave UVT agree sample
// by sample.
fn interval_sample(x: u32, y: u32, i: u32) -> vec2<u32> {
    if (frame.interleave_pixel_tuples == 0u) {
        let s = u32(height_texels[uvt_pixel_at(x, y, i) + 3u]);
        return vec2<u32>(s, uvt_pixel_at(x, y, s));
    }
    let q = interleave_slot(x, y);
    let tile = frame.interleave_tile;
    let s = u32(height_texels[frame.uvt_slot_sample + q * frame.spp + i]);
    return vec2<u32>(s, frame.uvt_interleave + 4u * (i * tile * tile + q));
}

// A micropolygon over the shutter (reference MovingQuad): its corners,
// their packed colours, and which of its triangles (a, b, c), (a, c, d)
// may be drawn at all.
struct MovingQuad {
    a: Moving,
    b: Moving,
    c: Moving,
    d: Moving,
    colors: vec4<u32>,
    drawable: vec2<bool>,
}

// The quad at time and lens `tl` (reference MovingQuad::place): a triangle
// is drawn when it is drawable and all its corners can be seen at tl.x.
fn place_quad(q: MovingQuad, tl: vec3<f32>) -> Quad {
    let t = tl.x;
    let seen_ac = visible_at(q.a, t) && visible_at(q.c, t);
    let drawn = vec2<bool>(q.drawable.x && seen_ac && visible_at(q.b, t), q.drawable.y && seen_ac && visible_at(q.d, t));
    return make_quad(moving_at(q.a, t, tl.yz), moving_at(q.b, t, tl.yz), moving_at(q.c, t, tl.yz), moving_at(q.d, t, tl.yz), q.colors, drawn);
}

// Whether the triangle of corners x, y, z can all be seen at some time of [t0, t1].
fn seen_in(x: Moving, y: Moving, z: Moving, t0: f32, t1: f32) -> bool {
    let seen_from = max(max(max(0.0, x.t_open), y.t_open), z.t_open);
    let seen_until = min(min(min(1.0, x.t_close), y.t_close), z.t_close);
    return seen_from <= t1 && seen_until >= t0;
}

// The corners (a, b, c, d) of the drawable triangles seen during [t0, t1]
// (reference MovingQuad::corners_seen).
fn corners_seen(q: MovingQuad, t0: f32, t1: f32) -> vec4<bool> {
    let abc = q.drawable.x && seen_in(q.a, q.b, q.c, t0, t1);
    let acd = q.drawable.y && seen_in(q.a, q.c, q.d, t0, t1);
    return vec4<bool>(abc || acd, abc, abc || acd, acd);
}

// Places q at sample s's own time and lens (`tl`) and tests the sample; a
// quad without a triangle there still counts as tested.
fn place_and_test(q: MovingQuad, tl: vec3<f32>, x: u32, y: u32, s: u32, counts: ptr<function, SampleCounts>) {
    test_quad(place_quad(q, tl), x, y, s, counts);
}

// The box over both ends of a point, grown by r (Bounding box).
fn ends_bounds(b: Bounds, m: Moving, used: bool) -> Bounds {
    if (!used) {
        return b;
    }
    return bounds_add(bounds_add(b, m.open.xy), m.close.xy);
}

// Bounding box: the box over both ends of the corners, grown by their
// largest blur; every sample of the strata it touches, each with its own
// time and lens.
fn raster_bbox_5d(q: MovingQuad, counts: ptr<function, SampleCounts>) {
    let used = corners_seen(q, 0.0, 1.0);
    var r = 0.0;
    r = select(r, max(r, moving_blur(q.a)), used.x);
    r = select(r, max(r, moving_blur(q.b)), used.y);
    r = select(r, max(r, moving_blur(q.c)), used.z);
    r = select(r, max(r, moving_blur(q.d)), used.w);
    let ends = ends_bounds(ends_bounds(ends_bounds(ends_bounds(no_bounds(), q.a, used.x), q.b, used.y), q.c, used.z), q.d, used.w);
    if (!ends.ok) {
        return;
    }
    let strata = strata_box(ends.lo - vec2<f32>(r), ends.hi + vec2<f32>(r));
    if (!strata.ok) {
        return;
    }
    let total = strata_count(strata);
    var n = 0u;
    loop {
        if (n >= total) {
            break;
        }
        let sample = strata_sample(strata, n);
        place_and_test(q, pixel_tuple(sample.x, sample.y, sample.z), sample.x, sample.y, sample.z, counts);
        n += 1u;
    }
    if (n < total) {
        loop_cut();
    }
}

// Simple UVT: tuple s positions the quad once; sample s of each pixel
// whose stratum its box touches is tested.
fn raster_simple(q: MovingQuad, counts: ptr<function, SampleCounts>) {
    let spp = frame.spp;
    let k = frame.k;
    var s = 0u;
    loop {
        if (s >= spp) {
            break;
        }
        let placed = place_quad(q, uvt_record(frame.uvt_simple + 4u * s));
        let bounds = quad_bounds(placed);
        let strata = strata_box(bounds.lo, bounds.hi);
        let columns = span_of(strata.x0, strata.x1, s % k);
        let rows = span_of(strata.y0, strata.y1, s / k);
        if (bounds.ok && strata.ok && columns.ok && rows.ok) {
            let nx = columns.last - columns.first + 1u;
            let total = nx * (rows.last - rows.first + 1u);
            var n = 0u;
            loop {
                if (n >= total) {
                    break;
                }
                test_quad(placed, columns.first + n % nx, rows.first + n / nx, s, counts);
                n += 1u;
            }
            if (n < total) {
                loop_cut();
            }
        }
        s += 1u;
    }
    if (s < spp) {
        loop_cut();
    }
}

// Interleave UVT: tuple n positions the quad once; in every K x K tile
// (counted in absolute pixels) its box overlaps, the one sample carrying
// tuple n is tested if its stratum is in the box.
fn raster_interleave(q: MovingQuad, counts: ptr<function, SampleCounts>) {
    let tuples = frame.interleave_tuples;
    let tile = frame.interleave_tile;
    let k = frame.k;
    var tuple = 0u;
    loop {
        if (tuple >= tuples) {
            break;
        }
        let placed = place_quad(q, uvt_record(frame.uvt_interleave + 4u * tuple));
        let bounds = quad_bounds(placed);
        let strata = strata_box(bounds.lo, bounds.hi);
        if (bounds.ok && strata.ok) {
            let tx0 = (strata.x0 / k + frame.origin_x) / tile;
            let ty0 = (strata.y0 / k + frame.origin_y) / tile;
            let ntx = (strata.x1 / k + frame.origin_x) / tile - tx0 + 1u;
            let nty = (strata.y1 / k + frame.origin_y) / tile - ty0 + 1u;
            let total = ntx * nty;
            var n = 0u;
            loop {
                if (n >= total) {
                    break;
                }
                let tx = tx0 + n % ntx;
                let ty = ty0 + n / ntx;
                let permutation = tile_permutation(tx, ty);
                let j = u32(height_texels[frame.uvt_inverse + permutation * tuples + tuple]);
                let slot = j / frame.spp;
                let s = j % frame.spp;
                // The sample's pixel in absolute and then in image coordinates.
                let gx = tx * tile + slot % tile;
                let gy = ty * tile + slot / tile;
                var tested = false;
                if (gx >= frame.origin_x && gy >= frame.origin_y) {
                    let x = gx - frame.origin_x;
                    let y = gy - frame.origin_y;
                    if (x < frame.width && y < frame.height && strata_hold(strata, x, y, s)) {
                        test_quad(placed, x, y, s, counts);
                        tested = true;
                    }
                }
                if (!tested) {
                    (*counts).skipped += 1u;
                }
                n += 1u;
            }
            if (n < total) {
                loop_cut();
            }
        }
        tuple += 1u;
    }
    if (tuple < tuples) {
        loop_cut();
    }
}

// A point's positions at the ends of [t0, t1] through the corners of the
// lens box [lens_lo, lens_hi]: its extremes, as the position is bilinear
// in time and lens position.
fn interval_bounds(b: Bounds, m: Moving, used: bool, t0: f32, t1: f32, lens_lo: vec2<f32>, lens_hi: vec2<f32>) -> Bounds {
    if (!used) {
        return b;
    }
    var out = bounds_add(b, moving_at(m, t0, lens_lo).xy);
    out = bounds_add(out, moving_at(m, t0, lens_hi).xy);
    out = bounds_add(out, moving_at(m, t1, lens_lo).xy);
    return bounds_add(out, moving_at(m, t1, lens_hi).xy);
}

// INTERVAL: time interval i gets the box of the quad over the interval
// and the lens region its samples use (the UV-T pairing: the lens box at
// frame.uvt_interval_lens); in each of its pixels the one sample whose
// time lies in interval i is tested if its stratum is in the box.
fn raster_interval(q: MovingQuad, counts: ptr<function, SampleCounts>) {
    let spp = frame.spp;
    let n_f = f32(spp);
    var i = 0u;
    loop {
        if (i >= spp) {
            break;
        }
        let t0 = f32(i) / n_f;
        let t1 = f32(i + 1u) / n_f;
        let at = frame.uvt_interval_lens + 4u * i;
        let lens_lo = vec2<f32>(height_texels[at], height_texels[at + 1u]);
        let lens_hi = vec2<f32>(height_texels[at + 2u], height_texels[at + 3u]);
        let used = corners_seen(q, t0, t1);
        var bounds = interval_bounds(no_bounds(), q.a, used.x, t0, t1, lens_lo, lens_hi);
        bounds = interval_bounds(bounds, q.b, used.y, t0, t1, lens_lo, lens_hi);
        bounds = interval_bounds(bounds, q.c, used.z, t0, t1, lens_lo, lens_hi);
        bounds = interval_bounds(bounds, q.d, used.w, t0, t1, lens_lo, lens_hi);
        let strata = strata_box(bounds.lo, bounds.hi);
        if (bounds.ok && strata.ok) {
            let k = frame.k;
            let x0 = strata.x0 / k;
            let y0 = strata.y0 / k;
            let nx = strata.x1 / k - x0 + 1u;
            let total = nx * (strata.y1 / k - y0 + 1u);
            var n = 0u;
            loop {
                if (n >= total) {
                    break;
                }
                let x = x0 + n % nx;
                let y = y0 + n / nx;
                let sample = interval_sample(x, y, i);
                let s = sample.x;
                if (strata_hold(strata, x, y, s)) {
                    place_and_test(q, uvt_record(sample.y), x, y, s, counts);
                } else {
                    (*counts).skipped += 1u;
                }
                n += 1u;
            }
            if (n < total) {
                loop_cut();
            }
        }
        i += 1u;
    }
    if (i < spp) {
        loop_cut();
    }
}

// reyes::reference::raster5d::adaptive_costs and adaptive_choice:
// SAMPLING_INTERLEAVE or SAMPLING_INTERVAL for a grid with this largest
// motion and blur (pixels), whichever its estimated cost is lower for.
fn adaptive_choice(motion: f32, blur: f32) -> u32 {
    let n = f32(frame.spp);
    let k = f32(frame.k);
    let kt = f32(frame.interleave_tile);
    let m = frame.adaptive_micropolygon;
    let side = m + motion / n + 2.0 * blur / k + 1.0 / k;
    let interval = n * side * side * (1.0 + ADAPTIVE_PLACE_COST);
    let tiles = (1.0 + m / kt) * (1.0 + m / kt);
    let interleave = n * kt * kt * (ADAPTIVE_PLACE_COST + tiles);
    if (interleave < interval) {
        return SAMPLING_INTERLEAVE;
    }
    return SAMPLING_INTERVAL;
}

// reyes::reference::raster5d::Mode5d::for_grid.
fn mode_for_grid(motion: f32, blur: f32) -> u32 {
    if (frame.sampling == SAMPLING_ADAPTIVE) {
        return adaptive_choice(motion, blur);
    }
    if (frame.sampling == SAMPLING_NEAREST) {
        return SAMPLING_BBOX;
    }
    return frame.sampling;
}

// reyes::reference::raster5d::raster_quad_5d: the micropolygon of corners
// (a, b, c, d) with their packed colours, its triangles (a, b, c) and
// (a, c, d) drawn where `drawn` says so and their corners are usable.
fn raster_quad_5d(mode: u32, ma: Moving, mb: Moving, mc: Moving, md: Moving, colors: vec4<u32>, drawn: vec2<bool>, counts: ptr<function, SampleCounts>) {
    let ua = ma.usable;
    let uc = mc.usable;
    let drawable = vec2<bool>(drawn.x && ua && mb.usable && uc, drawn.y && ua && uc && md.usable);
    if (!(drawable.x || drawable.y)) {
        return;
    }
    let q = MovingQuad(ma, mb, mc, md, colors, drawable);
    switch mode {
        case SAMPLING_SIMPLE: {
            raster_simple(q, counts);
        }
        case SAMPLING_INTERLEAVE: {
            raster_interleave(q, counts);
        }
        case SAMPLING_INTERVAL: {
            raster_interval(q, counts);
        }
        default: {
            raster_bbox_5d(q, counts);
        }
    }
}

// Each grid's largest point motion and circle of confusion (f32 bits; both
// >= 0, so they order like their bits), gathered by the DiceShadeSample
// procedures for Adaptive sampling: words 2 * slot and 2 * slot + 1 for
// the item in `slot` (a workgroup holds up to DICE_SLOTS items).
var<workgroup> grid_extent: array<atomic<u32>, GRID_EXTENT_WORDS>;
