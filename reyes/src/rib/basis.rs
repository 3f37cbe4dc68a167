//! Spline bases (`Basis`) and the exact change of basis of `Patch` and
//! `PatchMesh` control points to bicubic Bezier patches.
//!
//! A RenderMan bicubic patch is `P(u, v) = U Bu G Bv^T V^T` with
//! `U = [u^3 u^2 u 1]` and `G[i][j]` the control point in column `i` (u)
//! and row `j` (v). With `Mb` the Bezier basis, the same surface has the
//! Bezier control points `Mb^-1 Bu G Bv^T Mb^-T`: exact, whatever the basis.

use glam::DVec3;

/// A 4x4 basis matrix (row-major, as in `RtBasis`) and its step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Basis {
    /// The matrix, `m[row][col]`, rows for `u^3, u^2, u, 1`.
    pub m: [[f64; 4]; 4],
    /// How many control points to advance from one patch of a mesh to the next.
    pub step: usize,
}

/// The Bezier basis (step 3).
pub const BEZIER: Basis = Basis {
    m: [
        [-1.0, 3.0, -3.0, 1.0],
        [3.0, -6.0, 3.0, 0.0],
        [-3.0, 3.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
    ],
    step: 3,
};

const S6: f64 = 1.0 / 6.0;
/// The uniform cubic B-spline basis (step 1).
pub const B_SPLINE: Basis = Basis {
    m: [
        [-S6, 3.0 * S6, -3.0 * S6, S6],
        [3.0 * S6, -6.0 * S6, 3.0 * S6, 0.0],
        [-3.0 * S6, 0.0, 3.0 * S6, 0.0],
        [S6, 4.0 * S6, S6, 0.0],
    ],
    step: 1,
};

/// The Catmull-Rom basis (step 1).
pub const CATMULL_ROM: Basis = Basis {
    m: [
        [-0.5, 1.5, -1.5, 0.5],
        [1.0, -2.5, 2.0, -0.5],
        [-0.5, 0.0, 0.5, 0.0],
        [0.0, 1.0, 0.0, 0.0],
    ],
    step: 1,
};

/// The Hermite basis (step 2): control points `P0, T0, P1, T1`.
pub const HERMITE: Basis = Basis {
    m: [
        [2.0, 1.0, -2.0, 1.0],
        [-3.0, -2.0, 3.0, -1.0],
        [0.0, 1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0, 0.0],
    ],
    step: 2,
};

/// The power basis (step 4): control points are the polynomial coefficients.
pub const POWER: Basis = Basis {
    m: [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ],
    step: 4,
};

/// The inverse of the Bezier basis matrix.
const BEZIER_INVERSE: [[f64; 4]; 4] = [
    [0.0, 0.0, 0.0, 1.0],
    [0.0, 0.0, 1.0 / 3.0, 1.0],
    [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0],
    [1.0, 1.0, 1.0, 1.0],
];

/// A basis by its RenderMan name, with its default step.
pub fn named(name: &str) -> Option<Basis> {
    Some(match name {
        "bezier" => BEZIER,
        "b-spline" | "bspline" => B_SPLINE,
        "catmull-rom" | "catmullrom" => CATMULL_ROM,
        "hermite" => HERMITE,
        "power" => POWER,
        _ => return None,
    })
}

impl Basis {
    /// `U B`: the weights of the four control points at `u`.
    pub fn weights(&self, u: f64) -> [f64; 4] {
        let pu = [u * u * u, u * u, u, 1.0];
        let mut w = [0.0; 4];
        for (k, wk) in w.iter_mut().enumerate() {
            *wk = (0..4).map(|r| pu[r] * self.m[r][k]).sum();
        }
        w
    }

    /// `Mb^-1 B`: Bezier control point `i` is `sum_k c[i][k] G[k]`.
    fn bezier_change(self) -> [[f64; 4]; 4] {
        let mut c = [[0.0; 4]; 4];
        for (i, row) in c.iter_mut().enumerate() {
            for (k, ck) in row.iter_mut().enumerate() {
                *ck = (0..4).map(|r| BEZIER_INVERSE[i][r] * self.m[r][k]).sum();
            }
        }
        c
    }
}

/// The Bezier control points (`points[v * 4 + u]`) of the bicubic patch with
/// control points `g` (`g[j * 4 + i]`, u fastest) in bases `ub` and `vb`.
pub fn bicubic_to_bezier(g: &[DVec3; 16], ub: &Basis, vb: &Basis) -> [DVec3; 16] {
    let (cu, cv) = (ub.bezier_change(), vb.bezier_change());
    // Rows first (u), then columns (v).
    let mut rows = [DVec3::ZERO; 16];
    for j in 0..4 {
        for i in 0..4 {
            rows[j * 4 + i] = (0..4).map(|k| cu[i][k] * g[j * 4 + k]).sum();
        }
    }
    let mut out = [DVec3::ZERO; 16];
    for j in 0..4 {
        for i in 0..4 {
            out[j * 4 + i] = (0..4).map(|k| cv[j][k] * rows[k * 4 + i]).sum();
        }
    }
    out
}

/// The bicubic Bezier control points of the bilinear patch with corners
/// `p[0]` (u=0,v=0), `p[1]` (1,0), `p[2]` (0,1), `p[3]` (1,1): degree
/// elevation, exact.
pub fn bilinear_to_bezier(p: &[DVec3; 4]) -> [DVec3; 16] {
    let mut out = [DVec3::ZERO; 16];
    for j in 0..4 {
        let v = j as f64 / 3.0;
        for i in 0..4 {
            let u = i as f64 / 3.0;
            out[j * 4 + i] = p[0] * (1.0 - u) * (1.0 - v)
                + p[1] * u * (1.0 - v)
                + p[2] * (1.0 - u) * v
                + p[3] * u * v;
        }
    }
    out
}

/// Whether a mesh direction wraps around.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wrap {
    /// `"periodic"`: the last patch joins the first.
    Periodic,
    /// `"nonperiodic"`.
    Nonperiodic,
}

