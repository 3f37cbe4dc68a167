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
mod tests {
    use super::*;
    use crate::color::CLEAR_KEY;

    fn point(x: f32, y: f32) -> ScreenPoint {
        ScreenPoint {
            pixel: Vec3::new(x, y, 0.5),
            w: 1.0,
        }
    }

    /// Two triangles sharing an edge (a quad split along its diagonal, and a
    /// quad with a shared horizontal and vertical edge through sample
    /// positions): every sample inside the union is hit exactly once.
    #[test]
    fn shared_edges_are_watertight() {
        // Dense samples: 8x8 per pixel, 16x16 pixels; corners placed exactly on
        // sample rows/columns and on irrational-ish positions.
        let quads: [[(f32, f32); 4]; 4] = [
            [(1.0, 1.0), (15.0, 1.0), (15.0, 15.0), (1.0, 15.0)],
            [(0.0625, 2.0625), (13.3, 0.7), (15.1, 14.2), (2.2, 12.9)],
            [(3.0, 0.5), (12.5, 3.0), (9.0, 15.5), (0.5, 9.0)],
            [
                (8.0625, 0.0625),
                (15.9375, 8.0625),
                (8.0625, 15.9375),
                (0.0625, 8.0625),
            ],
        ];
        for quad in quads {
            for flip in [false, true] {
                let [a, b, c, d] = quad.map(|(x, y)| point(x, y));
                // Orientation must not matter: also try the mirrored winding.
                let (b, d) = if flip { (d, b) } else { (b, d) };
                let k = 8;
                let samples = SampleGrid::new(k, false);
                let mut hits = vec![0u32; 16 * 16 * 64];
                let mut stats = RenderStats::default();
                for (t, tri) in [[a, b, c], [a, c, d]].into_iter().enumerate() {
                    let mut fb = Framebuffer::new(16, 16, k * k);
                    raster_triangle(&mut fb, &samples, tri, [t as u32; 3], &mut stats);
                    for (count, key) in hits.iter_mut().zip(&fb.keys) {
                        *count += u32::from(*key != CLEAR_KEY);
                    }
                }
                // Compare with an exact point-in-convex-quad test in f64.
                let poly = [a, b, c, d].map(|p| (f64::from(p.pixel.x), f64::from(p.pixel.y)));
                let fb = Framebuffer::new(16, 16, k * k);
                let mut inside_count = 0;
                for y in 0..16 {
                    for x in 0..16 {
                        for s in 0..k * k {
                            let p = samples.position(x, y, s);
                            let (px, py) = (f64::from(p.x), f64::from(p.y));
                            let sides: Vec<f64> = (0..4)
                                .map(|e| {
                                    let (ax, ay) = poly[e];
                                    let (bx, by) = poly[(e + 1) % 4];
                                    (bx - ax) * (py - ay) - (by - ay) * (px - ax)
                                })
                                .collect();
                            let strictly_in =
                                sides.iter().all(|&v| v > 0.0) || sides.iter().all(|&v| v < 0.0);
                            let strictly_out =
                                sides.iter().any(|&v| v > 0.0) && sides.iter().any(|&v| v < 0.0);
                            let n = hits[fb.index(x, y, s)];
                            assert!(n <= 1, "sample hit {n} times at ({x},{y},{s}) in {quad:?}");
                            if strictly_in {
                                inside_count += 1;
                                assert_eq!(n, 1, "hole at ({x},{y},{s}) in {quad:?}");
                            }
                            if strictly_out {
                                assert_eq!(n, 0, "hit outside at ({x},{y},{s})");
                            }
                        }
                    }
                }
                assert!(inside_count > 1000);
                assert_eq!(
                    stats.samples_hit,
                    hits.iter().map(|&h| u64::from(h)).sum::<u64>()
                );
            }
        }
    }

