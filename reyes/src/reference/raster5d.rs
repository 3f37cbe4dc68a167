//! Rasterization with motion blur and depth of field: the sampling modes
//! Bounding box, Simple UVT, Interleave UVT, INTERVAL and Adaptive
//! ([`crate::scene::Sampling`]).
//!
//! A micropolygon corner is known at shutter open and close
//! ([`MovingPoint`]); a sample with time `t` and lens position `l` sees it
//! at `lerp(open, close, t) + l * lerp(coc_open, coc_close, t)` in pixels
//! (depth interpolated likewise), see [`crate::motion`]. A corner that
//! crosses the near or far plane during the shutter is seen only during
//! the part of it in which it is in view, between the projections at the
//! ends of that part. Each mode decides
//! which (triangle position, sample) pairs to test; the test itself is the
//! plain path's edge-function test with the top-left rule, done on the
//! triangle positioned at the sample's time and lens position. Every tested
//! pair counts in `samples_tested`, every hit in `samples_hit`.

use glam::{Vec2, Vec3, Vec4};

use super::framebuffer::Framebuffer;
use super::raster::{SampleGrid, edge, inside, key_depth};
use crate::camera::Camera;
use crate::color::{blend_rgb10, pack_key};
use crate::motion::PreparedLens;
use crate::params::{ADAPTIVE_INTERLEAVE_BIAS, NEAR_EPS};
use crate::scene::Sampling;
use crate::stats::RenderStats;
use crate::uvt::{INTERLEAVE_TILE, TimeLens, UvtTables};

/// A grid point at shutter open and close, over the part of the shutter
/// during which it can be seen.
///
/// A point can be a triangle corner while its clip position lies in front
/// of the near plane and not past the far plane (`0 <= z <= w`, `w >
/// NEAR_EPS`). Its clip position moves linearly between open and close, so
/// that part is one interval `[t_open, t_close]` of the shutter
/// ([`visible_span`]). [`Self::open`] and [`Self::close`] are the point's
/// projections at the ends of that interval, and a sample at a time in it
/// sees the point at the linear interpolation of the two (the papers'
/// constant screen velocity). A point visible during the whole shutter
/// has `t_open = 0` and `t_close = 1`, and its ends are its projections at
/// open and close. A moving object that crosses the near or far plane
/// during the shutter is thus sampled while it is in view, instead of
/// vanishing for the whole shutter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MovingPoint {
    /// `(px, py, depth)` at `t_open`.
    pub open: Vec3,
    /// `(px, py, depth)` at `t_close`.
    pub close: Vec3,
    /// Signed circle of confusion (pixels) at `t_open`.
    pub coc_open: f32,
    /// Signed circle of confusion (pixels) at `t_close`.
    pub coc_close: f32,
    /// The shutter time from which the point can be seen.
    pub t_open: f32,
    /// The shutter time until which the point can be seen.
    pub t_close: f32,
    /// Whether the point can be seen at all: a non-empty interval whose
    /// ends project with `w > NEAR_EPS` and depth in `[0, 1]`.
    pub usable: bool,
}

/// The interval `[lo, hi]` of shutter times `t` in `[0, 1]` at which the
/// clip position `clip_open + (clip_close - clip_open) * t` lies in front
/// of the near plane and not past the far plane; `lo > hi` when there is
/// none (or an end is not finite). Shared with the WGSL `visible_span`.
pub fn visible_span(clip_open: Vec4, clip_close: Vec4) -> (f32, f32) {
    const NEVER: (f32, f32) = (1.0, 0.0);
    if !(clip_open.is_finite() && clip_close.is_finite()) {
        return NEVER;
    }
    // Each plane is a function of the clip position that is linear in t and
    // >= 0 on the visible side.
    let planes = [
        (clip_open.z, clip_close.z),
        (clip_open.w - clip_open.z, clip_close.w - clip_close.z),
        (clip_open.w - NEAR_EPS, clip_close.w - NEAR_EPS),
    ];
    let mut span = (0.0f32, 1.0f32);
    for (f0, f1) in planes {
        if f0 >= 0.0 && f1 >= 0.0 {
            continue;
        }
        if f0 < 0.0 && f1 < 0.0 {
            return NEVER;
        }
        let t = f0 / (f0 - f1);
        if f0 < 0.0 {
            span.0 = span.0.max(t);
        } else {
            span.1 = span.1.min(t);
        }
    }
    span
}

