// Micropolygons as quads (reyes::reference::quad, operation for
// operation): the quad (a, b, c, d) is split along its 0-2 diagonal into
// the triangles (a, b, c) and (a, c, d); a sample is tested once per quad,
// with five edge functions, the diagonal's shared by both triangles, and
// only the samples of the strata its box touches are tested. Also the
// still bbox and nearest paths (reyes::reference::raster).

// The sample strata [x0, x1] x [y0, y1] (stratum columns and rows of this
// image, k per pixel) a box in the full image's pixels touches, clamped to
// the frame (reference StrataBox). A screen tile's strata are the full
// image's less the tile's origin: integers, subtracted exactly.
struct StrataBox {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
    ok: bool,
}

fn strata_box(lo: vec2<f32>, hi: vec2<f32>) -> StrataBox {
    let kf = f32(frame.k);
    let ox = f32(frame.origin_x * frame.k);
    let oy = f32(frame.origin_y * frame.k);
    // Clamped in float first, so the integer conversions are always in range.
    let x0 = max(floor((lo.x - STRATUM_MARGIN) * kf) - ox, 0.0);
    let y0 = max(floor((lo.y - STRATUM_MARGIN) * kf) - oy, 0.0);
    let x1 = min(floor((hi.x + STRATUM_MARGIN) * kf) - ox, f32(frame.width * frame.k) - 1.0);
    let y1 = min(floor((hi.y + STRATUM_MARGIN) * kf) - oy, f32(frame.height * frame.k) - 1.0);
    if (!(x0 <= x1 && y0 <= y1)) {
        return StrataBox(0u, 0u, 0u, 0u, false);
    }
    return StrataBox(u32(x0), u32(y0), u32(x1), u32(y1), true);
}

// Sample n of the box's strata, row by row: (x, y, s).
fn strata_count(b: StrataBox) -> u32 {
    return (b.x1 - b.x0 + 1u) * (b.y1 - b.y0 + 1u);
}

fn strata_sample(b: StrataBox, n: u32) -> vec3<u32> {
    let k = frame.k;
    let nx = b.x1 - b.x0 + 1u;
    let gx = b.x0 + n % nx;
    let gy = b.y0 + n / nx;
    return vec3<u32>(gx / k, gy / k, (gy % k) * k + gx % k);
}

// Whether sample s of pixel (x, y) lies in one of the box's strata.
fn strata_hold(b: StrataBox, x: u32, y: u32, s: u32) -> bool {
    let gx = x * frame.k + s % frame.k;
    let gy = y * frame.k + s / frame.k;
    return gx >= b.x0 && gx <= b.x1 && gy >= b.y0 && gy <= b.y1;
}

// The pixels p with p * k + offset in [first, last] (reference span_of).
struct Span {
    first: u32,
    last: u32,
    ok: bool,
}

fn span_of(first: u32, last: u32, offset: u32) -> Span {
    let k = frame.k;
    if (last < offset) {
        return Span(0u, 0u, false);
    }
    let lo = (first + k - 1u - offset) / k;
    let hi = (last - offset) / k;
    return Span(lo, hi, lo <= hi);
}

// One of a quad's triangles, oriented so that its area is positive
// (reference Triangle); `ok` is false when it is not drawn.
struct Tri {
    a: vec3<f32>,
    b: vec3<f32>,
    c: vec3<f32>,
    colors: vec3<u32>,
    area: f32,
    // The diagonal's far end is b (the diagonal is the edge a -> b), not c.
    c_second: bool,
    ok: bool,
}

fn make_tri(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, colors: vec3<u32>, c_is_third: bool, drawn: bool) -> Tri {
    let area = edge(a.xy, b.xy, c.xy);
    if (!drawn || area == 0.0 || !is_finite_f32(area)) {
        return Tri(a, b, c, colors, 0.0, false, false);
    }
    if (area < 0.0) {
        return Tri(a, c, b, colors.xzy, -area, c_is_third, true);
    }
    return Tri(a, b, c, colors, area, !c_is_third, true);
}

// A micropolygon's triangles (a, b, c) and (a, c, d) at one position.
struct Quad {
    t0: Tri,
    t1: Tri,
    diagonal_a: vec2<f32>,
    diagonal_c: vec2<f32>,
}

fn make_quad(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, d: vec3<f32>, colors: vec4<u32>, drawn: vec2<bool>) -> Quad {
    return Quad(
        make_tri(a, b, c, colors.xyz, true, drawn.x),
        make_tri(a, c, d, colors.xzw, false, drawn.y),
        a.xy,
        c.xy,
    );
}

// A screen box; `ok` is false when it holds nothing.
struct Bounds {
    lo: vec2<f32>,
    hi: vec2<f32>,
    ok: bool,
}

fn no_bounds() -> Bounds {
    return Bounds(vec2<f32>(0.0), vec2<f32>(0.0), false);
}

