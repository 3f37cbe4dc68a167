//! A micropolygon as one quad for sample tests: the box of its four
//! corners, clamped to the sample strata it touches ([`StrataBox`]), and a
//! sample test with the quad's edges ([`Quad::test`]).
//!
//! The quad `(a, b, c, d)` is split along its 0–2 diagonal into the
//! triangles `(a, b, c)` and `(a, c, d)`. A sample is tested once per quad,
//! not once per triangle: five edge functions, the diagonal's shared by
//! both triangles (the edge function is exactly antisymmetric, see
//! `reyes::reference::raster::edge`, so the result is bit for bit that of testing
//! each triangle on its own). A sample inside both triangles of a folded
//! quad is offered by both, as each triangle alone would offer it.
//!
//! A sample lies in its stratum: sample `s = row * k + col` of pixel
//! `(x, y)` is within stratum `(x * k + col, y * k + row)` of the `k x k`
//! strata per pixel ([`crate::sampling`]), so only the samples of the
//! strata a box touches can be inside it. Fatahalian et al. (2009) report
//! up to twice the sample test efficiency from quads and boxes clamped to
//! strata.

use glam::{Vec2, Vec3};

use super::framebuffer::Framebuffer;
use super::raster::{edge, inside, key_depth};
use crate::color::{blend_rgb10, pack_key};
use crate::params::STRATUM_MARGIN;
use crate::stats::RenderStats;

/// The sample strata `[x0, x1] x [y0, y1]` (global stratum columns and rows,
/// `k` per pixel) that a screen box touches, clamped to the frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StrataBox {
    /// First stratum column.
    pub x0: u32,
    /// First stratum row.
    pub y0: u32,
    /// Last stratum column.
    pub x1: u32,
    /// Last stratum row.
    pub y1: u32,
    /// Strata per pixel side.
    pub k: u32,
}

impl StrataBox {
    /// The strata of a `width x height` frame with `k x k` samples per pixel
    /// that the box `[lo, hi]` (pixels) touches, grown by
    /// [`STRATUM_MARGIN`]; `None` when it misses the frame.
    pub fn new(lo: Vec2, hi: Vec2, k: u32, width: u32, height: u32) -> Option<StrataBox> {
        let kf = k as f32;
        // Clamped in float first (saturating casts keep huge values harmless).
        let x0 = ((lo.x - STRATUM_MARGIN) * kf).floor().max(0.0);
        let y0 = ((lo.y - STRATUM_MARGIN) * kf).floor().max(0.0);
        let x1 = ((hi.x + STRATUM_MARGIN) * kf)
            .floor()
            .min((width * k) as f32 - 1.0);
        let y1 = ((hi.y + STRATUM_MARGIN) * kf)
            .floor()
            .min((height * k) as f32 - 1.0);
        if !(x0 <= x1 && y0 <= y1) {
            return None;
        }
        Some(StrataBox {
            x0: x0 as u32,
            y0: y0 as u32,
            x1: x1 as u32,
            y1: y1 as u32,
            k,
        })
    }

    /// The pixels `[x0, x1] x [y0, y1]` these strata lie in.
    pub fn pixels(&self) -> [u32; 4] {
        [
            self.x0 / self.k,
            self.y0 / self.k,
            self.x1 / self.k,
            self.y1 / self.k,
        ]
    }

    /// Whether sample `s` of pixel `(x, y)` lies in one of these strata.
    #[inline]
    pub fn holds(&self, x: u32, y: u32, s: u32) -> bool {
        let gx = x * self.k + s % self.k;
        let gy = y * self.k + s / self.k;
        (self.x0..=self.x1).contains(&gx) && (self.y0..=self.y1).contains(&gy)
    }