    #[test]
    fn top_left_rule_on_a_grid_of_squares() {
        // A 4x4 tiling of squares whose edges lie exactly on sample positions
        // (spp 1: samples at pixel centres, squares with corners on centres).
        let k = 1;
        let samples = SampleGrid::new(k, false);
        let mut fb_hits = vec![0u32; 8 * 8];
        let mut stats = RenderStats::default();
        for j in 0..4 {
            for i in 0..4 {
                let (x0, y0) = (0.5 + i as f32 * 1.0, 0.5 + j as f32 * 1.0);
                let a = point(x0, y0);
                let b = point(x0 + 1.0, y0);
                let c = point(x0 + 1.0, y0 + 1.0);
                let d = point(x0, y0 + 1.0);
                for tri in [[a, b, c], [a, c, d]] {
                    let mut fb = Framebuffer::new(8, 8, 1);
                    raster_triangle(&mut fb, &samples, tri, [0; 3], &mut stats);
                    for (h, key) in fb_hits.iter_mut().zip(&fb.keys) {
                        *h += u32::from(*key != CLEAR_KEY);
                    }
                }
            }
        }
        // The union covers centres (0.5..=4.5)^2; with the top-left rule the
        // top and left boundary rows/columns are in, bottom and right are out:
        // exactly pixels 0..4 x 0..4, each once.
        for y in 0..8 {
            for x in 0..8 {
                let expected = u32::from(x < 4 && y < 4);
                assert_eq!(fb_hits[y * 8 + x], expected, "pixel ({x},{y})");
            }
        }
    }

    /// The square of side `side` with its top-left corner at `(x, y)`.
    fn square(x: f32, y: f32, side: f32) -> [ScreenPoint; 4] {
        [
            point(x, y),
            point(x + side, y),
            point(x + side, y + side),
            point(x, y + side),
        ]
    }

    /// Nearest-mode rasterization of the drawn quad of `corners`.
    fn nearest(
        fb: &mut Framebuffer,
        samples: &SampleGrid,
        corners: [ScreenPoint; 4],
        stats: &mut RenderStats,
    ) {
        let quad = still_quad(corners, [7; 4], [true; 2]);
        raster_nearest(fb, samples, corners, &quad, stats);
    }

    #[test]
    fn nearest_picks_the_stratum_of_the_centroid() {
        let mut fb = Framebuffer::new(4, 4, 4);
        let mut stats = RenderStats::default();
        let samples = SampleGrid::new(2, false);
        nearest(&mut fb, &samples, square(2.6, 1.1, 0.3), &mut stats);
        // Centroid (2.75, 1.25): pixel (2, 1), sample column 1, row 0 -> s = 1,
        // at (2.75, 1.25): inside.
        let i = fb.index(2, 1, 1);
        assert_ne!(fb.keys[i], CLEAR_KEY);
        assert_eq!(fb.keys.iter().filter(|&&k| k != CLEAR_KEY).count(), 1);
        assert_eq!((stats.samples_tested, stats.samples_hit), (1, 1));
        nearest(&mut fb, &samples, square(-2.0, 1.0, 1.0), &mut stats);
        assert_eq!((stats.samples_tested, stats.samples_hit), (1, 1));
    }

    /// Sattlecker and Steinberger's inside test: a micropolygon whose
    /// nearest sample lies outside it writes nothing (the old nearest mode
    /// wrote every centroid's sample).
    #[test]
    fn nearest_writes_no_sample_outside_the_micropolygon() {
        let mut fb = Framebuffer::new(4, 4, 1);
        let mut stats = RenderStats::default();
        let samples = SampleGrid::new(1, false);
        // A sliver around (2.1, 1.1): its nearest sample, the centre
        // (2.5, 1.5) of pixel (2, 1), is outside it.
        nearest(&mut fb, &samples, square(2.0, 1.0, 0.2), &mut stats);
        assert!(fb.keys.iter().all(|&k| k == CLEAR_KEY));
        assert_eq!((stats.samples_tested, stats.samples_hit), (1, 0));
    }

