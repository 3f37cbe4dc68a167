//! Rasterization of diced grids into the sample framebuffer.
//!
//! Two modes ([`crate::scene::Sampling`]):
//! * **bbox**: each micropolygon is split into triangles `(a, b, c)` and
//!   `(a, c, d)`; every sample in the strata that the micropolygon's box
//!   touches is tested once against both, with edge functions and a
//!   top-left fill rule ([`raster_quad`], see [`super::quad`]).
//!   [`raster_triangle`], a box per triangle over whole pixels, is what the
//!   renderer did before; it stays as the independent check of the quad
//!   test and for measuring what the quad boxes save
//!   ([`super::ReferenceOptions::triangle_boxes`]).
//! * **nearest**: each micropolygon tests only the sample nearest its
//!   centroid, and writes it if it lies inside (Sattlecker and Steinberger).

use glam::{Vec2, Vec3};

use super::framebuffer::Framebuffer;
use super::quad::{Quad, StrataBox, test_sample};
use crate::color::{blend_rgb10, pack_key};
use crate::dicing::GridSize;
use crate::params::NEAR_EPS;
use crate::sampling::sample_offset;
use crate::stats::RenderStats;

/// A grid point after projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenPoint {
    /// `(px, py, depth)` from [`crate::camera::Camera::to_pixel`].
    pub pixel: Vec3,
    /// Clip-space w.
    pub w: f32,
}

impl ScreenPoint {
    /// Usable as a triangle corner: `w > NEAR_EPS` and depth in `[0, 1]`.
    pub fn usable(&self) -> bool {
        self.w > NEAR_EPS && (0.0..=1.0).contains(&self.pixel.z)
    }
}

/// The sampling setup shared by every micropolygon of a frame.
#[derive(Debug, Clone)]
pub struct SampleGrid {
    /// Samples per pixel side (`k = sqrt(spp)`).
    pub k: u32,
    /// Whether samples are jittered.
    pub jitter: bool,
    /// The un-jittered offsets of the `k * k` samples, indexed by sample.
    offsets: Vec<Vec2>,
}

impl SampleGrid {
    /// The sample layout for `k * k` samples per pixel.
    pub fn new(k: u32, jitter: bool) -> SampleGrid {
        SampleGrid {
            k,
            jitter,
            offsets: (0..k * k)
                .map(|s| sample_offset(0, 0, s, k, false))
                .collect(),
        }
    }

    /// Position of sample `s` of pixel `(x, y)`.
    #[inline]
    pub(crate) fn position(&self, x: u32, y: u32, s: u32) -> Vec2 {
        if self.jitter {
            Vec2::new(x as f32, y as f32) + sample_offset(x, y, s, self.k, true)
        } else {
            Vec2::new(x as f32, y as f32) + self.offsets[s as usize]
        }
    }
}

/// `(b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)`: positive when `p`
/// is to the left of `a -> b` in a y-up frame (to the right on the y-down screen).
#[inline]
fn edge_raw(a: Vec2, b: Vec2, p: Vec2) -> f32 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// The edge function of `a -> b` at `p`, always computed from the
/// lexicographically smaller endpoint, so that the two triangles sharing an
/// edge get exactly opposite values (`E_ab = -E_ba` bit for bit). Without
/// this, rounding could leave a sample on a shared edge in both triangles or
/// in neither.
#[inline]
pub(crate) fn edge(a: Vec2, b: Vec2, p: Vec2) -> f32 {
    if a.x < b.x || (a.x == b.x && a.y <= b.y) {
        edge_raw(a, b, p)
    } else {
        -edge_raw(b, a, p)
    }
}

/// Top-left rule for a triangle with positive area (clockwise on the y-down
/// screen): the edge `a -> b` owns samples exactly on it if it is a *top* edge
/// (horizontal, pointing right: the triangle lies below it) or a *left* edge
/// (pointing up on the screen, `dy < 0`).
#[inline]
fn owns(a: Vec2, b: Vec2) -> bool {
    let d = b - a;
    d.y < 0.0 || (d.y == 0.0 && d.x > 0.0)
}

/// Whether a sample with edge value `e` is inside the half-plane of `a -> b`.
#[inline]
pub(crate) fn inside(e: f32, a: Vec2, b: Vec2) -> bool {
    e > 0.0 || (e == 0.0 && owns(a, b))
}

/// Clamps a depth into `[0, 1]` and turns -0.0 into +0.0, so its bit pattern
/// orders correctly inside a sample key.
#[inline]
pub(crate) fn key_depth(z: f32) -> f32 {
    let z = z.clamp(0.0, 1.0);
    if z == 0.0 { 0.0 } else { z }
}