/// The patch count along one direction of `n` control points, or why the
/// count does not fit the step.
pub(super) fn patch_count(
    n: usize,
    wrap: Wrap,
    step: usize,
    order: usize,
) -> Result<usize, String> {
    match wrap {
        Wrap::Nonperiodic => {
            if n < order || !(n - order).is_multiple_of(step) {
                Err(format!(
                    "{n} control points do not make whole nonperiodic patches (need {order} + a multiple of the step {step})"
                ))
            } else {
                Ok((n - order) / step + 1)
            }
        }
        Wrap::Periodic => {
            if n == 0 || !n.is_multiple_of(step) || n < order.min(2) {
                Err(format!(
                    "{n} control points do not make whole periodic patches (need a multiple of the step {step})"
                ))
            } else {
                Ok(n / step)
            }
        }
    }
}

/// One direction of a mesh: control point count, wrap and basis.
#[derive(Debug, Clone, Copy)]
pub struct MeshDir {
    /// Control points along the direction.
    pub n: usize,
    /// Periodic or not.
    pub wrap: Wrap,
    /// The basis (only its step matters for bilinear meshes, which use step 1).
    pub basis: Basis,
}

/// The patches of a `PatchMesh` along u and along v (what [`patch_mesh`]
/// makes, `nu * nv` of them), from `points` control points; or why they do
/// not make whole patches.
pub fn patch_mesh_counts(
    bicubic: bool,
    u: MeshDir,
    v: MeshDir,
    points: usize,
) -> Result<(usize, usize), String> {
    if u.n.checked_mul(v.n) != Some(points) {
        return Err(format!(
            "\"P\" has {points} points but nu * nv is {} * {}",
            u.n, v.n
        ));
    }
    let (order, ustep, vstep) = if bicubic {
        (4, u.basis.step, v.basis.step)
    } else {
        (2, 1, 1)
    };
    if ustep == 0 || vstep == 0 {
        return Err("a basis step must be at least 1".into());
    }
    let nup = patch_count(u.n, u.wrap, ustep, order).map_err(|e| format!("u: {e}"))?;
    let nvp = patch_count(v.n, v.wrap, vstep, order).map_err(|e| format!("v: {e}"))?;
    Ok((nup, nvp))
}