    /// Every sample of these strata, row by row: `(x, y, s)`.
    pub fn samples(&self) -> impl Iterator<Item = (u32, u32, u32)> + '_ {
        let k = self.k;
        (self.y0..=self.y1).flat_map(move |gy| {
            (self.x0..=self.x1).map(move |gx| (gx / k, gy / k, (gy % k) * k + gx % k))
        })
    }

    /// The pixels `x` of columns `[x0, x1]` whose sample column `col`
    /// (`s % k`) lies in these strata, as `(first, last)`; `None` if none.
    pub fn columns_of(&self, col: u32) -> Option<(u32, u32)> {
        span_of(self.x0, self.x1, col, self.k)
    }

    /// Likewise for the rows of sample row `row` (`s / k`).
    pub fn rows_of(&self, row: u32) -> Option<(u32, u32)> {
        span_of(self.y0, self.y1, row, self.k)
    }
}

/// The pixels `p` with `p * k + offset` in `[first, last]`.
fn span_of(first: u32, last: u32, offset: u32, k: u32) -> Option<(u32, u32)> {
    if last < offset {
        return None;
    }
    let lo = (first + k - 1 - offset) / k;
    let hi = (last - offset) / k;
    (lo <= hi).then_some((lo, hi))
}

/// One of a quad's triangles, oriented so that its area is positive:
/// `(a, p, q)` is `(a, b, c)` or `(a, c, d)`, or the same with its last two
/// corners swapped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    /// `(px, py, depth)` of the corners: `a` first.
    pub corners: [Vec3; 3],
    /// The packed colours of the corners, in the same order.
    pub colors: [u32; 3],
    /// Twice the area, positive.
    pub area: f32,
    /// Whether the diagonal's far end `c` is the second corner (so the
    /// diagonal is the edge `a -> corner 1`) rather than the third (the
    /// edge `corner 2 -> a`).
    pub c_second: bool,
}

impl Triangle {
    /// Triangle `(a, b, c)` of a quad (`c` the diagonal's far end when
    /// `c_is_third`, else `b`), oriented; `None` without area (degenerate
    /// or not finite).
    pub fn new(corners: [Vec3; 3], colors: [u32; 3], c_is_third: bool) -> Option<Triangle> {
        let [a, b, c] = corners.map(Vec3::truncate);
        let area = edge(a, b, c);
        if area == 0.0 || !area.is_finite() {
            return None;
        }
        Some(if area < 0.0 {
            Triangle {
                corners: [corners[0], corners[2], corners[1]],
                colors: [colors[0], colors[2], colors[1]],
                area: -area,
                c_second: c_is_third,
            }
        } else {
            Triangle {
                corners,
                colors,
                area,
                c_second: !c_is_third,
            }
        })
    }

    /// The depth and the blended colour at `p`, if `p` is inside; `diagonal`
    /// is the quad's `edge(a, c, p)`.
    #[inline]
    pub fn fragment_at(&self, p: Vec2, diagonal: f32) -> Option<(f32, u32)> {
        let [a, b, c] = self.corners.map(Vec3::truncate);
        let e_bc = edge(b, c, p);
        // The diagonal's edge function, shared with the other triangle.
        let (e_ca, e_ab) = if self.c_second {
            (edge(c, a, p), diagonal)
        } else {
            (-diagonal, edge(a, b, p))
        };
        if inside(e_bc, b, c) && inside(e_ca, c, a) && inside(e_ab, a, b) {
            let [za, zb, zc] = self.corners.map(|v| v.z);
            let z = (e_bc * za + e_ca * zb + e_ab * zc) / self.area;
            Some((z, blend_rgb10(self.colors, [e_bc, e_ca, e_ab], self.area)))
        } else {
            None
        }
    }
}

/// A micropolygon's triangles at one position: `(a, b, c)` and `(a, c, d)`,
/// each `None` when it is not drawn there (culled, a corner out of view,
/// or no area).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quad {
    /// `a` and `c`, the ends of the diagonal.
    pub diagonal: [Vec2; 2],
    /// The two triangles.
    pub triangles: [Option<Triangle>; 2],
}