/// Rasterizes one triangle in bbox mode, offering every covered sample the
/// interpolated depth and the blend of its corners' packed `colors`
/// ([`blend_rgb10`]; three equal colours for constant shading).
pub fn raster_triangle(
    framebuffer: &mut Framebuffer,
    samples: &SampleGrid,
    corners: [ScreenPoint; 3],
    colors: [u32; 3],
    stats: &mut RenderStats,
) {
    if !corners.iter().all(ScreenPoint::usable) {
        return;
    }
    let [pa, pb, pc] = corners.map(|c| c.pixel);
    let area = edge(pa.truncate(), pb.truncate(), pc.truncate());
    if area == 0.0 || !area.is_finite() {
        return;
    }
    // Normalise the orientation: with b and c swapped the area is positive,
    // and "inside" means every edge function is positive.
    let (pb, pc, colors) = if area < 0.0 {
        (pc, pb, [colors[0], colors[2], colors[1]])
    } else {
        (pb, pc, colors)
    };
    let area = area.abs();
    let (a, b, c) = (pa.truncate(), pb.truncate(), pc.truncate());

    let lo = a.min(b).min(c);
    let hi = a.max(b).max(c);
    // Saturating float-to-int casts keep huge coordinates harmless.
    let x0 = (lo.x.floor() as i64).max(0);
    let y0 = (lo.y.floor() as i64).max(0);
    let x1 = (hi.x.floor() as i64).min(i64::from(framebuffer.width) - 1);
    let y1 = (hi.y.floor() as i64).min(i64::from(framebuffer.height) - 1);
    if x0 > x1 || y0 > y1 {
        return;
    }
    let spp = samples.k * samples.k;
    for y in y0 as u32..=y1 as u32 {
        for x in x0 as u32..=x1 as u32 {
            for s in 0..spp {
                stats.samples_tested += 1;
                let p = samples.position(x, y, s);
                let e_bc = edge(b, c, p);
                let e_ca = edge(c, a, p);
                let e_ab = edge(a, b, p);
                if inside(e_bc, b, c) && inside(e_ca, c, a) && inside(e_ab, a, b) {
                    stats.samples_hit += 1;
                    let z = (e_bc * pa.z + e_ca * pb.z + e_ab * pc.z) / area;
                    let color = blend_rgb10(colors, [e_bc, e_ca, e_ab], area);
                    framebuffer.offer(x, y, s, pack_key(key_depth(z), color));
                }
            }
        }
    }
}

/// Rasterizes one micropolygon in bbox mode: every sample of the strata
/// its box touches is tested once against its drawn triangles, and offered
/// the interpolated depth and blended colour of each it is inside.
pub fn raster_quad(
    framebuffer: &mut Framebuffer,
    samples: &SampleGrid,
    quad: &Quad,
    stats: &mut RenderStats,
) {
    let Some((lo, hi)) = quad.bounds() else {
        return;
    };
    let Some(strata) = StrataBox::new(lo, hi, samples.k, framebuffer.width, framebuffer.height)
    else {
        return;
    };
    for (x, y, s) in strata.samples() {
        test_sample(
            framebuffer,
            quad,
            samples.position(x, y, s),
            (x, y, s),
            stats,
        );
    }
}

/// The quad of a still micropolygon's corners for [`raster_quad`]: a
/// triangle is drawn when `drawn` says so and its corners are usable.
pub fn still_quad(corners: [ScreenPoint; 4], colors: [u32; 4], drawn: [bool; 2]) -> Quad {
    let [a, b, c, d] = corners.map(|p| p.usable());
    Quad::new(
        corners.map(|p| p.pixel),
        colors,
        [drawn[0] && a && b && c, drawn[1] && a && c && d],
    )
}

/// Nearest mode: tests the one sample nearest the centroid of the
/// micropolygon's 4 corners (their averaged px, py): the sample whose
/// stratum contains the centroid (the nearest sample exactly when jitter
/// is off), and offers it the fragment of the triangle of `quad` it lies
/// in, if any (Sattlecker and Steinberger's inside test). Nothing is tested
/// when the centroid is off screen or a corner has `w <= NEAR_EPS`.
pub fn raster_nearest(
    framebuffer: &mut Framebuffer,
    samples: &SampleGrid,
    corners: [ScreenPoint; 4],
    quad: &Quad,
    stats: &mut RenderStats,
) {
    let k = samples.k;
    if !corners.iter().all(|c| c.w > NEAR_EPS) {
        return;
    }
    let centroid = corners.iter().map(|c| c.pixel).sum::<Vec3>() * 0.25;
    let (width, height) = (framebuffer.width as f32, framebuffer.height as f32);
    let on_screen =
        centroid.x >= 0.0 && centroid.x < width && centroid.y >= 0.0 && centroid.y < height;
    if !on_screen {
        return;
    }
    // Global sample column/row; the min() guards against rounding up to the edge.
    let gx = ((centroid.x * k as f32).floor() as u32).min(framebuffer.width * k - 1);
    let gy = ((centroid.y * k as f32).floor() as u32).min(framebuffer.height * k - 1);
    let (x, y) = (gx / k, gy / k);
    let s = (gy % k) * k + gx % k;
    test_sample(
        framebuffer,
        quad,
        samples.position(x, y, s),
        (x, y, s),
        stats,
    );
}

/// Whether triangle `(a, b, c)` of a grid (in grid order: `b` one step
/// along u from `a`, `c` one more along v) shows its front on screen, for
/// an object whose front faces along `front * (dP/du x dP/dv)`: with the
/// screen's y pointing down, that is a negative signed area `front *
/// E_ab(c) < 0` (edge-on and unprojectable triangles are not).
pub fn shows_front(a: Vec2, b: Vec2, c: Vec2, front: f32) -> bool {
    front * edge(a, b, c) < 0.0
}

/// Largest side of the pixel bounding box of 4 corners.
pub fn micropolygon_size(corners: &[ScreenPoint; 4]) -> f32 {
    let first = corners[0].pixel.truncate();
    let (lo, hi) = corners[1..].iter().fold((first, first), |(lo, hi), c| {
        (lo.min(c.pixel.truncate()), hi.max(c.pixel.truncate()))
    });
    let size = hi - lo;
    size.x.max(size.y)
}

/// The 4 corner values `a = (i, j)`, `b = (i+1, j)`, `c = (i+1, j+1)`,
/// `d = (i, j+1)` of micropolygon `(i, j)` of a grid of `size` whose point
/// `(i, j)` is `values[j * (nu + 1) + i]`.
pub fn micropolygon_corners<T: Copy>(values: &[T], size: GridSize, i: u32, j: u32) -> [T; 4] {
    debug_assert!(i < size.nu && j < size.nv);
    let at = |i: u32, j: u32| values[(j * (size.nu + 1) + i) as usize];
    [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]
}

#[cfg(test)]
mod tests;