/// The patches of the fan [`polygon`] makes of a polygon of `n` vertices
/// (at least 3): one per two triangles.
pub fn fan_patches(n: usize) -> usize {
    n.saturating_sub(1) / 2
}

/// The Bezier patches of a `PatchMesh`: `bicubic` (else bilinear), points
/// `p[v * nu + u]`.
pub fn patch_mesh(
    bicubic: bool,
    u: MeshDir,
    v: MeshDir,
    p: &[DVec3],
) -> Result<Vec<[DVec3; 16]>, String> {
    let (nup, nvp) = patch_mesh_counts(bicubic, u, v, p.len())?;
    let (ustep, vstep) = if bicubic {
        (u.basis.step, v.basis.step)
    } else {
        (1, 1)
    };
    let at = |i: usize, j: usize| p[(j % v.n) * u.n + (i % u.n)];
    let mut out = Vec::with_capacity(nup.saturating_mul(nvp).min(p.len()));
    for pv in 0..nvp {
        for pu in 0..nup {
            let (i0, j0) = (pu * ustep, pv * vstep);
            if bicubic {
                let mut g = [DVec3::ZERO; 16];
                for j in 0..4 {
                    for i in 0..4 {
                        g[j * 4 + i] = at(i0 + i, j0 + j);
                    }
                }
                out.push(bicubic_to_bezier(&g, &u.basis, &v.basis));
            } else {
                let c = [
                    at(i0, j0),
                    at(i0 + 1, j0),
                    at(i0, j0 + 1),
                    at(i0 + 1, j0 + 1),
                ];
                out.push(bilinear_to_bezier(&c));
            }
        }
    }
    Ok(out)
}

/// The Bezier patches of a convex `Polygon` with vertices `p`: bilinear
/// quads of four consecutive vertices cut off the polygon level by level
/// (see [`polygon_fan`]; a last triangle as a quad with its third corner
/// doubled), raised to bicubic. `dP/du x dP/dv` has the sign of
/// `(p1 - p0) x (p2 - p0)`.
pub fn polygon(p: &[DVec3]) -> Vec<[DVec3; 16]> {
    polygon_fan(p.len())
        .into_iter()
        .map(|corners| bilinear_to_bezier(&corners.map(|k| p[k])))
        .collect()
}

/// The vertices (positions in the polygon) at the corners `(u, v) = (0,0),
/// (1,0), (0,1), (1,1)` of each patch of [`polygon`] over `n` vertices, as
/// many as [`fan_patches`] counts.
///
/// Each level walks the polygon's remaining vertices `l` in order and cuts
/// off the quads `(l[j], l[j+1], l[j+2], l[j+3])` for `j = 0, 3, 6, ...`
/// (corners `(l[j], l[j+1], l[j+3], l[j+2])`), keeping `l[j]` and `l[j+3]`;
/// the last four (or three: a triangle `(l0, l1, l2, l2)`) make the last
/// patch. A convex polygon is covered exactly, each quad by its own chord.
/// A fan from vertex 0 covered it too, but with slivers as long as the
/// polygon: a polygon of 700,000 vertices along an arc split each of its
/// 350,000 slivers into pieces along its whole length, for minutes. Here a
/// level's quads lie along the boundary, their lengths sum to the
/// perimeter, and there are `log3 n` levels.
pub fn polygon_fan(n: usize) -> Vec<[usize; 4]> {
    let mut out = Vec::with_capacity(fan_patches(n));
    let mut remaining: Vec<usize> = (0..n).collect();
    while remaining.len() > 4 {
        let mut next = Vec::with_capacity(remaining.len() / 3 + 3);
        let mut j = 0;
        while j + 3 < remaining.len() {
            let l = &remaining[j..j + 4];
            out.push([l[0], l[1], l[3], l[2]]);
            next.push(l[0]);
            j += 3;
        }
        next.extend_from_slice(&remaining[j..]);
        remaining = next;
    }
    match remaining[..] {
        [a, b, c, d] => out.push([a, b, d, c]),
        [a, b, c] => out.push([a, b, c, c]),
        _ => {}
    }
    out
}