fn bounds_add(b: Bounds, p: vec2<f32>) -> Bounds {
    if (!b.ok) {
        return Bounds(p, p, true);
    }
    return Bounds(min(p, b.lo), max(p, b.hi), true);
}

fn tri_bounds(b: Bounds, t: Tri) -> Bounds {
    if (!t.ok) {
        return b;
    }
    return bounds_add(bounds_add(bounds_add(b, t.a.xy), t.b.xy), t.c.xy);
}

// The box of the drawn triangles (reference Quad::bounds).
fn quad_bounds(q: Quad) -> Bounds {
    return tri_bounds(tri_bounds(no_bounds(), q.t0), q.t1);
}

// Offers sample s of pixel (x, y), at p, the fragment of t if p is inside
// (reference Triangle::fragment_at); `diagonal` is edge(a, c, p).
fn tri_offer(t: Tri, p: vec2<f32>, diagonal: f32, x: u32, y: u32, s: u32) -> bool {
    let a = t.a.xy;
    let b = t.b.xy;
    let c = t.c.xy;
    let e_bc = edge(b, c, p);
    var e_ca = -diagonal;
    var e_ab = diagonal;
    if (t.c_second) {
        e_ca = edge(c, a, p);
    } else {
        e_ab = edge(a, b, p);
    }
    if (inside(e_bc, b, c) && inside(e_ca, c, a) && inside(e_ab, a, b)) {
        let z = (e_bc * t.a.z + e_ca * t.b.z + e_ab * t.c.z) / t.area;
        offer(x, y, s, z, blend_rgb10(t.colors, vec3<f32>(e_bc, e_ca, e_ab), t.area));
        return true;
    }
    return false;
}

// Tests sample s of pixel (x, y) once against both triangles of q (reference
// Quad::test), offering a fragment for each it is inside.
fn test_quad(q: Quad, x: u32, y: u32, s: u32, counts: ptr<function, SampleCounts>) {
    (*counts).tested += 1u;
    let p = sample_position(x, y, s);
    let diagonal = edge(q.diagonal_a, q.diagonal_c, p);
    var hit = false;
    if (q.t0.ok) {
        hit = tri_offer(q.t0, p, diagonal, x, y, s);
    }
    if (q.t1.ok) {
        hit = tri_offer(q.t1, p, diagonal, x, y, s) || hit;
    }
    if (hit) {
        (*counts).hit += 1u;
    }
}

fn loop_cut() {
    atomicAdd(&stats[STAT_LOOPS_CUT], 1u);
}

// reyes::reference::raster::still_quad: a triangle is drawn when `drawn`
// says so and its corners (px, py, depth, clip w) are usable.
fn still_quad(a: vec4<f32>, b: vec4<f32>, c: vec4<f32>, d: vec4<f32>, colors: vec4<u32>, drawn: vec2<bool>) -> Quad {
    let ua = usable(a);
    let uc = usable(c);
    return make_quad(a.xyz, b.xyz, c.xyz, d.xyz, colors, vec2<bool>(drawn.x && ua && usable(b) && uc, drawn.y && ua && uc && usable(d)));
}

// reyes::reference::raster::raster_quad (bbox mode): every sample of the
// strata the box touches, as one loop over strata; a loop the driver cut
// short is detected (n < total afterwards) and counted, never silently
// ignored.
fn raster_quad(q: Quad, counts: ptr<function, SampleCounts>) {
    let bounds = quad_bounds(q);
    if (!bounds.ok) {
        return;
    }
    let strata = strata_box(bounds.lo, bounds.hi);
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
        test_quad(q, sample.x, sample.y, sample.z, counts);
        n += 1u;
    }
    if (n < total) {
        loop_cut();
    }
}

// reyes::reference::raster::raster_nearest: the sample whose stratum holds
// the centroid of the 4 corners, written if it lies inside q.
fn raster_nearest(a: vec4<f32>, b: vec4<f32>, c: vec4<f32>, d: vec4<f32>, q: Quad, counts: ptr<function, SampleCounts>) {
    if (!(a.w > NEAR_EPS && b.w > NEAR_EPS && c.w > NEAR_EPS && d.w > NEAR_EPS)) {
        return;
    }
    let centroid = (((a.xyz + b.xyz) + c.xyz) + d.xyz) * 0.25;
    // The window of the full image this frame covers (all of it, or a tile).
    let x0 = f32(frame.origin_x);
    let y0 = f32(frame.origin_y);
    let on_screen = centroid.x >= x0 && centroid.x < x0 + f32(frame.width) && centroid.y >= y0 && centroid.y < y0 + f32(frame.height);
    if (!on_screen) {
        return;
    }
    let k = frame.k;
    let gx = min(u32(floor(centroid.x * f32(k)) - x0 * f32(k)), frame.width * k - 1u);
    let gy = min(u32(floor(centroid.y * f32(k)) - y0 * f32(k)), frame.height * k - 1u);
    test_quad(q, gx / k, gy / k, (gy % k) * k + gx % k, counts);
}