/// The clip position at shutter time `t`, exactly an end at 0 and 1.
fn clip_at(clip_open: Vec4, clip_close: Vec4, t: f32) -> Vec4 {
    if t == 0.0 {
        clip_open
    } else if t == 1.0 {
        clip_close
    } else {
        clip_open + (clip_close - clip_open) * t
    }
}

impl MovingPoint {
    /// The point from its clip positions at open and close, projected by
    /// `camera` and blurred by `lens`.
    pub fn new(
        clip_open: Vec4,
        clip_close: Vec4,
        camera: &Camera,
        lens: &PreparedLens,
    ) -> MovingPoint {
        let ok = |p: Vec3, w: f32| w > NEAR_EPS && (0.0..=1.0).contains(&p.z);
        let (t_open, t_close) = visible_span(clip_open, clip_close);
        let c0 = clip_at(clip_open, clip_close, t_open);
        let c1 = clip_at(clip_open, clip_close, t_close);
        let mut open = camera.to_pixel(c0);
        let mut close = camera.to_pixel(c1);
        // A clipped end lies on the near or far plane: rounding must not
        // push its depth out of [0, 1].
        if t_open > 0.0 {
            open.z = open.z.clamp(0.0, 1.0);
        }
        if t_close < 1.0 {
            close.z = close.z.clamp(0.0, 1.0);
        }
        MovingPoint {
            open,
            close,
            coc_open: lens.coc(c0.w),
            coc_close: lens.coc(c1.w),
            t_open,
            t_close,
            usable: t_open <= t_close && ok(open, c0.w) && ok(close, c1.w),
        }
    }

    /// Whether a sample at shutter time `t` can see the point.
    #[inline]
    pub fn visible_at(&self, t: f32) -> bool {
        t >= self.t_open && t <= self.t_close
    }

    /// Where shutter time `t` lies between [`Self::open`] (0) and
    /// [`Self::close`] (1), clamped to them.
    #[inline]
    fn param(&self, t: f32) -> f32 {
        if self.t_open == 0.0 && self.t_close == 1.0 {
            // Visible during the whole shutter: exactly `t`.
            return t;
        }
        let length = self.t_close - self.t_open;
        if length > 0.0 {
            ((t - self.t_open) / length).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// The signed circle of confusion at shutter time `t` (clamped to the
    /// visible interval).
    #[inline]
    pub fn coc_at(&self, t: f32) -> f32 {
        self.coc_open + (self.coc_close - self.coc_open) * self.param(t)
    }

    /// Where a sample at `t` through lens position `lens` sees the point
    /// (`t` clamped to the visible interval).
    #[inline]
    pub fn at(&self, t: f32, lens: Vec2) -> Vec3 {
        let s = self.param(t);
        let p = self.open + (self.close - self.open) * s;
        let coc = self.coc_open + (self.coc_close - self.coc_open) * s;
        Vec3::new(p.x + lens.x * coc, p.y + lens.y * coc, p.z)
    }

    /// The point's screen motion while it is visible, in pixels.
    pub fn motion(&self) -> f32 {
        (self.close.truncate() - self.open.truncate()).length()
    }

    /// The larger of its circles of confusion, in pixels.
    pub fn blur(&self) -> f32 {
        self.coc_open.abs().max(self.coc_close.abs())
    }
}

/// The per-frame inputs of 5D rasterization.
#[derive(Debug)]
pub struct Sampler<'a> {
    /// Screen positions of the samples.
    pub samples: &'a SampleGrid,
    /// Time and lens coordinates of the samples.
    pub uvt: &'a UvtTables,
}

/// A triangle at one time and lens position, ready for sample tests.
struct Placed {
    a: Vec3,
    b: Vec3,
    c: Vec3,
    /// The packed colours of `a`, `b` and `c`.
    colors: [u32; 3],
    area: f32,
}

/// Positions triangle `corners` at `(t, lens)`; `None` when a corner cannot
/// be seen at `t` or the triangle has no area there (degenerate, or not
/// finite).
fn place(corners: &[MovingPoint; 3], colors: [u32; 3], tl: TimeLens) -> Option<Placed> {
    if !corners.iter().all(|c| c.visible_at(tl.t)) {
        return None;
    }
    let a = corners[0].at(tl.t, tl.lens);
    let b = corners[1].at(tl.t, tl.lens);
    let c = corners[2].at(tl.t, tl.lens);
    let area = edge(a.truncate(), b.truncate(), c.truncate());
    if area == 0.0 || !area.is_finite() {
        return None;
    }
    // With b and c swapped the area is positive (as in the plain path).
    let (b, c, colors) = if area < 0.0 {
        (c, b, [colors[0], colors[2], colors[1]])
    } else {
        (b, c, colors)
    };
    Some(Placed {
        a,
        b,
        c,
        colors,
        area: area.abs(),
    })
}

impl Placed {
    /// The depth and the blended colour at `p` if `p` is inside.
    #[inline]
    fn fragment_at(&self, p: Vec2) -> Option<(f32, u32)> {
        let (a, b, c) = (self.a.truncate(), self.b.truncate(), self.c.truncate());
        let e_bc = edge(b, c, p);
        let e_ca = edge(c, a, p);
        let e_ab = edge(a, b, p);
        if inside(e_bc, b, c) && inside(e_ca, c, a) && inside(e_ab, a, b) {
            let z = (e_bc * self.a.z + e_ca * self.b.z + e_ab * self.c.z) / self.area;
            Some((z, blend_rgb10(self.colors, [e_bc, e_ca, e_ab], self.area)))
        } else {
            None
        }
    }

