//! Dicing: evaluate a patch on a 16 x 16 grid of points with shading normals.

use glam::Vec3;

use crate::bezier;
use crate::params::{
    DEGENERATE_NORMAL_REL_EPS, DEGENERATE_PARAM_MAX, DEGENERATE_PARAM_MIN, GRID_POINTS, GRID_QUADS,
};

/// Number of points in a grid.
pub const GRID_LEN: usize = GRID_POINTS * GRID_POINTS;

/// A diced grid: point `(i, j)` (i along u / s, j along v / t) is at index
/// `j * GRID_POINTS + i`.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// World-space positions.
    pub positions: [Vec3; GRID_LEN],
    /// Unit normals facing the eye (two-sided shading).
    pub normals: [Vec3; GRID_LEN],
}

/// Dices a patch: `s = i / 15`, `t = j / 15` for `i, j` in `0..16`.
pub fn dice(points: &[Vec3; 16], eye: Vec3) -> Grid {
    let mut grid = Grid {
        positions: [Vec3::ZERO; GRID_LEN],
        normals: [Vec3::ZERO; GRID_LEN],
    };
    for j in 0..GRID_POINTS {
        for i in 0..GRID_POINTS {
            let s = i as f32 / GRID_QUADS as f32;
            let t = j as f32 / GRID_QUADS as f32;
            let (position, normal) = surface_point(points, s, t, eye);
            grid.positions[j * GRID_POINTS + i] = position;
            grid.normals[j * GRID_POINTS + i] = normal;
        }
    }
    grid
}

/// Whether `n = a x b` is degenerate: `|n|^2 <= eps * |a|^2 |b|^2`, `|n|^2 == 0`,
/// or not finite.
pub(crate) fn degenerate(n: Vec3, a: Vec3, b: Vec3) -> bool {
    let n2 = n.length_squared();
    !n2.is_finite()
        || n2 <= DEGENERATE_NORMAL_REL_EPS * (a.length_squared() * b.length_squared())
        || n2 == 0.0
}

/// The unit geometric normal `normalize(dP/ds x dP/dt)` at `(s, t)`, not
/// turned towards the eye: the direction displacement moves a point. A
/// degenerate normal is re-evaluated at the clamped parameters as in
/// [`surface_point`]; if that is degenerate too the result is zero (the
/// point is not displaced: there is no direction to move it along).
pub fn displacement_normal(points: &[Vec3; 16], s: f32, t: f32) -> Vec3 {
    let e = bezier::evaluate(points, s, t);
    let mut n = e.d_ds.cross(e.d_dt);
    if degenerate(n, e.d_ds, e.d_dt) {
        let inner = bezier::evaluate(
            points,
            s.clamp(DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
            t.clamp(DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
        );
        n = inner.d_ds.cross(inner.d_dt);
        if degenerate(n, inner.d_ds, inner.d_dt) {
            return Vec3::ZERO;
        }
    }
    n.normalize_or_zero()
}

/// Position and unit shading normal at `(s, t)`, facing `eye`. Never NaN.
///
/// `n = dP/ds x dP/dt`; if degenerate, the tangents are re-evaluated at
/// `(clamp(s, 0.01, 0.99), clamp(t, 0.01, 0.99))`; if still degenerate,
/// `n = eye - P` (and +z if even that is zero). Then `n` is normalized and
/// flipped if `dot(n, eye - P) < 0`.
pub fn surface_point(points: &[Vec3; 16], s: f32, t: f32, eye: Vec3) -> (Vec3, Vec3) {
    let e = bezier::evaluate(points, s, t);
    let mut n = e.d_ds.cross(e.d_dt);
    if degenerate(n, e.d_ds, e.d_dt) {
        let inner = bezier::evaluate(
            points,
            s.clamp(DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
            t.clamp(DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
        );
        n = inner.d_ds.cross(inner.d_dt);
        if degenerate(n, inner.d_ds, inner.d_dt) {
            n = eye - e.position;
        }
    }
    let mut n = n.normalize_or_zero();
    if n == Vec3::ZERO {
        // Only reachable when the eye lies on the surface point itself.
        n = Vec3::Z;
    }
    if n.dot(eye - e.position) < 0.0 {
        n = -n;
    }
    (e.position, n)
}
