//! The faces still irregular at the deepest level (those at extraordinary
//! vertices, at darts, where creases bend or meet): a Bezier patch through
//! limit positions, and the measured distance from it to the limit surface.
//!
//! The patch over such a face interpolates the limit positions of the
//! face's corners, edge points and face point one level down (the surface
//! at `u, v` in `{0, 1/2, 1}`), biquadratically, raised to bicubic. Its
//! boundary curve over an edge depends only on the three points on that
//! edge, so the two faces on an edge agree (the stitching makes them agree
//! bit for bit). The error is measured against the limit positions of the
//! vertices three levels down (a 9 x 9 grid of `u, v` per face).

use glam::Vec3;

use super::level::Level;
use crate::bezier;

/// The vertices, `depth` levels below `levels[level]`, on the `(2^depth +
/// 1)^2` grid of quad `f`: `[j * n + i]`, `i` along `v0 -> v1`. The levels
/// below must have refined the quad that deep.
pub(super) fn vertex_grid(levels: &[Level], level: usize, f: u32, depth: usize) -> Vec<u32> {
    let q = levels[level].quad(f);
    let mut n = 2;
    let mut grid = vec![q[0], q[1], q[3], q[2]];
    for d in 0..depth {
        let (parent, child) = (&levels[level + d], &levels[level + d + 1]);
        let m = 2 * n - 1;
        let mut next = vec![0u32; m * m];
        for j in 0..n {
            for i in 0..n {
                let v = grid[j * n + i];
                next[2 * j * m + 2 * i] = child.from_vertex[&v];
                if i + 1 < n {
                    let w = grid[j * n + i + 1];
                    next[2 * j * m + 2 * i + 1] = child.from_edge[&super::level::edge(v, w)];
                    if j + 1 < n {
                        let (face, _) = parent
                            .face_with_edge(v, w)
                            .expect("a grid cell is a face of its level");
                        next[(2 * j + 1) * m + 2 * i + 1] = child.from_face[&face];
                    }
                }
                if j + 1 < n {
                    let w = grid[(j + 1) * n + i];
                    next[(2 * j + 1) * m + 2 * i] = child.from_edge[&super::level::edge(v, w)];
                }
            }
        }
        grid = next;
        n = m;
    }
    grid
}

/// The limit position of complete vertex `v`, for a level where every
/// sharpness is 0 or infinite and every face is a quad.
pub(super) fn limit_position(level: &Level, v: u32) -> Vec3 {
    let p = level.positions[v as usize];
    let edges = level.edges_of(v);
    let sharp: Vec<Vec3> = edges
        .iter()
        .filter(|e| e.1 > 0.0)
        .map(|e| level.positions[e.0 as usize])
        .collect();
    if level.vertex_sharpness[v as usize] > 0.0 || sharp.len() > 2 {
        return p;
    }
    if let [a, b] = sharp[..] {
        return (a + p * 4.0 + b) / 6.0;
    }
    let faces = level.faces_of(v);
    let n = faces.len() as f32;
    let mut edge_sum = Vec3::ZERO;
    let mut diagonal_sum = Vec3::ZERO;
    for &f in faces {
        let q = level.quad(f);
        let k = level.corner_of(f, v);
        edge_sum += level.positions[q[(k + 1) % 4] as usize];
        diagonal_sum += level.positions[q[(k + 2) % 4] as usize];
    }
    (p * (n * n) + edge_sum * 4.0 + diagonal_sum) / (n * (n + 5.0))
}

/// The bicubic Bezier points of the biquadratic through the 3 x 3 limit
/// positions `q` (`[j * 3 + i]`, at `u, v` in `{0, 1/2, 1}`).
pub(super) fn biquadratic_patch(q: &[Vec3; 9]) -> [Vec3; 16] {
    // Through p0, pm, p1 at 0, 1/2, 1, as a cubic: p0, (4 pm - p1) / 3,
    // (4 pm - p0) / 3, p1.
    let raise = |p0: Vec3, pm: Vec3, p1: Vec3| -> [Vec3; 4] {
        [p0, (pm * 4.0 - p1) / 3.0, (pm * 4.0 - p0) / 3.0, p1]
    };
    let mut rows = [[Vec3::ZERO; 4]; 3];
    for (j, row) in rows.iter_mut().enumerate() {
        *row = raise(q[j * 3], q[j * 3 + 1], q[j * 3 + 2]);
    }
    let mut out = [Vec3::ZERO; 16];
    for i in 0..4 {
        let column = raise(rows[0][i], rows[1][i], rows[2][i]);
        for (j, &p) in column.iter().enumerate() {
            out[j * 4 + i] = p;
        }
    }
    out
}

/// The patch approximating quad `f` of `levels[level]` (the level below
/// must have refined it).
pub(super) fn approximate_patch(levels: &[Level], level: usize, f: u32) -> [Vec3; 16] {
    let grid = vertex_grid(levels, level, f, 1);
    let below = &levels[level + 1];
    let q: [Vec3; 9] = std::array::from_fn(|i| limit_position(below, grid[i]));
    biquadratic_patch(&q)
}

/// How deep [`patch_error`] looks below the patch's level.
pub(super) const MEASURE_DEPTH: usize = 3;

/// The largest distance between `points` (the patch over quad `f` of
/// `levels[level]`) and the limit positions of the quad's vertices
/// [`MEASURE_DEPTH`] levels down, each compared with the patch at its
/// own `u, v`.
pub(super) fn patch_error(levels: &[Level], level: usize, f: u32, points: &[Vec3; 16]) -> f32 {
    let grid = vertex_grid(levels, level, f, MEASURE_DEPTH);
    let below = &levels[level + MEASURE_DEPTH];
    let n = (1usize << MEASURE_DEPTH) + 1;
    let mut worst = 0.0f32;
    for j in 0..n {
        for i in 0..n {
            let limit = limit_position(below, grid[j * n + i]);
            let (u, v) = (i as f32 / (n - 1) as f32, j as f32 / (n - 1) as f32);
            worst = worst.max((bezier::position(points, u, v) - limit).length());
        }
    }
    worst
}