    fn lo(&self) -> Vec2 {
        self.a
            .truncate()
            .min(self.b.truncate())
            .min(self.c.truncate())
    }

    fn hi(&self) -> Vec2 {
        self.a
            .truncate()
            .max(self.b.truncate())
            .max(self.c.truncate())
    }
}

/// The pixels `[x0, x1] x [y0, y1]` a screen box `[lo, hi]` touches,
/// clamped to the screen; `None` when it misses the screen (or is NaN).
fn pixel_range(lo: Vec2, hi: Vec2, width: u32, height: u32) -> Option<[u32; 4]> {
    // Clamped in float first (saturating casts keep huge values harmless).
    let x0 = lo.x.floor().max(0.0);
    let y0 = lo.y.floor().max(0.0);
    let x1 = hi.x.floor().min(width as f32 - 1.0);
    let y1 = hi.y.floor().min(height as f32 - 1.0);
    if !(x0 <= x1 && y0 <= y1) {
        return None;
    }
    Some([x0 as u32, y0 as u32, x1 as u32, y1 as u32])
}

/// Tests sample `s` of pixel `(x, y)` against `placed`, offering its
/// fragment on a hit.
#[inline]
fn test(
    framebuffer: &mut Framebuffer,
    sampler: &Sampler<'_>,
    placed: &Placed,
    (x, y, s): (u32, u32, u32),
    stats: &mut RenderStats,
) {
    stats.samples_tested += 1;
    if let Some((z, color)) = placed.fragment_at(sampler.samples.position(x, y, s)) {
        stats.samples_hit += 1;
        framebuffer.offer(x, y, s, pack_key(key_depth(z), color));
    }
}

/// Places `corners` at sample `(x, y, s)`'s own time and lens `tl` and
/// tests the sample; a triangle without area there still counts as tested.
fn place_and_test(
    framebuffer: &mut Framebuffer,
    sampler: &Sampler<'_>,
    corners: &[MovingPoint; 3],
    colors: [u32; 3],
    tl: TimeLens,
    sample: (u32, u32, u32),
    stats: &mut RenderStats,
) {
    match place(corners, colors, tl) {
        Some(placed) => test(framebuffer, sampler, &placed, sample, stats),
        None => stats.samples_tested += 1,
    }
}

/// The mode a grid uses under [`Sampling::Adaptive`]: Interleave UVT when
/// INTERVAL's estimated sample tests exceed Interleave's by more than
/// [`ADAPTIVE_INTERLEAVE_BIAS`], else INTERVAL. For a micropolygon of about
/// a pixel, INTERVAL tests `spp` boxes of side about
/// `2 + motion / spp + 2 * blur` pixels, one sample per pixel each, and
/// Interleave UVT tests `spp * K^2` tuples, each in about `(1 + 1 / K)^2`
/// tiles. `motion` and `blur` are the grid's largest point motion and
/// circle of confusion, in pixels.
pub fn adaptive_choice(motion: f32, blur: f32, spp: u32) -> Mode5d {
    let side = 2.0 + motion / spp as f32 + 2.0 * blur;
    let k = INTERLEAVE_TILE as f32;
    let interleave = k * k * (1.0 + 1.0 / k) * (1.0 + 1.0 / k);
    // NaN (a point behind the eye) compares false: INTERVAL, as for a still grid.
    if side * side > ADAPTIVE_INTERLEAVE_BIAS * interleave {
        Mode5d::Interleave
    } else {
        Mode5d::Interval
    }
}

/// The 5D sampling algorithms ([`Sampling`] with Adaptive resolved per grid).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode5d {
    /// Bounding box.
    Bbox,
    /// Simple UVT.
    Simple,
    /// Interleave UVT.
    Interleave,
    /// INTERVAL.
    Interval,
}

