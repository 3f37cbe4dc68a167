//! Bicubic Bezier patch mathematics: evaluation with exact tangents, the
//! De Casteljau half split, and the u/v extents that choose a split direction.
//!
//! Control points are indexed `points[v * 4 + u]` (see [`crate::model::Patch`]);
//! the evaluation parameters are `s` (along u) and `t` (along v), both in `[0, 1]`.

use glam::{Vec2, Vec3};

/// Which parameter direction a split halves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SplitDirection {
    /// Halve along u (each row is split; the halves are u in [u0, um] and [um, u1]).
    U,
    /// Halve along v (each column is split).
    V,
}

/// The cubic Bernstein basis at `t`: `[(1-t)^3, 3t(1-t)^2, 3t^2(1-t), t^3]`.
pub fn bernstein(t: f32) -> [f32; 4] {
    let mt = 1.0 - t;
    [mt * mt * mt, 3.0 * t * mt * mt, 3.0 * t * t * mt, t * t * t]
}

/// The quadratic Bernstein basis at `t`: `[(1-t)^2, 2t(1-t), t^2]`, which
/// weighs the differences of the control points in a cubic's derivative.
pub fn bernstein_quadratic(t: f32) -> [f32; 3] {
    let mt = 1.0 - t;
    [mt * mt, 2.0 * t * mt, t * t]
}

/// A surface point with its two exact partial derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// `P(s, t)`.
    pub position: Vec3,
    /// `dP/ds` (along u).
    pub d_ds: Vec3,
    /// `dP/dt` (along v).
    pub d_dt: Vec3,
}

/// `sum over rows v of wv[v] * (sum over columns u of wu[u] * p[v * 4 + u])`.
fn tensor(points: &[Vec3; 16], wu: &[f32; 4], wv: &[f32; 4]) -> Vec3 {
    let mut sum = Vec3::ZERO;
    for v in 0..4 {
        let row = points[v * 4] * wu[0]
            + points[v * 4 + 1] * wu[1]
            + points[v * 4 + 2] * wu[2]
            + points[v * 4 + 3] * wu[3];
        sum += row * wv[v];
    }
    sum
}

/// `dP/ds`: `3 * sum over rows v of wv[v] * (sum over i of q[i] * (p[v * 4 +
/// i + 1] - p[v * 4 + i]))`, with `q` the quadratic basis at `s`. In this
/// difference (hodograph) form the tangent along a collapsed edge (all four
/// points equal) is exactly zero, so the normal there is seen to be
/// degenerate; Bernstein-derivative weights, whose float sum is not exactly
/// zero, would leave rounding noise of any direction.
fn tangent_s(points: &[Vec3; 16], s: f32, wv: &[f32; 4]) -> Vec3 {
    let q = bernstein_quadratic(s);
    let mut sum = Vec3::ZERO;
    for v in 0..4 {
        let p = |i: usize| points[v * 4 + i];
        let row = (p(1) - p(0)) * q[0] + (p(2) - p(1)) * q[1] + (p(3) - p(2)) * q[2];
        sum += row * wv[v];
    }
    sum * 3.0
}

/// `dP/dt`: `3 * sum over v < 3 of q[v] * (sum over u of wu[u] * (p[(v +
/// 1) * 4 + u] - p[v * 4 + u]))`, with `q` the quadratic basis at `t` (the
/// difference form of [`tangent_s`]).
fn tangent_t(points: &[Vec3; 16], wu: &[f32; 4], t: f32) -> Vec3 {
    let q = bernstein_quadratic(t);
    let mut sum = Vec3::ZERO;
    for v in 0..3 {
        let d = |u: usize| points[(v + 1) * 4 + u] - points[v * 4 + u];
        let row = d(0) * wu[0] + d(1) * wu[1] + d(2) * wu[2] + d(3) * wu[3];
        sum += row * q[v];
    }
    sum * 3.0
}

/// Evaluates the patch position at `(s, t)`.
pub fn position(points: &[Vec3; 16], s: f32, t: f32) -> Vec3 {
    tensor(points, &bernstein(s), &bernstein(t))
}

/// Evaluates the position and the exact tangents `dP/ds`, `dP/dt` at `(s, t)`
/// from the Bernstein form, the tangents in difference form (exactly zero
/// along a collapsed edge).
pub fn evaluate(points: &[Vec3; 16], s: f32, t: f32) -> SurfacePoint {
    let (bs, bt) = (bernstein(s), bernstein(t));
    SurfacePoint {
        position: tensor(points, &bs, &bt),
        d_ds: tangent_s(points, s, &bt),
        d_dt: tangent_t(points, &bs, t),
    }
}

/// De Casteljau subdivision of one cubic at t = 1/2, written out so the GPU
/// can use the same operation order:
/// `l1 = (p0+p1)/2, m = (p1+p2)/2, r2 = (p2+p3)/2, l2 = (l1+m)/2,
/// r1 = (m+r2)/2, mid = (l2+r1)/2`; left = `[p0, l1, l2, mid]`,
/// right = `[mid, r1, r2, p3]`.
pub fn split_cubic(p: [Vec3; 4]) -> ([Vec3; 4], [Vec3; 4]) {
    let l1 = (p[0] + p[1]) * 0.5;
    let m = (p[1] + p[2]) * 0.5;
    let r2 = (p[2] + p[3]) * 0.5;
    let l2 = (l1 + m) * 0.5;
    let r1 = (m + r2) * 0.5;
    let mid = (l2 + r1) * 0.5;
    ([p[0], l1, l2, mid], [mid, r1, r2, p[3]])
}

