//! Watertightness, ownership and sampling checks of the still rasterizer.

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
            let p =
                centre + Vec2::new(rng.random_range(-size..size), rng.random_range(-size..size));
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
