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
//! which (micropolygon position, sample) pairs to test; the test itself is
//! the plain path's quad test ([`super::quad`]): both triangles of the
//! micropolygon positioned at the sample's time and lens position, with
//! edge functions and the top-left rule. Boxes are clamped to the sample
//! strata they touch. Every tested pair counts in `samples_tested`, every
//! sample inside in `samples_hit`, and every sample a loop reached but
//! skipped for its stratum (Interleave UVT's tiles, INTERVAL's pixels) in
//! `samples_skipped`.

use glam::{Vec2, Vec3, Vec4};

use super::framebuffer::Framebuffer;
use super::quad::{Quad, StrataBox, test_sample};
use super::raster::SampleGrid;
use super::shutter::clip_at;
pub use super::shutter::visible_span;
use crate::camera::Camera;
use crate::motion::PreparedLens;
use crate::params::{ADAPTIVE_PLACE_COST, NEAR_EPS};
use crate::scene::Sampling;
use crate::stats::RenderStats;
use crate::uvt::{PixelTuples, TimeLens, UvtTables};

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
    /// Which tuples the bounding box and INTERVAL give a pixel's samples
    /// (Adaptive: the Interleave tuples).
    pub pixel_tuples: PixelTuples,
    /// The side of a micropolygon in pixels that Adaptive's cost model
    /// assumes ([`crate::prepare::PreparedScene::nominal_micropolygon_px`]).
    pub micropolygon_px: f32,
}