/// Splits a patch at u = 1/2 (each of the 4 rows): `(left, right)`, where
/// left covers the lower half of the u range.
pub fn split_u(points: &[Vec3; 16]) -> ([Vec3; 16], [Vec3; 16]) {
    let mut left = [Vec3::ZERO; 16];
    let mut right = [Vec3::ZERO; 16];
    for v in 0..4 {
        let row = [
            points[v * 4],
            points[v * 4 + 1],
            points[v * 4 + 2],
            points[v * 4 + 3],
        ];
        let (l, r) = split_cubic(row);
        left[v * 4..v * 4 + 4].copy_from_slice(&l);
        right[v * 4..v * 4 + 4].copy_from_slice(&r);
    }
    (left, right)
}

/// Splits a patch at v = 1/2 (each of the 4 columns): `(low, high)`, where
/// low covers the lower half of the v range.
pub fn split_v(points: &[Vec3; 16]) -> ([Vec3; 16], [Vec3; 16]) {
    let mut low = [Vec3::ZERO; 16];
    let mut high = [Vec3::ZERO; 16];
    for u in 0..4 {
        let column = [points[u], points[4 + u], points[8 + u], points[12 + u]];
        let (l, h) = split_cubic(column);
        for v in 0..4 {
            low[v * 4 + u] = l[v];
            high[v * 4 + u] = h[v];
        }
    }
    (low, high)
}

/// Splits a patch in the given direction.
pub fn split(points: &[Vec3; 16], direction: SplitDirection) -> ([Vec3; 16], [Vec3; 16]) {
    match direction {
        SplitDirection::U => split_u(points),
        SplitDirection::V => split_v(points),
    }
}

/// The "u extent" and "v extent" of 16 points under a distance function:
/// u extent = sum over rows v of `dist(p(v,0), p(v,3))`,
/// v extent = sum over columns u of `dist(p(0,u), p(3,u))`.
fn extents<P: Copy>(points: &[P; 16], dist: impl Fn(P, P) -> f32) -> (f32, f32) {
    let mut u_extent = 0.0;
    let mut v_extent = 0.0;
    for k in 0..4 {
        u_extent += dist(points[k * 4], points[k * 4 + 3]);
        v_extent += dist(points[k], points[12 + k]);
    }
    (u_extent, v_extent)
}

/// Split direction from world-space (3D) extents: U if u extent >= v extent.
pub fn split_direction_3d(points: &[Vec3; 16]) -> SplitDirection {
    let (u, v) = extents(points, |a, b| (b - a).length());
    if u >= v {
        SplitDirection::U
    } else {
        SplitDirection::V
    }
}

/// Split direction from pixel-space (2D) extents: U if u extent >= v extent.
pub fn split_direction_2d(points: &[Vec2; 16]) -> SplitDirection {
    let (u, v) = extents(points, |a, b| (b - a).length());
    if u >= v {
        SplitDirection::U
    } else {
        SplitDirection::V
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng, rngs::StdRng};

    fn random_patch(rng: &mut StdRng) -> [Vec3; 16] {
        std::array::from_fn(|_| {
            Vec3::new(
                rng.random_range(-5.0..5.0),
                rng.random_range(-5.0..5.0),
                rng.random_range(-5.0..5.0),
            )
        })
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() <= 1e-4 * (1.0 + a.length())
    }

    #[test]
    fn split_halves_reproduce_the_surface() {
        let seed: u64 = rand::random();
        println!("split_halves_reproduce_the_surface seed = {seed}");
        let mut rng = StdRng::seed_from_u64(seed);
        for _ in 0..200 {
            let p = random_patch(&mut rng);
            let (left, right) = split_u(&p);
            let (low, high) = split_v(&p);
            for _ in 0..20 {
                let (s, t): (f32, f32) = (rng.random(), rng.random());
                // Left half at local s covers u = s / 2; right half u = 1/2 + s / 2.
                let original_l = position(&p, s * 0.5, t);
                let original_r = position(&p, 0.5 + s * 0.5, t);
                assert!(close(position(&left, s, t), original_l), "seed {seed}");
                assert!(close(position(&right, s, t), original_r), "seed {seed}");
                let original_lo = position(&p, s, t * 0.5);
                let original_hi = position(&p, s, 0.5 + t * 0.5);
                assert!(close(position(&low, s, t), original_lo), "seed {seed}");
                assert!(close(position(&high, s, t), original_hi), "seed {seed}");
            }
        }
    }

    #[test]
    fn tangents_match_finite_differences() {
        let mut rng = StdRng::seed_from_u64(7);
        let p = random_patch(&mut rng);
        let h = 1e-2f32;
        for &(s, t) in &[(0.3f32, 0.6f32), (0.5, 0.5), (0.8, 0.2)] {
            let e = evaluate(&p, s, t);
            let fd_s = (position(&p, s + h, t) - position(&p, s - h, t)) / (2.0 * h);
            let fd_t = (position(&p, s, t + h) - position(&p, s, t - h)) / (2.0 * h);
            assert!((e.d_ds - fd_s).length() < 1e-2 * (1.0 + fd_s.length()));
            assert!((e.d_dt - fd_t).length() < 1e-2 * (1.0 + fd_t.length()));
        }
    }

    #[test]
    fn bernstein_is_a_partition_of_unity() {
        for i in 0..=10 {
            let t = i as f32 / 10.0;
            assert!((bernstein(t).iter().sum::<f32>() - 1.0).abs() < 1e-6);
            assert!((bernstein_quadratic(t).iter().sum::<f32>() - 1.0).abs() < 1e-6);
        }
    }
}
