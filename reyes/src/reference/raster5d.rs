//! Rasterization with motion blur and depth of field: the sampling modes
//! Bounding box, Simple UVT, Interleave UVT, INTERVAL and Adaptive
//! ([`crate::scene::Sampling`]).
//!
//! A micropolygon corner is known at shutter open and close
//! ([`MovingPoint`]); a sample with time `t` and lens position `l` sees it
//! at `lerp(open, close, t) + l * lerp(coc_open, coc_close, t)` in pixels
//! (depth interpolated likewise), see [`crate::motion`]. Each mode decides
//! which (triangle position, sample) pairs to test; the test itself is the
//! plain path's edge-function test with the top-left rule, done on the
//! triangle positioned at the sample's time and lens position. Every tested
//! pair counts in `samples_tested`, every hit in `samples_hit`.

use glam::{Vec2, Vec3};

use super::framebuffer::Framebuffer;
use super::raster::{SampleGrid, edge, inside, key_depth};
use crate::color::{blend_rgb10, pack_key};
use crate::params::{ADAPTIVE_INTERLEAVE_BIAS, NEAR_EPS};
use crate::scene::Sampling;
use crate::stats::RenderStats;
use crate::uvt::{INTERLEAVE_TILE, TimeLens, UvtTables};

/// A grid point at shutter open and close.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MovingPoint {
    /// `(px, py, depth)` at open.
    pub open: Vec3,
    /// `(px, py, depth)` at close.
    pub close: Vec3,
    /// Signed circle of confusion (pixels) at open.
    pub coc_open: f32,
    /// Signed circle of confusion (pixels) at close.
    pub coc_close: f32,
    /// Whether the point can be a triangle corner at both ends: clip
    /// `w > NEAR_EPS` and depth in `[0, 1]` at open and at close.
    pub usable: bool,
}

impl MovingPoint {
    /// The point from its projections (`pixel`, clip `w`) and circles of
    /// confusion at open and close.
    pub fn new(open: Vec3, w_open: f32, close: Vec3, w_close: f32, coc: [f32; 2]) -> MovingPoint {
        let ok = |p: Vec3, w: f32| w > NEAR_EPS && (0.0..=1.0).contains(&p.z);
        MovingPoint {
            open,
            close,
            coc_open: coc[0],
            coc_close: coc[1],
            usable: ok(open, w_open) && ok(close, w_close),
        }
    }

    /// Where a sample at `t` through lens position `lens` sees the point.
    #[inline]
    pub fn at(&self, t: f32, lens: Vec2) -> Vec3 {
        let p = self.open + (self.close - self.open) * t;
        let coc = self.coc_open + (self.coc_close - self.coc_open) * t;
        Vec3::new(p.x + lens.x * coc, p.y + lens.y * coc, p.z)
    }

    /// The point's screen motion during the shutter, in pixels.
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

/// Positions triangle `corners` at `(t, lens)`; `None` when it has no area
/// there (degenerate, or not finite).
fn place(corners: &[MovingPoint; 3], colors: [u32; 3], tl: TimeLens) -> Option<Placed> {
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
            for i in 0..spp {
                let (t0, t1) = (i as f32 / n, (i + 1) as f32 / n);
                let mut lo = Vec2::INFINITY;
                let mut hi = Vec2::NEG_INFINITY;
                let mut r = 0.0f32;
                for c in &corners {
                    let (p0, p1) = (c.at(t0, Vec2::ZERO), c.at(t1, Vec2::ZERO));
                    lo = lo.min(p0.truncate()).min(p1.truncate());
                    hi = hi.max(p0.truncate()).max(p1.truncate());
                    // The circle of confusion is linear in t: largest at an end.
                    let coc = |t: f32| c.coc_open + (c.coc_close - c.coc_open) * t;
                    r = r.max(coc(t0).abs()).max(coc(t1).abs());
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
