// Rasterization with motion blur and depth of field
// (reyes::reference::raster5d, operation for operation): the sampling modes
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

// A triangle at one time and lens position; `ok` is false when a corner
// cannot be seen then or the triangle has no area there.
struct Placed {
    a: vec3<f32>,
    b: vec3<f32>,
    c: vec3<f32>,
    // The packed colours of a, b and c.
    colors: vec3<u32>,
    area: f32,
    ok: bool,
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

fn place(ma: Moving, mb: Moving, mc: Moving, colors: vec3<u32>, tl: vec3<f32>) -> Placed {
    let a = moving_at(ma, tl.x, tl.yz);
    if (!(visible_at(ma, tl.x) && visible_at(mb, tl.x) && visible_at(mc, tl.x))) {
        return Placed(a, a, a, colors, 0.0, false);
    }
    var b = moving_at(mb, tl.x, tl.yz);
    var c = moving_at(mc, tl.x, tl.yz);
    let area = edge(a.xy, b.xy, c.xy);
    if (area == 0.0 || !is_finite_f32(area)) {
        return Placed(a, b, c, colors, 0.0, false);
    }
    if (area < 0.0) {
        let swap = b;
        b = c;
        c = swap;
        return Placed(a, b, c, colors.xzy, abs(area), true);
    }
    return Placed(a, b, c, colors, abs(area), true);
}

// Places the triangle at sample s's own time and lens (`tl`) and tests the
// sample; a triangle without area there still counts as tested.
fn place_and_test(ma: Moving, mb: Moving, mc: Moving, colors: vec3<u32>, tl: vec3<f32>, x: u32, y: u32, s: u32, counts: ptr<function, SampleCounts>) {
    let placed = place(ma, mb, mc, colors, tl);
    if (placed.ok) {
        test_sample(placed, x, y, s, counts);
    } else {
        (*counts).tested += 1u;
    }
}

fn placed_lo(p: Placed) -> vec2<f32> {
    return min(min(p.a.xy, p.b.xy), p.c.xy);
}

fn placed_hi(p: Placed) -> vec2<f32> {
    return max(max(p.a.xy, p.b.xy), p.c.xy);
}

// Tests sample s of pixel (x, y) against a placed triangle.
fn test_sample(p: Placed, x: u32, y: u32, s: u32, counts: ptr<function, SampleCounts>) {
    (*counts).tested += 1u;
    let q = sample_position(x, y, s);
    let a = p.a.xy;
    let b = p.b.xy;
    let c = p.c.xy;
    let e_bc = edge(b, c, q);
    let e_ca = edge(c, a, q);
    let e_ab = edge(a, b, q);
    if (inside(e_bc, b, c) && inside(e_ca, c, a) && inside(e_ab, a, b)) {
        (*counts).hit += 1u;
        let z = (e_bc * p.a.z + e_ca * p.b.z + e_ab * p.c.z) / p.area;
        offer(x, y, s, z, blend_rgb10(p.colors, vec3<f32>(e_bc, e_ca, e_ab), p.area));
    }
}

// The pixel range (x0, y0, x1, y1) a box touches, clamped to the screen;
// `.w < .y` or `.z < .x` when it misses (reyes::reference::raster5d::pixel_range).
struct PixelRange {
    x0: u32,
    y0: u32,
    nx: u32,
    ny: u32,
    ok: bool,
}

fn pixel_range(lo: vec2<f32>, hi: vec2<f32>) -> PixelRange {
    let x0 = max(floor(lo.x), 0.0);
    let y0 = max(floor(lo.y), 0.0);
    let x1 = min(floor(hi.x), f32(frame.width) - 1.0);
    let y1 = min(floor(hi.y), f32(frame.height) - 1.0);
    if (!(x0 <= x1 && y0 <= y1)) {
        return PixelRange(0u, 0u, 0u, 0u, false);
    }
    return PixelRange(u32(x0), u32(y0), u32(x1) - u32(x0) + 1u, u32(y1) - u32(y0) + 1u, true);
}

fn loop_cut() {
    atomicAdd(&stats[STAT_LOOPS_CUT], 1u);
}

// Bounding box: the box over both ends, grown by the corners' largest blur;
// every sample of every pixel in it, each with its own time and lens.
fn raster_bbox_5d(ma: Moving, mb: Moving, mc: Moving, colors: vec3<u32>, counts: ptr<function, SampleCounts>) {
    let r = max(max(max(0.0, moving_blur(ma)), moving_blur(mb)), moving_blur(mc));
    let lo = min(min(min(ma.open.xy, ma.close.xy), min(mb.open.xy, mb.close.xy)), min(mc.open.xy, mc.close.xy));
    let hi = max(max(max(ma.open.xy, ma.close.xy), max(mb.open.xy, mb.close.xy)), max(mc.open.xy, mc.close.xy));
    let range = pixel_range(lo - vec2<f32>(r), hi + vec2<f32>(r));
    if (!range.ok) {
        return;
    }
    let spp = frame.spp;
    let total = range.nx * range.ny * spp;
    var n = 0u;
    loop {
        if (n >= total) {
            break;
        }
        let s = n % spp;
        let pixel = n / spp;
        let x = range.x0 + pixel % range.nx;
        let y = range.y0 + pixel / range.nx;
        place_and_test(ma, mb, mc, colors, uvt_record(uvt_pixel_at(x, y, s)), x, y, s, counts);
        n += 1u;
    }
    if (n < total) {
        loop_cut();
    }
}

// Simple UVT: tuple s positions the triangle once; sample s of each pixel
// in its box is tested.
fn raster_simple(ma: Moving, mb: Moving, mc: Moving, colors: vec3<u32>, counts: ptr<function, SampleCounts>) {
    let spp = frame.spp;
    var s = 0u;
    loop {
        if (s >= spp) {
            break;
        }
        let placed = place(ma, mb, mc, colors, uvt_record(frame.uvt_simple + 4u * s));
        let range = pixel_range(placed_lo(placed), placed_hi(placed));
        if (placed.ok && range.ok) {
            let total = range.nx * range.ny;
            var n = 0u;
            loop {
                if (n >= total) {
                    break;
                }
                test_sample(placed, range.x0 + n % range.nx, range.y0 + n / range.nx, s, counts);
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

// Interleave UVT: tuple n positions the triangle once; in every 2x2 tile
// its box overlaps, the one sample carrying tuple n is tested.
fn raster_interleave(ma: Moving, mb: Moving, mc: Moving, colors: vec3<u32>, counts: ptr<function, SampleCounts>) {
    let tuples = frame.interleave_tuples;
    var tuple = 0u;
    loop {
        if (tuple >= tuples) {
            break;
        }
        let placed = place(ma, mb, mc, colors, uvt_record(frame.uvt_interleave + 4u * tuple));
        let range = pixel_range(placed_lo(placed), placed_hi(placed));
        if (placed.ok && range.ok) {
            let tx0 = range.x0 / INTERLEAVE_TILE;
            let ty0 = range.y0 / INTERLEAVE_TILE;
            let ntx = (range.x0 + range.nx - 1u) / INTERLEAVE_TILE - tx0 + 1u;
            let nty = (range.y0 + range.ny - 1u) / INTERLEAVE_TILE - ty0 + 1u;
            let total = ntx * nty;
            var n = 0u;
            loop {
                if (n >= total) {
                    break;
                }
                let tx = tx0 + n % ntx;
                let ty = ty0 + n / ntx;
                // Tile origins are multiples of INTERLEAVE_TILE (TILE_ALIGN).
                let permutation = jitter_hash(
                    tx + frame.origin_x / INTERLEAVE_TILE,
                    ty + frame.origin_y / INTERLEAVE_TILE,
                    0u,
                    PERMUTATION_CHANNEL,
                ) % INTERLEAVE_PERMUTATIONS;
                let j = u32(height_texels[frame.uvt_inverse + permutation * tuples + tuple]);
                let q = j / frame.spp;
                let x = tx * INTERLEAVE_TILE + q % INTERLEAVE_TILE;
                let y = ty * INTERLEAVE_TILE + q / INTERLEAVE_TILE;
                if (x < frame.width && y < frame.height) {
                    test_sample(placed, x, y, j % frame.spp, counts);
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

// INTERVAL: time interval i gets the box of the triangle over the interval
// (grown by the largest blur in it); in each of its pixels the one sample
// whose time lies in interval i is tested.
fn raster_interval(ma: Moving, mb: Moving, mc: Moving, colors: vec3<u32>, counts: ptr<function, SampleCounts>) {
    let spp = frame.spp;
    let n_f = f32(spp);
    // The times at which all three corners can be seen.
    let seen_from = max(max(max(0.0, ma.t_open), mb.t_open), mc.t_open);
    let seen_until = min(min(min(1.0, ma.t_close), mb.t_close), mc.t_close);
    var i = 0u;
    loop {
        if (i >= spp) {
            break;
        }
        let t0 = f32(i) / n_f;
        let t1 = f32(i + 1u) / n_f;
        if (t1 < seen_from || t0 > seen_until) {
            i += 1u;
            continue;
        }
        let a0 = moving_at(ma, t0, vec2<f32>(0.0));
        let a1 = moving_at(ma, t1, vec2<f32>(0.0));
        let b0 = moving_at(mb, t0, vec2<f32>(0.0));
        let b1 = moving_at(mb, t1, vec2<f32>(0.0));
        let c0 = moving_at(mc, t0, vec2<f32>(0.0));
        let c1 = moving_at(mc, t1, vec2<f32>(0.0));
        let lo = min(min(min(a0.xy, a1.xy), min(b0.xy, b1.xy)), min(c0.xy, c1.xy));
        let hi = max(max(max(a0.xy, a1.xy), max(b0.xy, b1.xy)), max(c0.xy, c1.xy));
        var r = 0.0;
        r = max(max(r, abs(moving_coc(ma, t0))), abs(moving_coc(ma, t1)));
        r = max(max(r, abs(moving_coc(mb, t0))), abs(moving_coc(mb, t1)));
        r = max(max(r, abs(moving_coc(mc, t0))), abs(moving_coc(mc, t1)));
        let range = pixel_range(lo - vec2<f32>(r), hi + vec2<f32>(r));
        if (range.ok) {
            let total = range.nx * range.ny;
            var n = 0u;
            loop {
                if (n >= total) {
                    break;
                }
                let x = range.x0 + n % range.nx;
                let y = range.y0 + n / range.nx;
                let s = u32(height_texels[uvt_pixel_at(x, y, i) + 3u]);
                place_and_test(ma, mb, mc, colors, uvt_record(uvt_pixel_at(x, y, s)), x, y, s, counts);
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

// reyes::reference::raster5d::adaptive_choice: SAMPLING_INTERLEAVE or
// SAMPLING_INTERVAL for a grid with this largest motion and blur (pixels).
fn adaptive_choice(motion: f32, blur: f32) -> u32 {
    let side = 2.0 + motion / f32(frame.spp) + 2.0 * blur;
    let k = f32(INTERLEAVE_TILE);
    let interleave = k * k * (1.0 + 1.0 / k) * (1.0 + 1.0 / k);
    if (side * side > ADAPTIVE_INTERLEAVE_BIAS * interleave) {
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

fn raster_triangle_5d(mode: u32, ma: Moving, mb: Moving, mc: Moving, colors: vec3<u32>, counts: ptr<function, SampleCounts>) {
    if (!(ma.usable && mb.usable && mc.usable)) {
        return;
    }
    switch mode {
        case SAMPLING_SIMPLE: {
            raster_simple(ma, mb, mc, colors, counts);
        }
        case SAMPLING_INTERLEAVE: {
            raster_interleave(ma, mb, mc, colors, counts);
        }
        case SAMPLING_INTERVAL: {
            raster_interval(ma, mb, mc, colors, counts);
        }
        default: {
            raster_bbox_5d(ma, mb, mc, colors, counts);
        }
    }
}

// Each grid's largest point motion and circle of confusion (f32 bits; both
// >= 0, so they order like their bits), gathered by the DiceShadeSample
// procedures for Adaptive sampling: words 2 * slot and 2 * slot + 1 for
// the item in `slot` (a workgroup holds up to DICE_SLOTS items).
var<workgroup> grid_extent: array<atomic<u32>, GRID_EXTENT_WORDS>;