impl Mode5d {
    /// The algorithm `sampling` uses for a grid whose largest point motion
    /// and circle of confusion are `motion` and `blur` pixels; `None` for
    /// [`Sampling::Nearest`].
    pub fn for_grid(sampling: Sampling, motion: f32, blur: f32, spp: u32) -> Option<Mode5d> {
        Some(match sampling {
            Sampling::Bbox => Mode5d::Bbox,
            Sampling::Simple => Mode5d::Simple,
            Sampling::Interleave => Mode5d::Interleave,
            Sampling::Interval => Mode5d::Interval,
            Sampling::Adaptive => adaptive_choice(motion, blur, spp),
            Sampling::Nearest => return None,
        })
    }
}

/// Rasterizes one moving, defocused triangle with `mode`; its corners carry
/// the packed `colors` (see [`crate::reference::raster::raster_triangle`]).
pub fn raster_triangle_5d(
    framebuffer: &mut Framebuffer,
    sampler: &Sampler<'_>,
    mode: Mode5d,
    corners: [MovingPoint; 3],
    colors: [u32; 3],
    stats: &mut RenderStats,
) {
    if !corners.iter().all(|c| c.usable) {
        return;
    }
    let (width, height) = (framebuffer.width, framebuffer.height);
    let uvt = sampler.uvt;
    let spp = uvt.spp;
    match mode {
        Mode5d::Bbox => {
            // Box over both ends, grown by the largest blur of the corners.
            let r = corners.iter().fold(0.0f32, |r, c| r.max(c.blur()));
            let ends = corners
                .iter()
                .flat_map(|c| [c.open.truncate(), c.close.truncate()]);
            let (lo, hi) = ends.fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p), hi.max(p))
            });
            let Some([x0, y0, x1, y1]) =
                pixel_range(lo - Vec2::splat(r), hi + Vec2::splat(r), width, height)
            else {
                return;
            };
            for y in y0..=y1 {
                for x in x0..=x1 {
                    for s in 0..spp {
                        let tl = uvt.pixel[uvt.pixel_index(x, y, s)];
                        place_and_test(
                            framebuffer,
                            sampler,
                            &corners,
                            colors,
                            tl,
                            (x, y, s),
                            stats,
                        );
                    }
                }
            }
        }
        Mode5d::Simple => {
            for (s, &tl) in uvt.simple.iter().enumerate() {
                let Some(placed) = place(&corners, colors, tl) else {
                    continue;
                };
                let Some([x0, y0, x1, y1]) = pixel_range(placed.lo(), placed.hi(), width, height)
                else {
                    continue;
                };
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        test(framebuffer, sampler, &placed, (x, y, s as u32), stats);
                    }
                }
            }
        }
        Mode5d::Interleave => {
            for (n, &tl) in uvt.interleave.iter().enumerate() {
                let Some(placed) = place(&corners, colors, tl) else {
                    continue;
                };
                let Some([x0, y0, x1, y1]) = pixel_range(placed.lo(), placed.hi(), width, height)
                else {
                    continue;
                };
                for ty in y0 / INTERLEAVE_TILE..=y1 / INTERLEAVE_TILE {
                    for tx in x0 / INTERLEAVE_TILE..=x1 / INTERLEAVE_TILE {
                        let (x, y, s) = uvt.interleave_sample(tx, ty, n as u32);
                        if x < width && y < height {
                            test(framebuffer, sampler, &placed, (x, y, s), stats);
                        }
                    }
                }
            }
        }
        Mode5d::Interval => {
            let n = spp as f32;
            // The times at which all three corners can be seen.
            let seen_from = corners.iter().fold(0.0f32, |t, c| t.max(c.t_open));
            let seen_until = corners.iter().fold(1.0f32, |t, c| t.min(c.t_close));
            for i in 0..spp {
                let (t0, t1) = (i as f32 / n, (i + 1) as f32 / n);
                if t1 < seen_from || t0 > seen_until {
                    continue;
                }
                let mut lo = Vec2::INFINITY;
                let mut hi = Vec2::NEG_INFINITY;
                let mut r = 0.0f32;
                for c in &corners {
                    let (p0, p1) = (c.at(t0, Vec2::ZERO), c.at(t1, Vec2::ZERO));
                    lo = lo.min(p0.truncate()).min(p1.truncate());
                    hi = hi.max(p0.truncate()).max(p1.truncate());
                    // The circle of confusion is linear in t: largest at an end.
                    r = r.max(c.coc_at(t0).abs()).max(c.coc_at(t1).abs());
                }
                let Some([x0, y0, x1, y1]) =
                    pixel_range(lo - Vec2::splat(r), hi + Vec2::splat(r), width, height)
                else {
                    continue;
                };
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        let s = uvt.sample_in_stratum[uvt.pixel_index(x, y, i)];
                        let tl = uvt.pixel[uvt.pixel_index(x, y, s)];
                        place_and_test(
                            framebuffer,
                            sampler,
                            &corners,
                            colors,
                            tl,
                            (x, y, s),
                            stats,
                        );
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec4;

    use super::visible_span;
    use crate::params::NEAR_EPS;

    /// A clip position with depth `z` and `w` (x and y do not matter).
    fn clip(z: f32, w: f32) -> Vec4 {
        Vec4::new(0.0, 0.0, z, w)
    }

    fn assert_span(open: Vec4, close: Vec4, expected: (f32, f32)) {
        let (lo, hi) = visible_span(open, close);
        assert!(
            (lo - expected.0).abs() < 1e-6 && (hi - expected.1).abs() < 1e-6,
            "{open} -> {close}: span ({lo}, {hi}), expected {expected:?}"
        );
    }

    #[test]
    fn a_point_in_view_at_both_ends_is_seen_during_the_whole_shutter() {
        assert_eq!(visible_span(clip(0.5, 2.0), clip(1.0, 3.0)), (0.0, 1.0));
    }

    #[test]
    fn a_point_crossing_the_near_plane_is_seen_until_it_does() {
        // z goes from 1 to -3: it reaches 0 a quarter into the shutter.
        assert_span(clip(1.0, 2.0), clip(-3.0, 0.5), (0.0, 0.25));
        // And the other way round: seen from three quarters on.
        assert_span(clip(-3.0, 0.5), clip(1.0, 2.0), (0.75, 1.0));
    }

    #[test]
    fn a_point_receding_past_the_far_plane_is_seen_until_it_does() {
        // w - z goes from 1 to -1: past the far plane from half-way.
        assert_span(clip(1.0, 2.0), clip(5.0, 4.0), (0.0, 0.5));
    }

    #[test]
    fn a_point_passing_behind_the_eye_is_seen_while_in_front_of_it() {
        // Depth 0 (on the near plane) throughout, w from 1 to -1: seen
        // while w > NEAR_EPS, up to just before half-way.
        let (lo, hi) = visible_span(clip(0.0, 1.0), clip(0.0, -1.0));
        assert_eq!(lo, 0.0);
        let expected = (1.0 - NEAR_EPS) / 2.0;
        assert!((hi - expected).abs() < 1e-7 && hi < 0.5, "{hi}");
    }

    #[test]
    fn a_point_out_of_view_throughout_or_not_finite_is_never_seen() {
        let never = |open, close| {
            let (lo, hi) = visible_span(open, close);
            assert!(lo > hi, "{open} -> {close}: ({lo}, {hi})");
        };
        never(clip(-1.0, 2.0), clip(-0.5, 3.0));
        never(clip(3.0, 2.0), clip(4.0, 3.0));
        never(clip(0.5, f32::NAN), clip(0.5, 1.0));
        never(clip(0.5, 1.0), clip(f32::INFINITY, 1.0));
    }
}
