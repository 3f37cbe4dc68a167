// Dicing to a shading rate: edge spacings, grid sizes, grid classes and
// the canonical positions of grid points. Twin of reyes::dicing and of the
// rate parts of reyes::reference::bound, operation for operation. An edge
// spacing is coded in 8 bits: 0 when not fixed, else e + 1 for a vertex
// spacing of 2^-e along the edge's line; a piece's four codes are packed
// in PatchItem::edges (edge k in bits 8k..8k+8, in the order EDGE_V0,
// EDGE_V1, EDGE_U0, EDGE_U1). RATE_ROUNDING, MAX_GRID_QUADS, GRID_CLASS_*
// and DICING_* are generated from the Rust side.

// reyes::dicing::exp2i: 2^e exactly, from its bits.
fn exp2i(e: i32) -> f32 {
    return bitcast<f32>(u32(127 + e) << 23u);
}

// reyes::dicing::level: l of a dyadic extent 2^-l.
fn level_of(extent: f32) -> u32 {
    return 127u - ((bitcast<u32>(extent) >> 23u) & 0xffu);
}

// reyes::dicing::rate_for: the power of two nearest length / side (the
// object's micropolygon side, the square root of its shading rate) in
// ratio, or 0 when it exceeds MAX_GRID_QUADS or the length is not finite.
fn rate_for(length: f32, side: f32) -> u32 {
    let x = length / side;
    if (!is_finite_f32(x)) {
        return 0u;
    }
    var n = 1u;
    // At most log2(MAX_GRID_QUADS) + 1 doublings.
    for (var k = 0u; k < 5u; k += 1u) {
        if (!(f32(n) * RATE_ROUNDING < x)) {
            break;
        }
        n *= 2u;
        if (n > MAX_GRID_QUADS) {
            return 0u;
        }
    }
    return n;
}

// reyes::dicing::polygon_length: the mean of chord and control polygon,
// summed so that the reversed curve gives the same bits.
fn polygon_length(p0: vec2<f32>, p1: vec2<f32>, p2: vec2<f32>, p3: vec2<f32>) -> f32 {
    let polygon = (dist2(p0, p1) + dist2(p2, p3)) + dist2(p1, p2);
    return 0.5 * (dist2(p0, p3) + polygon);
}

// reyes::dicing::fresh_spacing: the code of an edge measured afresh at
// `level` (0 when it cannot be projected or needs more than the largest grid).
fn fresh_spacing(length: f32, projectable: bool, level: u32, side: f32) -> u32 {
    if (!projectable) {
        return 0u;
    }
    let n = rate_for(length, side);
    if (n == 0u) {
        return 0u;
    }
    return level + countTrailingZeros(n) + 1u;
}

// reyes::dicing::halved_spacing: a fixed parent spacing is kept.
fn halved_spacing(parent: u32, length: f32, projectable: bool, level: u32, side: f32) -> u32 {
    if (parent != 0u) {
        return parent;
    }
    return fresh_spacing(length, projectable, level, side);
}

fn edge_code(edges: u32, edge: u32) -> u32 {
    return (edges >> (8u * edge)) & 0xffu;
}

// reyes::dicing::EdgeSpacing::quads: micropolygons along an edge of length
// 2^-level, -1 when not fixed.
fn edge_quads(code: u32, level: u32) -> i32 {
    if (code == 0u) {
        return -1;
    }
    let e = code - 1u;
    if (e >= level) {
        return i32(1u << (e - level));
    }
    return 0;
}

// Point k (0..4) of row `r` or column `c` of a piece's 16 points.
fn row_index(r: u32, k: u32) -> u32 {
    return r * 4u + k;
}

fn column_index(c: u32, k: u32) -> u32 {
    return k * 4u + c;
}

// A piece's 16 control points on screen (reyes::reference::bound::
// ScreenPiece): pixel positions, the screen growth of the displacement
// bound at each, and a bit per point that projects.
struct ScreenPiece {
    pixels: array<vec2<f32>, 16>,
    growths: array<f32, 16>,
    projectable: u32,
}

// reyes::reference::bound::line_length of row or column `line`: its
// projected polygon plus twice its largest growth, capped at
// DISPLACED_DICE_FRACTION of the largest grid's side.
fn line_length(screen: ptr<function, ScreenPiece>, along_u: bool, line: u32, side: f32) -> f32 {
    let i0 = line_index(along_u, line, 0u);
    let i1 = line_index(along_u, line, 1u);
    let i2 = line_index(along_u, line, 2u);
    let i3 = line_index(along_u, line, 3u);
    let growth = max(max((*screen).growths[i0], (*screen).growths[i1]), max((*screen).growths[i2], (*screen).growths[i3]));
    let cap = DISPLACED_DICE_FRACTION * f32(MAX_GRID_QUADS) * side;
    return polygon_length((*screen).pixels[i0], (*screen).pixels[i1], (*screen).pixels[i2], (*screen).pixels[i3]) + min(2.0 * growth, cap);
}