/// Whether the polygon `p` is convex and planar (up to rounding): every
/// turn bends the same way about its Newell normal.
pub fn convex(p: &[DVec3]) -> bool {
    let n = p.len();
    let normal: DVec3 = (0..n)
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % n]);
            DVec3::new(
                (a.y - b.y) * (a.z + b.z),
                (a.z - b.z) * (a.x + b.x),
                (a.x - b.x) * (a.y + b.y),
            )
        })
        .sum();
    let scale = p.iter().map(|q| q.abs().max_element()).fold(0.0, f64::max);
    if normal.length() <= 1e-12 * scale * scale {
        // No area: nothing to cover either way.
        return true;
    }
    let normal = normal.normalize();
    (0..n).all(|i| {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        let turn = (b - a).cross(c - b);
        turn.dot(normal) >= -1e-9 * scale * scale
            && (turn - normal * turn.dot(normal)).length() <= 1e-6 * scale * scale
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area of the triangle `a b c` in the xy plane.
    fn area2(a: DVec3, b: DVec3, c: DVec3) -> f64 {
        (b - a).truncate().perp_dot((c - a).truncate())
    }

    /// The patches of a polygon are as many as [`fan_patches`] counts, use
    /// every vertex, follow the polygon's orientation and cover a convex
    /// polygon exactly (their areas sum to its area).
    #[test]
    fn polygon_patches_cover_a_convex_polygon() {
        for n in 3..300 {
            let quads = polygon_fan(n);
            assert_eq!(quads.len(), fan_patches(n), "{n} vertices");
            let mut used = vec![false; n];
            for q in &quads {
                for &k in q {
                    used[k] = true;
                }
            }
            assert!(used.iter().all(|&u| u), "{n}: every vertex is a corner");
            let p: Vec<DVec3> = (0..n)
                .map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / n as f64;
                    DVec3::new(a.cos(), a.sin(), 0.0)
                })
                .collect();
            let polygon: f64 = (1..n - 1).map(|i| area2(p[0], p[i], p[i + 1])).sum();
            let mut covered = 0.0;
            for &[a, b, d, c] in &quads {
                let (a, b, c, d) = (p[a], p[b], p[c], p[d]);
                let (first, second) = (area2(a, b, c), area2(a, c, d));
                assert!(first > 0.0 && second >= 0.0, "{n}: counter-clockwise");
                covered += first + second;
            }
            assert!((covered - polygon).abs() < 1e-9 * polygon, "{n}: {covered} vs {polygon}");
        }
    }

    /// The longest patch edge of a polygon of many vertices along a circle
    /// is a small part of the circle, not a chord across it: a fan from
    /// vertex 0 made every patch as long as the polygon.
    #[test]
    fn patches_of_a_long_polygon_are_short() {
        let n = 30_001;
        let quads = polygon_fan(n);
        let point = |i: usize| {
            let a = std::f64::consts::FRAC_PI_2 * i as f64 / (n - 1) as f64;
            DVec3::new(a.cos(), a.sin(), 0.0)
        };
        let mut long = 0;
        for q in &quads {
            let corners = q.map(point);
            let extent = corners
                .iter()
                .flat_map(|a| corners.iter().map(move |b| a.distance(*b)))
                .fold(0.0, f64::max);
            if extent > 0.1 {
                long += 1;
            }
        }
        // Chords longer than a tenth of the radius: only the top levels'.
        assert!(long < 50, "{long} of {} patches are long", quads.len());
    }
}