impl Quad {
    /// The quad of corners `[a, b, c, d]` with corner colours `colors`;
    /// `drawn[i]` says whether triangle `i` may be drawn at all.
    pub fn new(corners: [Vec3; 4], colors: [u32; 4], drawn: [bool; 2]) -> Quad {
        let [a, b, c, d] = corners;
        let [ca, cb, cc, cd] = colors;
        Quad {
            diagonal: [a.truncate(), c.truncate()],
            triangles: [
                drawn[0]
                    .then(|| Triangle::new([a, b, c], [ca, cb, cc], true))
                    .flatten(),
                drawn[1]
                    .then(|| Triangle::new([a, c, d], [ca, cc, cd], false))
                    .flatten(),
            ],
        }
    }

    /// The screen box of the drawn triangles, `None` when there are none.
    pub fn bounds(&self) -> Option<(Vec2, Vec2)> {
        self.triangles
            .iter()
            .flatten()
            .flat_map(|t| t.corners)
            .map(Vec3::truncate)
            .fold(None, |bounds, p| match bounds {
                None => Some((p, p)),
                Some((lo, hi)) => Some((p.min(lo), p.max(hi))),
            })
    }

    /// The fragments of the sample at `p`: one per triangle it is inside.
    #[inline]
    pub fn test(&self, p: Vec2) -> [Option<(f32, u32)>; 2] {
        let diagonal = edge(self.diagonal[0], self.diagonal[1], p);
        self.triangles
            .map(|t| t.and_then(|t| t.fragment_at(p, diagonal)))
    }
}

/// Tests sample `(x, y, s)` at `position` once against `quad`: counts the
/// test (and the hit, if the sample is inside a triangle) and offers the
/// sample each triangle's fragment.
#[inline]
pub fn test_sample(
    framebuffer: &mut Framebuffer,
    quad: &Quad,
    position: Vec2,
    (x, y, s): (u32, u32, u32),
    stats: &mut RenderStats,
) {
    stats.samples_tested += 1;
    let fragments = quad.test(position);
    if fragments.iter().any(Option::is_some) {
        stats.samples_hit += 1;
    }
    for (z, color) in fragments.into_iter().flatten() {
        framebuffer.offer(x, y, s, pack_key(key_depth(z), color));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_spans_pick_the_pixels_of_one_sample_column() {
        // Strata columns 5..=9 with k = 4: pixel 1 (strata 4..8) holds
        // columns 1, 2, 3 of it; pixel 2 (strata 8..12) columns 0, 1.
        assert_eq!(span_of(5, 9, 0, 4), Some((2, 2)));
        assert_eq!(span_of(5, 9, 1, 4), Some((1, 2)));
        assert_eq!(span_of(5, 9, 3, 4), Some((1, 1)));
        assert_eq!(span_of(5, 6, 3, 4), None);
        assert_eq!(span_of(0, 1, 2, 4), None);
        assert_eq!(span_of(0, 0, 0, 1), Some((0, 0)));
    }

    #[test]
    fn a_box_holds_the_samples_of_its_strata_only() {
        let strata = StrataBox::new(Vec2::new(1.3, 2.6), Vec2::new(1.6, 2.9), 4, 8, 8).unwrap();
        // x strata floor(1.296 * 4) = 5 ..= floor(1.604 * 4) = 6, y 10 ..= 11.
        assert_eq!((strata.x0, strata.x1, strata.y0, strata.y1), (5, 6, 10, 11));
        let samples: Vec<_> = strata.samples().collect();
        assert_eq!(samples.len(), 4);
        for (x, y, s) in samples {
            assert!(strata.holds(x, y, s));
        }
        assert!(!strata.holds(1, 2, 0));
        assert!(StrataBox::new(Vec2::splat(-3.0), Vec2::splat(-1.0), 2, 8, 8).is_none());
    }
}