// Whether every point of row or column `line` projects (bit i of
// `projectable` is point i's).
fn line_projects(projectable: u32, along_u: bool, line: u32) -> bool {
    var mask = 0u;
    for (var k = 0u; k < 4u; k += 1u) {
        mask |= 1u << line_index(along_u, line, k);
    }
    return (projectable & mask) == mask;
}

// The line (row or column) of edge `edge`: rows 0 and 3 run along u.
fn edge_along_u(edge: u32) -> bool {
    return edge < EDGE_U0;
}

fn edge_line(edge: u32) -> u32 {
    return select(select(3u, 0u, edge == EDGE_U0), select(3u, 0u, edge == EDGE_V0), edge < EDGE_U0);
}

// The fresh spacing of edge `edge` of a piece at `level`.
fn measured_spacing(screen: ptr<function, ScreenPiece>, edge: u32, level: u32, side: f32) -> u32 {
    let along_u = edge_along_u(edge);
    let line = edge_line(edge);
    return fresh_spacing(line_length(screen, along_u, line, side), line_projects((*screen).projectable, along_u, line), level, side);
}

// reyes::reference::bound::input_edges: every edge afresh at level 0.
fn input_edges(screen: ptr<function, ScreenPiece>, side: f32) -> u32 {
    var edges = 0u;
    for (var edge = 0u; edge < 4u; edge += 1u) {
        edges |= measured_spacing(screen, edge, 0u, side) << (8u * edge);
    }
    return edges;
}

// reyes::reference::bound::split_edges: the halved edges keep fixed
// spacings, the split line is measured afresh, the fourth edge is the
// parent's. `uv` is the half's rectangle.
fn split_edges(parent: u32, along_u: bool, half: u32, screen: ptr<function, ScreenPiece>, uv: vec4<f32>, side: f32) -> u32 {
    let lu = level_of(uv.z - uv.x);
    let lv = level_of(uv.w - uv.y);
    var halved_a = EDGE_U0;
    var halved_b = EDGE_U1;
    var level_halved = lv;
    var split_line = select(EDGE_V0, EDGE_V1, half == 0u);
    var level_split = lu;
    if (along_u) {
        halved_a = EDGE_V0;
        halved_b = EDGE_V1;
        level_halved = lu;
        split_line = select(EDGE_U0, EDGE_U1, half == 0u);
        level_split = lv;
    }
    var edges = parent;
    for (var edge = 0u; edge < 4u; edge += 1u) {
        var code = edge_code(parent, edge);
        if (edge == halved_a || edge == halved_b) {
            if (code == 0u) {
                code = measured_spacing(screen, edge, level_halved, side);
            }
        } else if (edge == split_line) {
            code = measured_spacing(screen, edge, level_split, side);
        }
        edges = (edges & ~(0xffu << (8u * edge))) | (code << (8u * edge));
    }
    return edges;
}

// reyes::reference::bound::rate_grid: (nu, nv) of a projectable piece, 0
// in a direction that must be split.
fn rate_grid(screen: ptr<function, ScreenPiece>, edges: u32, uv: vec4<f32>, side: f32) -> vec2<u32> {
    let rows = max(max(line_length(screen, true, 0u, side), line_length(screen, true, 1u, side)), max(line_length(screen, true, 2u, side), line_length(screen, true, 3u, side)));
    let columns = max(max(line_length(screen, false, 0u, side), line_length(screen, false, 1u, side)), max(line_length(screen, false, 2u, side), line_length(screen, false, 3u, side)));
    return vec2<u32>(
        rate_direction(rows, edge_code(edges, EDGE_V0), edge_code(edges, EDGE_V1), level_of(uv.z - uv.x), side),
        rate_direction(columns, edge_code(edges, EDGE_U0), edge_code(edges, EDGE_U1), level_of(uv.w - uv.y), side),
    );
}

fn rate_direction(length: f32, a: u32, b: u32, level: u32, side: f32) -> u32 {
    let need = rate_for(length, side);
    let qa = edge_quads(a, level);
    let qb = edge_quads(b, level);
    if (need == 0u || qa < 0 || qb < 0) {
        return 0u;
    }
    let n = max(need, u32(max(qa, qb)));
    return select(0u, n, n <= MAX_GRID_QUADS);
}

// The grid a piece is diced into: rate dicing's, or the fixed 15 x 15.
fn piece_grid(screen: ptr<function, ScreenPiece>, edges: u32, uv: vec4<f32>, side: f32) -> vec2<u32> {
    if (frame.dicing == DICING_RATE) {
        return rate_grid(screen, edges, uv, side);
    }
    return vec2<u32>(FIXED_GRID_QUADS, FIXED_GRID_QUADS);
}

// reyes::dicing::GridSize::class: the smallest dice procedure that holds it.
fn grid_class(nu: u32, nv: u32) -> u32 {
    let quads = nu * nv;
    let points = (nu + 1u) * (nv + 1u);
    if (quads <= GRID_CLASS_SMALL_THREADS && points <= GRID_CLASS_SMALL_POINTS) {
        return GRID_CLASS_SMALL;
    }
    if (quads <= GRID_CLASS_MEDIUM_THREADS && points <= GRID_CLASS_MEDIUM_POINTS) {
        return GRID_CLASS_MEDIUM;
    }
    return GRID_CLASS_LARGE;
}

