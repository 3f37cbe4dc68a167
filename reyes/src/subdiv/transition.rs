//! Transition patches: no T-junctions between levels.
//!
//! A coarse patch next to refined ones meets two (or more) finer patches
//! along one edge, whose curves are De Casteljau pieces of its own. The
//! rate dicer measures each input patch's edges afresh, so the coarse edge
//! and its pieces can be diced to spacings that do not nest, leaving
//! slivers. Such a patch is therefore replaced by a fan of patches around
//! its centre `c = P(1/2, 1/2)`, one per piece of its boundary: patch `i`
//! has the boundary piece `d_i -> d_i+1` as its edge `v = 0` (the very
//! curve the finer neighbour has, bit for bit), the "spokes" `d_i -> c` and
//! `d_i+1 -> c` as its edges `u = 0` and `u = 1`, and its edge `v = 1`
//! collapsed to `c`. Over the triangle `(d_i, d_i+1, c)` of the coarse
//! patch's domain it interpolates the coarse patch at 4 x 4 points; a spoke
//! is computed once from the coarse patch alone, so the two fan patches on
//! it share it. The error against the coarse patch is measured.

use std::collections::HashSet;

use glam::{Vec2, Vec3};

use super::level::{Key, Level, edge};
use super::stitch::Stitched;
use crate::bezier;

/// The pieces `(level, from, to)` that cover the edge `a -> b` of
/// `levels[level]` as the patches on the far side see it: the edge itself,
/// or the pieces of its two halves when both are covered by finer edges of
/// patches.
fn pieces(
    levels: &[Level],
    used: &HashSet<(Key, Key)>,
    level: usize,
    (a, b): (u32, u32),
    out: &mut Vec<(usize, u32, u32)>,
) {
    if let Some((ca, m, cb)) = halves(levels, level, a, b)
        && covered(levels, used, level + 1, ca, m)
        && covered(levels, used, level + 1, m, cb)
    {
        pieces(levels, used, level + 1, (ca, m), out);
        pieces(levels, used, level + 1, (m, cb), out);
        return;
    }
    out.push((level, a, b));
}

/// The vertices one level down on edge `a -> b`: `a`'s vertex point, the
/// edge point, `b`'s vertex point.
fn halves(levels: &[Level], level: usize, a: u32, b: u32) -> Option<(u32, u32, u32)> {
    let child = levels.get(level + 1)?;
    Some((
        *child.from_vertex.get(&a)?,
        *child.from_edge.get(&edge(a, b))?,
        *child.from_vertex.get(&b)?,
    ))
}

/// Whether some patch has the edge `a -> b`, or its halves are covered.
fn covered(levels: &[Level], used: &HashSet<(Key, Key)>, level: usize, a: u32, b: u32) -> bool {
    let keys = &levels[level].keys;
    let (ka, kb) = (keys[a as usize], keys[b as usize]);
    if used.contains(&(ka.min(kb), ka.max(kb))) {
        return true;
    }
    halves(levels, level, a, b).is_some_and(|(ca, m, cb)| {
        covered(levels, used, level + 1, ca, m) && covered(levels, used, level + 1, m, cb)
    })
}

/// The cubic through `p` at `t = 0, 1/3, 2/3, 1`, in Bezier form.
fn interpolate(p: [Vec3; 4]) -> [Vec3; 4] {
    [
        p[0],
        (p[0] * -5.0 + p[1] * 18.0 - p[2] * 9.0 + p[3] * 2.0) / 6.0,
        (p[0] * 2.0 - p[1] * 9.0 + p[2] * 18.0 - p[3] * 5.0) / 6.0,
        p[3],
    ]
}

/// A fan patch: its points and the domain corners `d_i, d_i+1` it spans
/// (with `c = (1/2, 1/2)`).
pub(super) struct FanPatch {
    pub points: [Vec3; 16],
    pub domain: [Vec2; 2],
}

/// The fan replacing the patch `points` over quad `f` of `levels[level]`,
/// or `None` when no edge of it meets finer patches.
pub(super) fn fan(
    levels: &[Level],
    stitched: &Stitched,
    level: usize,
    f: u32,
    points: &[Vec3; 16],
) -> Option<Vec<FanPatch>> {
    let q = levels[level].quad(f);
    let mut boundary: Vec<(Vec2, [Vec3; 4])> = Vec::new();
    let corners = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    let mut split = false;
    for k in 0..4 {
        let mut list = Vec::new();
        pieces(
            levels,
            &stitched.used,
            level,
            (q[k], q[(k + 1) % 4]),
            &mut list,
        );
        split |= list.len() > 1;
        let (from, to) = (corners[k], corners[(k + 1) % 4]);
        let mut at = 0.0f32;
        for (l, a, b) in list {
            let keys = &levels[l].keys;
            let curve = stitched.curve(keys[a as usize], keys[b as usize])?;
            boundary.push((from.lerp(to, at), curve));
            // A piece `l - level` levels down spans 2^-(l - level) of the edge.
            at += (0..l - level).fold(1.0f32, |x, _| x * 0.5);
        }
    }
    if !split {
        return None;
    }
    let centre = Vec2::splat(0.5);
    let c = bezier::position(points, 0.5, 0.5);
    let at = |d: Vec2| bezier::position(points, d.x, d.y);
    // The spoke from boundary point `i` to the centre, the same bits for
    // both fan patches on it.
    let spoke = |i: usize| {
        let (d, start) = (boundary[i].0, boundary[i].1[0]);
        let mut s = interpolate(std::array::from_fn(|k| at(d.lerp(centre, k as f32 / 3.0))));
        s[0] = start;
        s[3] = c;
        s
    };
    let n = boundary.len();
    let fan = (0..n)
        .map(|i| {
            let j = (i + 1) % n;
            let (d0, d1) = (boundary[i].0, boundary[j].0);
            let domain = |s: f32, t: f32| d0.lerp(d1, s).lerp(centre, t);
            // Interpolate row by row, then column by column.
            let mut rows = [[Vec3::ZERO; 4]; 4];
            for (r, row) in rows.iter_mut().enumerate() {
                let t = r as f32 / 3.0;
                *row = interpolate(std::array::from_fn(|k| at(domain(k as f32 / 3.0, t))));
            }
            let mut p = [Vec3::ZERO; 16];
            for u in 0..4 {
                let column = interpolate(std::array::from_fn(|r| rows[r][u]));
                for (v, point) in column.into_iter().enumerate() {
                    p[v * 4 + u] = point;
                }
            }
            let (left, right) = (spoke(i), spoke(j));
            for k in 0..4 {
                p[k] = boundary[i].1[k];
                p[k * 4] = left[k];
                p[k * 4 + 3] = right[k];
                p[12 + k] = c;
            }
            FanPatch {
                points: p,
                domain: [d0, d1],
            }
        })
        .collect();
    Some(fan)
}

/// The largest distance between a fan patch and the patch it replaces, at
/// 9 x 9 points.
pub(super) fn fan_error(points: &[Vec3; 16], fan: &FanPatch) -> f32 {
    let centre = Vec2::splat(0.5);
    let mut worst = 0.0f32;
    for j in 0..=8 {
        for i in 0..=8 {
            let (s, t) = (i as f32 / 8.0, j as f32 / 8.0);
            let d = fan.domain[0].lerp(fan.domain[1], s).lerp(centre, t);
            let want = bezier::position(points, d.x, d.y);
            worst = worst.max((bezier::position(&fan.points, s, t) - want).length());
        }
    }
    worst
}