    /// Random quads (convex, concave, folded, some degenerate) against the
    /// per-triangle rasterizer: the same framebuffer and hits, and fewer
    /// tests over all. Prints its seed; `TEST_SEED` replays it.
    #[test]
    fn quads_match_their_triangles_with_fewer_tests() {
        use rand::Rng;
        let (seed, mut rng) = crate::test_random::fresh_rng("raster quads");
        let (mut quad_tests, mut triangle_tests) = (0, 0);
        for case in 0..300 {
            let k = [1, 2, 3, 4][case % 4];
            let jitter = case % 3 == 0;
            let samples = SampleGrid::new(k, jitter);
            let size = [0.3, 1.0, 3.0][case % 3];
            let centre = Vec2::new(rng.random_range(1.0..7.0), rng.random_range(1.0..7.0));
            let mut corners = [0; 4].map(|_| {
                let p = centre
                    + Vec2::new(rng.random_range(-size..size), rng.random_range(-size..size));
                ScreenPoint {
                    pixel: Vec3::new(p.x, p.y, rng.random_range(0.0..1.0)),
                    w: 1.0,
                }
            });
            if case % 7 == 0 {
                // A collapsed edge: one degenerate triangle.
                corners[1] = corners[0];
            }
            let colors = [0x0010_0401, 0x0020_0802, 0x0030_0c03, 0x0040_1004];
            let drawn = [case % 5 != 1, case % 5 != 2];
            let mut by_quad = Framebuffer::new(8, 8, k * k);
            let mut stats_quad = RenderStats::default();
            raster_quad(
                &mut by_quad,
                &samples,
                &still_quad(corners, colors, drawn),
                &mut stats_quad,
            );
            let mut by_triangle = Framebuffer::new(8, 8, k * k);
            let mut stats_triangle = RenderStats::default();
            let [a, b, c, d] = corners;
            let [ca, cb, cc, cd] = colors;
            for (i, (tri, cols)) in [([a, b, c], [ca, cb, cc]), ([a, c, d], [ca, cc, cd])]
                .into_iter()
                .enumerate()
            {
                if drawn[i] {
                    raster_triangle(&mut by_triangle, &samples, tri, cols, &mut stats_triangle);
                }
            }
            assert!(
                by_quad.keys == by_triangle.keys,
                "seed {seed}, case {case}: the framebuffers differ"
            );
            let covered = by_quad.keys.iter().filter(|&&k| k != CLEAR_KEY).count() as u64;
            assert_eq!(stats_quad.samples_hit, covered, "seed {seed}, case {case}");
            quad_tests += stats_quad.samples_tested;
            triangle_tests += stats_triangle.samples_tested;
        }
        println!("seed {seed}: {quad_tests} quad tests, {triangle_tests} triangle tests");
        // About half as many on these random quads (a third to a half of
        // a pixel box's strata lie outside a triangle's box); never near as
        // many.
        assert!(
            quad_tests * 4 < triangle_tests * 3,
            "{quad_tests} vs {triangle_tests}"
        );
    }

    #[test]
    fn skips_triangles_behind_the_eye_or_outside_depth() {
        let mut fb = Framebuffer::new(8, 8, 1);
        let mut stats = RenderStats::default();
        let samples = SampleGrid::new(1, false);
        let mut behind = [point(0.0, 0.0), point(8.0, 0.0), point(0.0, 8.0)];
        behind[1].w = 0.0;
        raster_triangle(&mut fb, &samples, behind, [0; 3], &mut stats);
        let mut beyond = [point(0.0, 0.0), point(8.0, 0.0), point(0.0, 8.0)];
        beyond[2].pixel.z = 1.5;
        raster_triangle(&mut fb, &samples, beyond, [0; 3], &mut stats);
        assert_eq!(stats.samples_tested, 0);
        assert!(fb.keys.iter().all(|&k| k == CLEAR_KEY));
    }
}