// ------------------------------------------------------------ grid points

// reyes::dicing::grid_param.
fn grid_param(a: f32, b: f32, i: u32, n: u32) -> f32 {
    return a + (b - a) * (f32(i) / f32(n));
}

// The input patch `index` in world space, from its 48 floats after the
// scene's other floats in height_texels: as stored, or placed by the
// object's placement when the object shares its model's patches
// (reyes::prepare::PatchStore).
fn load_patch(index: u32, object: Object) -> array<f32, 48> {
    var q: array<f32, 48>;
    let base = frame.patch_floats + 48u * index;
    for (var k = 0u; k < 48u; k += 1u) {
        q[k] = height_texels[base + k];
    }
    if (object.placed != 0u) {
        for (var k = 0u; k < 48u; k += 3u) {
            let placed = object.placement * vec4<f32>(q[k], q[k + 1u], q[k + 2u], 1.0);
            q[k] = placed.x;
            q[k + 1u] = placed.y;
            q[k + 2u] = placed.z;
        }
    }
    return q;
}

// reyes::dicing::curve_canonical: a cubic from its lexicographically
// smaller end.
fn curve_canonical(c0: vec3<f32>, c1: vec3<f32>, c2: vec3<f32>, c3: vec3<f32>, t: f32) -> vec3<f32> {
    let reversed = c3.x < c0.x || (c3.x == c0.x && (c3.y < c0.y || (c3.y == c0.y && c3.z < c0.z)));
    if (reversed) {
        let w = bernstein(1.0 - t);
        return ((c3 * w.x + c2 * w.y) + c1 * w.z) + c0 * w.w;
    }
    let w = bernstein(t);
    return ((c0 * w.x + c1 * w.y) + c2 * w.z) + c3 * w.w;
}

// reyes::dicing::patch_position: boundary points on their boundary curve,
// the rest from the tensor product.
fn patch_position(q: ptr<function, array<f32, 48>>, u: f32, v: f32) -> vec3<f32> {
    if (u == 0.0 || u == 1.0) {
        let c = select(3u, 0u, u == 0.0);
        return curve_canonical(patch_point(q, c), patch_point(q, 4u + c), patch_point(q, 8u + c), patch_point(q, 12u + c), v);
    }
    if (v == 0.0 || v == 1.0) {
        let r = select(12u, 0u, v == 0.0);
        return curve_canonical(patch_point(q, r), patch_point(q, r + 1u), patch_point(q, r + 2u), patch_point(q, r + 3u), u);
    }
    return tensor(q, bernstein(u), bernstein(v));
}

// reyes::dicing::border_point: where border point (i, j) at (u, v) goes.
// A corner between two vertices of its edge goes on their chord: a and b
// with the fraction f in (0, 1). Any other border point between two
// vertices snaps to the nearer one (the upper one at the middle), so that
// the finer side's border is made of the coarser side's very vertices
// rather than of points a rounding off its chord: a == b, f == 0. f == -1
// when the point stays in place.
struct Chord {
    a: vec2<f32>,
    b: vec2<f32>,
    f: f32,
}

fn border_chord(nu: u32, nv: u32, edges: u32, i: u32, j: u32, u: f32, v: f32) -> Chord {
    let on_edge = vec4<bool>(j == 0u, j == nv, i == 0u, i == nu);
    let corner = (on_edge.x || on_edge.y) && (on_edge.z || on_edge.w);
    for (var edge = 0u; edge < 4u; edge += 1u) {
        let code = edge_code(edges, edge);
        if (!on_edge[edge] || code == 0u) {
            continue;
        }
        let e = i32(code - 1u);
        let along_u = edge_along_u(edge);
        let q = select(v, u, along_u);
        let scaled = q * exp2i(e);
        let below = floor(scaled);
        if (below == scaled) {
            continue;
        }
        let h = exp2i(-e);
        let q0 = below * h;
        let q1 = (below + 1.0) * h;
        let f = scaled - below;
        var a = vec2<f32>(u, q0);
        var b = vec2<f32>(u, q1);
        if (along_u) {
            a = vec2<f32>(q0, v);
            b = vec2<f32>(q1, v);
        }
        if (corner) {
            return Chord(a, b, f);
        }
        let nearer = select(b, a, f < 0.5);
        return Chord(nearer, nearer, 0.0);
    }
    return Chord(vec2<f32>(0.0), vec2<f32>(0.0), -1.0);
}

// reyes::aov::depth_color (one channel).
fn depth_color(w: f32) -> vec3<f32> {
    return vec3<f32>(clamp(1.0 - w / frame.depth_range, 0.0, 1.0));
}

// reyes::dicing::chord_point.
fn chord_point(a: vec3<f32>, b: vec3<f32>, f: f32) -> vec3<f32> {
    return a + (b - a) * f;
}
