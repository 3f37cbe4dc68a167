//! Regular faces: where the limit surface over a quad is the uniform
//! bicubic B-spline of its 4 x 4 neighbourhood, and that patch in Bezier
//! form.
//!
//! A quad is regular when each of its corners is one of:
//! * an interior vertex of valence 4 with no sharp edge;
//! * a vertex on an infinitely sharp line (a boundary or a crease) with
//!   exactly the two sharp edges, one of them an edge of the quad, and two
//!   faces on the quad's side of the line: the neighbourhood across the line
//!   is the reflection `p' = 2 b - p` of the inner points `p` through the
//!   points `b` on the line, which makes the B-spline follow the crease
//!   rules exactly;
//! * an infinitely sharp corner whose two sharp edges are the quad's own:
//!   reflected across both edges.
//!
//! and no edge or vertex around it is semi-sharp. Children of a regular
//! face are regular again, so its limit is that B-spline.

use glam::Vec3;

use super::level::{Level, is_infinite};

/// The 3 x 3 neighbourhood of a corner `v` of a quad, `[y + 1][x + 1]`,
/// with `x` towards the quad's next vertex and `y` towards its previous.
type Block = [[Vec3; 3]; 3];

/// The B-spline control points of quad `f` (`[j * 4 + i]`, `i` along
/// `v0 -> v1`), if the quad is regular.
pub(super) fn bspline_points(level: &Level, f: u32) -> Option<[Vec3; 16]> {
    let quad = level.quad(f);
    // Corner k sits at `origin`, its x axis along `x` and y along `y`.
    type Frame = ((i32, i32), (i32, i32), (i32, i32));
    const FRAMES: [Frame; 4] = [
        ((1, 1), (1, 0), (0, 1)),
        ((2, 1), (0, 1), (-1, 0)),
        ((2, 2), (-1, 0), (0, -1)),
        ((1, 2), (0, -1), (1, 0)),
    ];
    let mut grid = [Vec3::ZERO; 16];
    for (k, &(origin, ax, ay)) in FRAMES.iter().enumerate() {
        let block = corner_block(level, quad, k)?;
        for y in -1..=1i32 {
            for x in -1..=1i32 {
                let i = origin.0 + x * ax.0 + y * ay.0;
                let j = origin.1 + x * ax.1 + y * ay.1;
                grid[(j * 4 + i) as usize] = block[(y + 1) as usize][(x + 1) as usize];
            }
        }
    }
    Some(grid)
}

/// The neighbourhood of corner `k` of `quad`, if that corner is regular.
fn corner_block(level: &Level, quad: [u32; 4], k: usize) -> Option<Block> {
    let v = quad[k];
    let next = quad[(k + 1) % 4];
    let diag = quad[(k + 2) % 4];
    let prev = quad[(k + 3) % 4];
    let vertex_sharpness = level.vertex_sharpness[v as usize];
    if vertex_sharpness > 0.0 && !is_infinite(vertex_sharpness) {
        return None;
    }
    let edges = level.edges_of(v);
    if edges.iter().any(|&(_, s)| s > 0.0 && !is_infinite(s)) {
        return None;
    }
    let sharp_count = edges.iter().filter(|&&(_, s)| s > 0.0).count();
    let corner = is_infinite(vertex_sharpness) || sharp_count > 2;
    let sharp_next = is_infinite(level.sharpness(v, next));
    let sharp_prev = is_infinite(level.sharpness(prev, v));
    let p = |i: u32| level.positions[i as usize];
    let (pv, pn, pd, pp) = (p(v), p(next), p(diag), p(prev));
    let mut b = [[Vec3::ZERO; 3]; 3];
    b[1][1] = pv;
    b[1][2] = pn;
    b[2][1] = pp;
    b[2][2] = pd;
    match (sharp_next, sharp_prev) {
        (false, false) => {
            if corner || sharp_count != 0 || edges.len() != 4 || level.faces_of(v).len() != 4 {
                return None;
            }
            let (g, j) = level.face_with_edge(next, v)?;
            let g = level.quad(g);
            b[0][1] = p(g[(j + 2) % 4]);
            b[0][2] = p(g[(j + 3) % 4]);
            let (kf, i) = level.face_with_edge(v, prev)?;
            let kq = level.quad(kf);
            b[2][0] = p(kq[(i + 2) % 4]);
            b[1][0] = p(kq[(i + 3) % 4]);
            let (d, m) = level.face_with_edge(g[(j + 2) % 4], v)?;
            b[0][0] = p(level.quad(d)[(m + 3) % 4]);
        }
        (true, false) => {
            if corner || sharp_count != 2 {
                return None;
            }
            let (kf, i) = level.face_with_edge(v, prev)?;
            let kq = level.quad(kf);
            if !is_infinite(level.sharpness(v, kq[(i + 3) % 4])) {
                return None;
            }
            b[2][0] = p(kq[(i + 2) % 4]);
            b[1][0] = p(kq[(i + 3) % 4]);
            b[0][1] = pv * 2.0 - pp;
            b[0][2] = pn * 2.0 - pd;
            b[0][0] = b[1][0] * 2.0 - b[2][0];
        }
        (false, true) => {
            if corner || sharp_count != 2 {
                return None;
            }
            let (g, j) = level.face_with_edge(next, v)?;
            let g = level.quad(g);
            if !is_infinite(level.sharpness(v, g[(j + 2) % 4])) {
                return None;
            }
            b[0][1] = p(g[(j + 2) % 4]);
            b[0][2] = p(g[(j + 3) % 4]);
            b[1][0] = pv * 2.0 - pn;
            b[2][0] = pp * 2.0 - pd;
            b[0][0] = b[0][1] * 2.0 - b[0][2];
        }
        (true, true) => {
            if !corner {
                return None;
            }
            b[0][1] = pv * 2.0 - pp;
            b[0][2] = pn * 2.0 - pd;
            b[1][0] = pv * 2.0 - pn;
            b[2][0] = pp * 2.0 - pd;
            b[0][0] = b[1][0] * 2.0 - b[2][0];
        }
    }
    Some(b)
}

/// The uniform cubic B-spline segment over its middle span in Bezier form:
/// row `r` of this matrix weighs the four B-spline points.
const BSPLINE_TO_BEZIER: [[f32; 4]; 4] = [
    [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0, 0.0],
    [0.0, 4.0 / 6.0, 2.0 / 6.0, 0.0],
    [0.0, 2.0 / 6.0, 4.0 / 6.0, 0.0],
    [0.0, 1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0],
];

/// The Bezier control points (`points[v * 4 + u]`) of the bicubic B-spline
/// patch with control points `grid` (same layout).
pub(super) fn bspline_to_bezier(grid: &[Vec3; 16]) -> [Vec3; 16] {
    let mut rows = [Vec3::ZERO; 16];
    for j in 0..4 {
        for (r, weights) in BSPLINE_TO_BEZIER.iter().enumerate() {
            rows[j * 4 + r] = (0..4).map(|c| grid[j * 4 + c] * weights[c]).sum();
        }
    }
    let mut out = [Vec3::ZERO; 16];
    for i in 0..4 {
        for (r, weights) in BSPLINE_TO_BEZIER.iter().enumerate() {
            out[r * 4 + i] = (0..4).map(|c| rows[c * 4 + i] * weights[c]).sum();
        }
    }
    out
}