/// The corners of each triangle of a quad `[a, b, c, d]`: `(a, b, c)` and
/// `(a, c, d)`, split along the 0–2 diagonal.
const TRIANGLE_CORNERS: [[usize; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

/// A micropolygon over the shutter: its corners, their colours, and which
/// of its triangles may be drawn at all (not culled, every corner usable).
#[derive(Debug, Clone, Copy)]
struct MovingQuad {
    corners: [MovingPoint; 4],
    colors: [u32; 4],
    active: [bool; 2],
}

impl MovingQuad {
    /// The quad at time and lens `tl`: a triangle is drawn when it is
    /// active and all its corners can be seen at `tl.t`.
    fn place(&self, tl: TimeLens) -> Quad {
        let drawn = |t: usize| {
            self.active[t]
                && TRIANGLE_CORNERS[t]
                    .iter()
                    .all(|&i| self.corners[i].visible_at(tl.t))
        };
        Quad::new(
            self.corners.map(|c| c.at(tl.t, tl.lens)),
            self.colors,
            [drawn(0), drawn(1)],
        )
    }

    /// The corners of the active triangles that can all be seen at some
    /// time of `[t0, t1]`.
    fn corners_seen(&self, t0: f32, t1: f32) -> impl Iterator<Item = &MovingPoint> + '_ {
        let mut used = [false; 4];
        for (t, corners) in TRIANGLE_CORNERS.iter().enumerate() {
            let seen_from = corners
                .iter()
                .fold(0.0f32, |from, &i| from.max(self.corners[i].t_open));
            let seen_until = corners
                .iter()
                .fold(1.0f32, |until, &i| until.min(self.corners[i].t_close));
            if self.active[t] && seen_from <= t1 && seen_until >= t0 {
                for &i in corners {
                    used[i] = true;
                }
            }
        }
        self.corners
            .iter()
            .zip(used)
            .filter_map(|(c, used)| used.then_some(c))
    }
}

/// Places `quad` at sample `(x, y, s)`'s own time and lens `tl` and tests
/// the sample once against both triangles; a quad without a triangle
/// there still counts as tested.
fn place_and_test(
    framebuffer: &mut Framebuffer,
    sampler: &Sampler<'_>,
    quad: &MovingQuad,
    tl: TimeLens,
    sample: (u32, u32, u32),
    stats: &mut RenderStats,
) {
    test(framebuffer, sampler, &quad.place(tl), sample, stats);
}

/// Tests sample `(x, y, s)` against a placed quad, offering its fragments.
#[inline]
fn test(
    framebuffer: &mut Framebuffer,
    sampler: &Sampler<'_>,
    quad: &Quad,
    (x, y, s): (u32, u32, u32),
    stats: &mut RenderStats,
) {
    let position = sampler.samples.position(x, y, s);
    test_sample(framebuffer, quad, position, (x, y, s), stats);
}

/// Adaptive's estimate of the cost of one micropolygon under INTERVAL and
/// under Interleave UVT, in units of one sample test (Adaptive picks the
/// cheaper, [`adaptive_choice`]).
///
/// For a micropolygon of side `m` pixels whose corners move up to
/// `motion` pixels over the shutter and blur up to `blur` pixels:
///
/// * INTERVAL draws `spp` boxes, one per time interval, each of side about
///   `m + motion / spp + 2 * blur / k` (the motion within the interval,
///   and the circle of confusion over the interval's lens region, `2 / k`
///   of the lens across), and tests the one sample per pixel of that
///   interval whose stratum the box touches: about `(side + 1 / k)^2`
///   tests, each of which places the quad at its sample's time and lens.
/// * Interleave UVT places the quad once per tuple, `spp * K^2` times, and
///   looks up one sample in each `K x K` tile the placed quad's box
///   touches, about `(1 + m / K)^2` of them.
///
/// A placement costs [`ADAPTIVE_PLACE_COST`] tests.
pub fn adaptive_costs(
    motion: f32,
    blur: f32,
    micropolygon_px: f32,
    spp: u32,
    tile: u32,
) -> (f32, f32) {
    let n = spp as f32;
    let k = n.sqrt();
    let kt = tile as f32;
    let side = micropolygon_px + motion / n + 2.0 * blur / k + 1.0 / k;
    let interval = n * side * side * (1.0 + ADAPTIVE_PLACE_COST);
    let tiles = (1.0 + micropolygon_px / kt) * (1.0 + micropolygon_px / kt);
    let interleave = n * kt * kt * (ADAPTIVE_PLACE_COST + tiles);
    (interval, interleave)
}

/// The mode a grid uses under [`Sampling::Adaptive`]: Interleave UVT when
/// its estimated cost ([`adaptive_costs`]) is below INTERVAL's, else
/// INTERVAL. `motion` and `blur` are the grid's largest point motion and
/// circle of confusion, in pixels.
pub fn adaptive_choice(
    motion: f32,
    blur: f32,
    micropolygon_px: f32,
    spp: u32,
    tile: u32,
) -> Mode5d {
    let (interval, interleave) = adaptive_costs(motion, blur, micropolygon_px, spp, tile);
    // NaN (a point behind the eye) compares false: INTERVAL, as for a still grid.
    if interleave < interval {
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
    pub fn for_grid(
        sampling: Sampling,
        motion: f32,
        blur: f32,
        sampler: &Sampler<'_>,
    ) -> Option<Mode5d> {
        Some(match sampling {
            Sampling::Bbox => Mode5d::Bbox,
            Sampling::Simple => Mode5d::Simple,
            Sampling::Interleave => Mode5d::Interleave,
            Sampling::Interval => Mode5d::Interval,
            Sampling::Adaptive => adaptive_choice(
                motion,
                blur,
                sampler.micropolygon_px,
                sampler.uvt.spp,
                sampler.uvt.tiles.tile,
            ),
            Sampling::Nearest => return None,
        })
    }
}

/// Rasterizes one moving, defocused micropolygon `[a, b, c, d]` with
/// `mode`: its triangles `(a, b, c)` and `(a, c, d)` (those `drawn`) share
/// one box per position, clamped to the sample strata it touches, and each
/// sample in it is tested once against both. Its corners carry the packed
/// `colors`.
pub fn raster_quad_5d(
    framebuffer: &mut Framebuffer,
    sampler: &Sampler<'_>,
    mode: Mode5d,
    corners: [MovingPoint; 4],
    colors: [u32; 4],
    drawn: [bool; 2],
    stats: &mut RenderStats,
) {
    let active = |t: usize| drawn[t] && TRIANGLE_CORNERS[t].iter().all(|&i| corners[i].usable);
    let quad = MovingQuad {
        corners,
        colors,
        active: [active(0), active(1)],
    };
    if !quad.active.iter().any(|&a| a) {
        return;
    }
    let (width, height) = (framebuffer.width, framebuffer.height);
    let uvt = sampler.uvt;
    let spp = uvt.spp;
    let k = sampler.samples.k;
    let strata = |lo: Vec2, hi: Vec2| StrataBox::new(lo, hi, k, width, height);
    match mode {
        Mode5d::Bbox => {
            // Box over both ends, grown by the largest blur of the corners.
            let (mut lo, mut hi, mut r) = (Vec2::INFINITY, Vec2::NEG_INFINITY, 0.0f32);
            for c in quad.corners_seen(0.0, 1.0) {
                lo = lo.min(c.open.truncate()).min(c.close.truncate());
                hi = hi.max(c.open.truncate()).max(c.close.truncate());
                r = r.max(c.blur());
            }
            let Some(strata) = strata(lo - Vec2::splat(r), hi + Vec2::splat(r)) else {
                return;
            };
            for (x, y, s) in strata.samples() {
                let tl = uvt.pixel_tuple(sampler.pixel_tuples, x, y, s);
                place_and_test(framebuffer, sampler, &quad, tl, (x, y, s), stats);
            }
        }
        Mode5d::Simple => {
            for (s, &tl) in uvt.simple.iter().enumerate() {
                let s = s as u32;
                let placed = quad.place(tl);
                let Some(strata) = placed.bounds().and_then(|(lo, hi)| strata(lo, hi)) else {
                    continue;
                };
                let (Some((x0, x1)), Some((y0, y1))) =
                    (strata.columns_of(s % k), strata.rows_of(s / k))
                else {
                    continue;
                };
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        test(framebuffer, sampler, &placed, (x, y, s), stats);
                    }
                }
            }
        }
        Mode5d::Interleave => {
            let tile = uvt.tiles.tile;
            for (n, &tl) in uvt.interleave.iter().enumerate() {
                let placed = quad.place(tl);
                let Some(strata) = placed.bounds().and_then(|(lo, hi)| strata(lo, hi)) else {
                    continue;
                };
                let [x0, y0, x1, y1] = strata.pixels();
                for ty in y0 / tile..=y1 / tile {
                    for tx in x0 / tile..=x1 / tile {
                        let (x, y, s) = uvt.interleave_sample(tx, ty, n as u32);
                        if x < width && y < height && strata.holds(x, y, s) {
                            test(framebuffer, sampler, &placed, (x, y, s), stats);
                        } else {
                            stats.samples_skipped += 1;
                        }
                    }
                }
            }
        }
        Mode5d::Interval => {
            let n = spp as f32;
            for i in 0..spp {
                let (t0, t1) = (i as f32 / n, (i + 1) as f32 / n);
                // The lens positions of this interval's samples.
                let [lens_lo, lens_hi] = uvt.interval_lens[i as usize];
                let mut lo = Vec2::INFINITY;
                let mut hi = Vec2::NEG_INFINITY;
                for c in quad.corners_seen(t0, t1) {
                    // A point's position is bilinear in time and lens
                    // position: its extremes lie at the ends of both.
                    for t in [t0, t1] {
                        for lens in [lens_lo, lens_hi] {
                            let p = c.at(t, lens).truncate();
                            lo = lo.min(p);
                            hi = hi.max(p);
                        }
                    }
                }
                let Some(strata) = strata(lo, hi) else {
                    continue;
                };
                let [x0, y0, x1, y1] = strata.pixels();
                for y in y0..=y1 {
                    for x in x0..=x1 {
                        let s = uvt.pixel_sample_in_stratum(sampler.pixel_tuples, x, y, i);
                        if strata.holds(x, y, s) {
                            let tl = uvt.pixel_tuple(sampler.pixel_tuples, x, y, s);
                            place_and_test(framebuffer, sampler, &quad, tl, (x, y, s), stats);
                        } else {
                            stats.samples_skipped += 1;
                        }
                    }
                }
            }
        }
    }
}
