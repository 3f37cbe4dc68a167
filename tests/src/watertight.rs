//! An independent reference for where a scene's surfaces cover the image,
//! and the crack count that compares a multisampled render with it.
//!
//! The reference shares nothing with the renderer but the patch evaluation
//! and the camera: it tessellates every input patch densely and uniformly
//! (no splitting, no dicing, no sample positions) and marks the pixels whose
//! centres lie inside any projected triangle. Away from silhouettes, a
//! watertight render of a closed surface covers every sample of every pixel
//! the reference covers; a crack is a pixel there that lost samples.

use reyes::prepare::PreparedScene;

/// Clip `w` at or below which a point cannot be projected (the renderer's
/// `NEAR_EPS`): triangles with such a corner are skipped.
const NEAR_W: f32 = 1e-5;

/// Half the side of the neighbourhood that must lie inside the reference
/// coverage for a pixel to count in [`cracks`]: 5 x 5 pixels, so that a
/// pixel within 2 pixels of a silhouette (where partial coverage is correct)
/// is never a crack.
const NEIGHBOURHOOD_RADIUS: u32 = 2;

/// The pixels of `prepared`'s image whose centres lie on a surface, from a
/// dense uniform tessellation of every patch: each patch is evaluated on a
/// grid of `samples_per_patch_side x samples_per_patch_side` points (at
/// least 2), projected, and its triangles are rasterized at pixel centres,
/// edges included. Triangles with a corner at clip `w <= 1e-5` (at or
/// behind the eye) are skipped; nothing else is clipped, so a scene meant
/// for crack counting should keep its surfaces beyond the near plane, where
/// the renderer draws everything too.
///
/// The triangles are chords of the surface, so on convex parts the
/// reference lies slightly inside the true silhouette: by about
/// `L^2 / (8 R)` pixels for a projected grid step of `L` pixels on a curve
/// of projected radius `R` pixels. Choose `samples_per_patch_side` so that
/// this is far below a pixel; [`cracks`] ignores the 2 pixels along every
/// silhouette anyway.
///
/// Returns the mask row-major, `width * height` of the prepared camera.
pub fn dense_coverage(prepared: &PreparedScene, samples_per_patch_side: u32) -> Vec<bool> {
    let camera = &prepared.camera;
    let width = camera.width as usize;
    let mut mask = vec![false; width * camera.height as usize];
    rasterize(prepared, samples_per_patch_side, 1, |x, y, _, _| {
        mask[y * width + x] = true;
    });
    mask
}

/// Which patches of `prepared` can be seen: all but those that are
/// clearly hidden, i.e. that cover some point of a `k x k` grid in some
/// pixel (`k = samples_per_pixel_side`: the centres of the strata of a
/// `k * k`-spp render, where its samples lie without jitter) and lie, at
/// every such point they cover, more than `depth_margin` (a fraction of the
/// view depth) behind the nearest surface there. From the same dense
/// tessellation as [`dense_coverage`] with a depth test.
///
/// Why: the renderers draw every surface two-sided, so behind a crack in a
/// closed surface's front layer lies its back layer, which covers the
/// samples the crack lost: coverage alone cannot see a crack there. A model
/// without its clearly hidden patches covers the same samples as the whole
/// model but lets the background show through a crack in front. The margin
/// keeps what the dense tessellation and a render could disagree about:
/// patches that are nearly as near as the front somewhere (where surfaces
/// touch, and behind internal silhouettes, where the render's chords end
/// the front layer a little earlier and the next layer shows), and patches
/// too small or too thin to cover any grid point. The dicing of a kept
/// patch does not depend on the patches dropped (an edge's vertices are a
/// function of the edge's curve), so the kept ones are diced as in the
/// whole model.
pub fn visible_patches(
    prepared: &PreparedScene,
    samples_per_patch_side: u32,
    samples_per_pixel_side: u32,
    depth_margin: f64,
) -> Vec<bool> {
    let camera = &prepared.camera;
    let k = samples_per_pixel_side.max(1) as usize;
    let width = camera.width as usize * k;
    let nearest = nearest_inverse_depth(prepared, samples_per_patch_side, k);
    let mut covers_a_point = vec![false; prepared.patches.len()];
    let mut near_the_front = vec![false; prepared.patches.len()];
    rasterize(
        prepared,
        samples_per_patch_side,
        k,
        |x, y, inverse_depth, patch| {
            covers_a_point[patch] = true;
            // w <= w_nearest * (1 + margin), in inverse depths.
            near_the_front[patch] |= inverse_depth * (1.0 + depth_margin) >= nearest[y * width + x];
        },
    );
    covers_a_point
        .iter()
        .zip(&near_the_front)
        .map(|(&covers, &near)| near || !covers)
        .collect()
}

/// The pixels of `prepared`'s image where the nearest surface is smooth:
/// it covers all `k x k` grid points of the pixel (`k =
/// samples_per_pixel_side`, as in [`visible_patches`]) and its view depth
/// changes by at most `max_relative_step` (a fraction of the depth) from
/// each of these points to the next one across and down, within the pixel
/// and into its neighbours. From the same dense tessellation as
/// [`dense_coverage`] with a depth test.
///
/// Why: at a silhouette inside the coverage (where a surface folds away and
/// the next layer shows behind it, or where a surface is seen nearly edge
/// on) the render's chords and the reference's end the front layer in
/// different places, so a sample there may see the next layer in one and
/// not in the other; coverage cannot tell that from a crack. Counting
/// cracks only where the front is smooth (and 2 pixels away, by the 5 x 5
/// rule of [`cracks`]) leaves out the silhouettes and keeps every seam
/// between pieces of a smooth surface, where cracks open.
pub fn smooth_front(
    prepared: &PreparedScene,
    samples_per_patch_side: u32,
    samples_per_pixel_side: u32,
    max_relative_step: f64,
) -> Vec<bool> {
    let camera = &prepared.camera;
    let k = samples_per_pixel_side.max(1) as usize;
    let (width, height) = (camera.width as usize, camera.height as usize);
    let (fine_width, fine_height) = (width * k, height * k);
    let nearest = nearest_inverse_depth(prepared, samples_per_patch_side, k);
    // Whether fine point (x, y) is covered and close in depth to the next
    // point across and the next point down (where those are in the image).
    let smooth_point = |x: usize, y: usize| {
        let here = nearest[y * fine_width + x];
        let close =
            |other: f64| other > 0.0 && (here - other).abs() <= max_relative_step * here.max(other);
        here > 0.0
            && (x + 1 >= fine_width || close(nearest[y * fine_width + x + 1]))
            && (y + 1 >= fine_height || close(nearest[(y + 1) * fine_width + x]))
    };
    let mut smooth = vec![false; width * height];
    for y in 0..height {
        for x in 0..width {
            // The pixel's own points, and the last column and row of the
            // pixels to its left and above, whose steps lead into it.
            let (x0, y0) = ((x * k).saturating_sub(1), (y * k).saturating_sub(1));
            smooth[y * width + x] =
                (y0..(y + 1) * k).all(|fy| (x0..(x + 1) * k).all(|fx| smooth_point(fx, fy)));
        }
    }
    smooth
}

/// The nearest surface's inverse view depth (`1 / w`, 0 where nothing is)
/// at every point of a grid `k` times finer than the pixels (see
/// [`rasterize`]), from the dense tessellation.
fn nearest_inverse_depth(
    prepared: &PreparedScene,
    samples_per_patch_side: u32,
    k: usize,
) -> Vec<f64> {
    let camera = &prepared.camera;
    let width = camera.width as usize * k;
    let mut nearest = vec![0.0f64; width * camera.height as usize * k];
    rasterize(
        prepared,
        samples_per_patch_side,
        k,
        |x, y, inverse_depth, _| {
            let slot = &mut nearest[y * width + x];
            *slot = slot.max(inverse_depth);
        },
    );
    nearest
}

/// Tessellates every patch of `prepared` on an `n x n` grid of points (`n =
/// samples_per_patch_side`, at least 2), projects it, and calls `visit(x,
/// y, inverse_depth, patch)` for every point of a grid `k` times finer
/// than the pixels (`x / k + (x % k + 0.5) / k`, likewise for y) inside or
/// on the edge of a triangle, with the inverse view depth `1 / w`
/// interpolated there (it is affine in screen space). Triangles with a
/// corner at clip `w <= 1e-5` are skipped.
fn rasterize(
    prepared: &PreparedScene,
    samples_per_patch_side: u32,
    k: usize,
    mut visit: impl FnMut(usize, usize, f64, usize),
) {
    let camera = &prepared.camera;
    let (width, height) = (camera.width as usize * k, camera.height as usize * k);
    let n = samples_per_patch_side.max(2) as usize;
    let view_proj = camera.view_proj();
    // (px, py, 1 / w) of each grid point, in units of the fine grid, or
    // None when it cannot be projected.
    let mut grid: Vec<Option<[f64; 3]>> = vec![None; n * n];
    for (patch_index, patch) in prepared.patches.iter().enumerate() {
        for (index, slot) in grid.iter_mut().enumerate() {
            let (i, j) = (index % n, index / n);
            let (s, t) = (i as f32 / (n - 1) as f32, j as f32 / (n - 1) as f32);
            let clip = view_proj * reyes::bezier::position(&patch.points, s, t).extend(1.0);
            *slot = (clip.w > NEAR_W).then(|| {
                let pixel = camera.to_pixel(clip);
                [
                    f64::from(pixel.x) * k as f64,
                    f64::from(pixel.y) * k as f64,
                    1.0 / f64::from(clip.w),
                ]
            });
        }
        let mut visit_patch =
            |x: usize, y: usize, inverse_depth: f64| visit(x, y, inverse_depth, patch_index);
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let corner = |di: usize, dj: usize| grid[(j + dj) * n + i + di];
                let (Some(a), Some(b), Some(c), Some(d)) =
                    (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1))
                else {
                    continue;
                };
                fill_triangle(width, height, [a, b, c], &mut visit_patch);
                fill_triangle(width, height, [a, c, d], &mut visit_patch);
            }
        }
    }
}

/// Calls `visit(x, y, value)` for the cells of a `width x height` grid
/// whose centres lie inside triangle `corners` (`(x, y, value)` each, x
/// and y in grid units) or on its edges (inclusive, so the reference itself
/// has no seams between triangles), with the value interpolated linearly
/// at the centre.
/// Degenerate triangles visit nothing.
fn fill_triangle(
    width: usize,
    height: usize,
    [a, b, c]: [[f64; 3]; 3],
    visit: &mut impl FnMut(usize, usize, f64),
) {
    let edge = |p: [f64; 3], q: [f64; 3], r: [f64; 2]| {
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    };
    let area = edge(a, b, [c[0], c[1]]);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let lo = |k: usize| a[k].min(b[k]).min(c[k]);
    let hi = |k: usize| a[k].max(b[k]).max(c[k]);
    // Cell x's centre is x + 0.5: the columns whose centres lie in the box.
    let first = |k: usize| (lo(k) - 0.5).ceil().max(0.0);
    let last = |k: usize, size: usize| (hi(k) - 0.5).floor().min(size as f64 - 1.0);
    let (x0, x1) = (first(0), last(0, width));
    let (y0, y1) = (first(1), last(1, height));
    if x0 > x1 || y0 > y1 {
        return;
    }
    for y in y0 as usize..=y1 as usize {
        for x in x0 as usize..=x1 as usize {
            let p = [x as f64 + 0.5, y as f64 + 0.5];
            // Barycentric weights of a, b and c (each edge's opposite corner).
            let (wa, wb, wc) = (
                edge(b, c, p) / area,
                edge(c, a, p) / area,
                edge(a, b, p) / area,
            );
            if wa >= 0.0 && wb >= 0.0 && wc >= 0.0 {
                visit(x, y, wa * a[2] + wb * b[2] + wc * c[2]);
            }
        }
    }
}

/// Clears `reference` (a mask of `prepared`'s image) within `radius_px`
/// pixels of the listed patch edges, `(patch, edge)` with `patch` an index
/// into `prepared.patches` and edges numbered as by
/// [`crate::shapes::unmatched_edges`] (0: `v = 0`, 1: `v = 1`, 2: `u = 0`,
/// 3: `u = 1`), so that [`cracks`] does not count pixels there.
///
/// Why: a dicer can only be watertight where the data is closed. A model
/// whose neighbouring patches do not share a boundary bit for bit (the
/// Killeroo has such edges: near misses, T-junctions and gaps of up to about
/// 0.01 units between patches) has seams of its own that no dicing closes;
/// a crack test of the dicer leaves them out.
pub fn exclude_edges(
    reference: &mut [bool],
    prepared: &PreparedScene,
    edges: &[(usize, usize)],
    radius_px: f32,
) {
    let camera = &prepared.camera;
    let (width, height) = (i64::from(camera.width), i64::from(camera.height));
    assert_eq!(
        reference.len(),
        (width * height) as usize,
        "reference is not the prepared image's size"
    );
    let view_proj = camera.view_proj();
    let radius = radius_px.max(0.0);
    for &(patch_index, edge) in edges {
        let Some(patch) = prepared.patches.get(patch_index) else {
            continue;
        };
        let pixel_at = |f: f32| {
            let (s, t) = match edge {
                0 => (f, 0.0),
                1 => (f, 1.0),
                2 => (0.0, f),
                _ => (1.0, f),
            };
            let clip = view_proj * reyes::bezier::position(&patch.points, s, t).extend(1.0);
            (clip.w > NEAR_W).then(|| {
                let pixel = camera.to_pixel(clip);
                (pixel.x, pixel.y)
            })
        };
        // Samples a quarter of a pixel apart along the edge's projection (a
        // boundary cubic is smooth: 8 chords estimate its length well).
        let length: f32 = (0..8)
            .filter_map(|i| Some((pixel_at(i as f32 / 8.0)?, pixel_at((i + 1) as f32 / 8.0)?)))
            .map(|(a, b)| (a.0 - b.0).hypot(a.1 - b.1))
            .sum();
        let steps = ((length * 4.0).ceil() as usize).clamp(8, 1 << 16);
        for i in 0..=steps {
            let Some((px, py)) = pixel_at(i as f32 / steps as f32) else {
                continue;
            };
            let (x0, x1) = (
                (px - radius - 0.5).floor() as i64,
                (px + radius).ceil() as i64,
            );
            let (y0, y1) = (
                (py - radius - 0.5).floor() as i64,
                (py + radius).ceil() as i64,
            );
            for y in y0.max(0)..=y1.min(height - 1) {
                for x in x0.max(0)..=x1.min(width - 1) {
                    let (dx, dy) = (x as f32 + 0.5 - px, y as f32 + 0.5 - py);
                    if dx * dx + dy * dy <= radius * radius {
                        reference[(y * width + x) as usize] = false;
                    }
                }
            }
        }
    }
}

/// The cracks of a render: the pixels `(x, y)` whose whole 5 x 5
/// neighbourhood lies inside `reference` (so they are well inside a closed
/// surface's projection, 2 pixels or more from any silhouette, and inside
/// the image) but that have fewer than `spp` covered samples. Row-major by
/// `y`, then `x`.
///
/// `covered_samples` is the render's per-pixel count of covered samples and
/// `reference` a coverage mask such as [`dense_coverage`]'s, both row-major
/// `width x height`.
///
/// # Panics
/// When the slices are not `width * height` long.
pub fn cracks(
    covered_samples: &[u16],
    spp: u32,
    reference: &[bool],
    width: u32,
    height: u32,
) -> Vec<(u32, u32)> {
    let pixels = width as usize * height as usize;
    assert_eq!(
        covered_samples.len(),
        pixels,
        "covered_samples is not {width} x {height}"
    );
    assert_eq!(
        reference.len(),
        pixels,
        "reference is not {width} x {height}"
    );
    let r = NEIGHBOURHOOD_RADIUS;
    let inside = |x: u32, y: u32| reference[y as usize * width as usize + x as usize];
    let mut found = Vec::new();
    for y in r..height.saturating_sub(r) {
        for x in r..width.saturating_sub(r) {
            let covered = u32::from(covered_samples[y as usize * width as usize + x as usize]);
            if covered >= spp {
                continue;
            }
            let surrounded = (y - r..=y + r).all(|ny| (x - r..=x + r).all(|nx| inside(nx, ny)));
            if surrounded {
                found.push((x, y));
            }
        }
    }
    found
}

/// Intersection over union of the reference coverage and the pixels where a
/// render covers at least half of the `spp` samples: the render's estimate
/// of whether the pixel's centre is covered, comparable to the reference's
/// centre test (counting any covered sample would grow the render by half a
/// pixel along every silhouette). 1 when both are empty.
pub fn coverage_iou(covered_samples: &[u16], spp: u32, reference: &[bool]) -> f64 {
    assert_eq!(covered_samples.len(), reference.len());
    let (mut both, mut either) = (0usize, 0usize);
    for (&covered, &inside) in covered_samples.iter().zip(reference) {
        let rendered = 2 * u32::from(covered) >= spp && covered > 0;
        both += usize::from(rendered && inside);
        either += usize::from(rendered || inside);
    }
    if either == 0 {
        1.0
    } else {
        both as f64 / either as f64
    }
}

/// The scene of a watertightness view: `model` at `width x height` and
/// `spp`, seen from `eye` looking at `target` (z up) with the near plane at
/// 0.01 (models may come close to the eye, and the reference does not clip
/// at the near plane), lit over the camera's shoulder.
pub fn view_scene(
    model: &reyes::model::Model,
    (width, height, spp): (u32, u32, u32),
    eye: glam::Vec3,
    target: glam::Vec3,
) -> reyes::scene::Scene {
    let mut scene = reyes::scene::Scene::for_model("watertight test model", model);
    scene.resolution.width = width;
    scene.resolution.height = height;
    scene.spp = spp;
    let camera = reyes::scene::CameraDesc {
        eye,
        target,
        up: glam::Vec3::Z,
        near: 0.01,
        ..scene.camera.expect("for_model frames a camera")
    };
    scene.lights = vec![reyes::scene::Light {
        direction: camera.shoulder_light_direction(),
        ..reyes::scene::Light::default()
    }];
    scene.camera = Some(camera);
    scene
}

#[cfg(test)]
mod tests {
    use super::*;
    use reyes::model::{Model, Patch};
    use reyes::scene::{CameraDesc, Scene};

    const SPP: u32 = 16;

    /// A `width x height` image whose pixels are all fully covered and all
    /// inside the reference.
    fn full(width: u32, height: u32) -> (Vec<u16>, Vec<bool>) {
        let pixels = (width * height) as usize;
        (vec![SPP as u16; pixels], vec![true; pixels])
    }

    #[test]
    fn a_hole_inside_the_reference_is_a_crack() {
        let (mut covered, reference) = full(20, 12);
        covered[6 * 20 + 9] = SPP as u16 - 1;
        covered[3 * 20 + 4] = 0;
        assert_eq!(
            cracks(&covered, SPP, &reference, 20, 12),
            vec![(4, 3), (9, 6)]
        );
    }

    #[test]
    fn a_full_render_has_no_cracks() {
        let (covered, reference) = full(20, 12);
        assert!(cracks(&covered, SPP, &reference, 20, 12).is_empty());
    }

    #[test]
    fn holes_near_the_reference_border_or_the_image_border_are_not_cracks() {
        let (width, height) = (24u32, 24u32);
        // The reference covers the square [5, 15) x [5, 15).
        let reference: Vec<bool> = (0..width * height)
            .map(|i| (5..15).contains(&(i % width)) && (5..15).contains(&(i / width)))
            .collect();
        let mut covered: Vec<u16> = reference
            .iter()
            .map(|&r| if r { SPP as u16 } else { 0 })
            .collect();
        let at = |x: u32, y: u32| (y * width + x) as usize;
        // On the border, one pixel in, and two pixels in: only the last is
        // surrounded by a 5 x 5 neighbourhood of reference pixels.
        for (x, y) in [(5, 9), (6, 9), (7, 9), (10, 14), (10, 13), (10, 12)] {
            covered[at(x, y)] = 3;
        }
        assert_eq!(
            cracks(&covered, SPP, &reference, width, height),
            vec![(7, 9), (10, 12)]
        );

        // The image border: a full reference, holes within 2 pixels of the edge.
        let (mut covered, reference) = full(10, 10);
        for (x, y) in [(0, 5), (1, 5), (8, 5), (5, 9), (5, 8)] {
            covered[(y * 10 + x) as usize] = 0;
        }
        assert!(cracks(&covered, SPP, &reference, 10, 10).is_empty());
    }

    #[test]
    fn iou_compares_half_covered_pixels_with_the_reference() {
        let reference = [true, true, false, false];
        assert_eq!(coverage_iou(&[16, 8, 7, 0], 16, &reference), 1.0);
        assert_eq!(coverage_iou(&[16, 0, 16, 0], 16, &reference), 1.0 / 3.0);
        assert_eq!(coverage_iou(&[0; 4], 16, &[false; 4]), 1.0);
    }

    /// A flat square patch `[-1, 1]^2` in the plane z = 0 (control points on
    /// a uniform grid, so the surface is the square itself).
    fn square() -> Model {
        let points: [[f32; 3]; 16] = std::array::from_fn(|index| {
            let (u, v) = ((index % 4) as f32, (index / 4) as f32);
            [u * 2.0 / 3.0 - 1.0, v * 2.0 / 3.0 - 1.0, 0.0]
        });
        Model {
            patches: vec![Patch {
                points: points.map(Into::into),
            }],
            st: None,
        }
    }

    /// `model` seen by a `width x height` camera at `eye` looking at `target`.
    fn prepared(
        model: &Model,
        eye: [f32; 3],
        target: [f32; 3],
        width: u32,
        height: u32,
    ) -> PreparedScene {
        let mut scene = Scene::for_model("test shape", model);
        scene.resolution.width = width;
        scene.resolution.height = height;
        let framed = scene.camera.expect("for_model frames a camera");
        scene.camera = Some(CameraDesc {
            eye: eye.into(),
            target: target.into(),
            up: [0.0, 1.0, 0.0].into(),
            ..framed
        });
        PreparedScene::new(&scene, std::slice::from_ref(model)).expect("the test scene prepares")
    }

    /// Seen face-on, the square covers exactly the pixels whose centres lie
    /// in its projection (checked away from the projected border, where a
    /// centre may sit within rounding of an edge).
    #[test]
    fn a_square_covers_its_projection() {
        let scene = prepared(&square(), [0.0, 0.0, 5.0], [0.0, 0.0, 0.0], 64, 48);
        let mask = dense_coverage(&scene, 4);
        let project = |x: f32, y: f32| {
            let pixel = scene
                .camera
                .to_pixel(scene.camera.to_clip([x, y, 0.0].into()));
            (pixel.x, pixel.y)
        };
        let (left, top) = project(-1.0, 1.0);
        let (right, bottom) = project(1.0, -1.0);
        assert!(
            right - left > 10.0 && bottom - top > 10.0,
            "the square is {left}..{right} x {top}..{bottom}"
        );
        let mut inside = 0;
        for y in 0..48 {
            for x in 0..64 {
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                let margin = (cx - left)
                    .abs()
                    .min((cx - right).abs())
                    .min((cy - top).abs())
                    .min((cy - bottom).abs());
                if margin < 1e-3 {
                    continue;
                }
                let expected = cx > left && cx < right && cy > top && cy < bottom;
                inside += usize::from(expected);
                assert_eq!(mask[y * 64 + x], expected, "pixel ({x}, {y})");
            }
        }
        assert!(inside > 100);
    }

    #[test]
    fn surfaces_behind_the_eye_cover_nothing() {
        let scene = prepared(&square(), [0.0, 0.0, -5.0], [0.0, 0.0, -10.0], 64, 48);
        assert!(dense_coverage(&scene, 8).iter().all(|&c| !c));
    }

    /// Of a square 5 units away in front of a smaller one 6 units away,
    /// only the front one is visible (with a margin below 20%); moved
    /// aside, the back one shows; shrunk below a sample spacing, it is kept.
    #[test]
    fn hidden_patches_are_not_visible() {
        let front = square();
        let mut model = front.clone();
        let behind = |dx: f32| Patch {
            points: front.patches[0]
                .points
                .map(|p| [p.x * 0.5 + dx, p.y * 0.5, -1.0].into()),
        };
        model.patches.push(behind(0.0));
        let scene = prepared(&model, [0.0, 0.0, 5.0], [0.0, 0.0, 0.0], 64, 48);
        assert_eq!(visible_patches(&scene, 4, 4, 0.02), vec![true, false]);
        // Within the margin, the one behind is kept.
        assert_eq!(visible_patches(&scene, 4, 4, 0.25), vec![true, true]);
        model.patches[1] = behind(1.2);
        let scene = prepared(&model, [0.0, 0.0, 5.0], [0.0, 0.0, 0.0], 64, 48);
        assert_eq!(visible_patches(&scene, 4, 4, 0.02), vec![true, true]);
        // Too small to cover a sample point: kept.
        model.patches[1] = Patch {
            points: front.patches[0]
                .points
                .map(|p| [p.x * 0.001, p.y * 0.001, -1.0].into()),
        };
        let scene = prepared(&model, [0.0, 0.0, 5.0], [0.0, 0.0, 0.0], 64, 48);
        assert_eq!(visible_patches(&scene, 4, 4, 0.02), vec![true, true]);
    }

    /// Excluding the square's `u = 0` edge clears a band along the left of
    /// its projection and nothing else.
    #[test]
    fn excluded_edges_clear_a_band_along_their_projection() {
        let scene = prepared(&square(), [0.0, 0.0, 5.0], [0.0, 0.0, 0.0], 64, 48);
        let full = dense_coverage(&scene, 4);
        let mut cleared = full.clone();
        exclude_edges(&mut cleared, &scene, &[(0, 2)], 1.5);
        let left = scene
            .camera
            .to_pixel(scene.camera.to_clip([-1.0, 0.0, 0.0].into()))
            .x;
        for y in 0..48 {
            for x in 0..64 {
                let i = y * 64 + x;
                let distance = (x as f32 + 0.5 - left).abs();
                if !full[i] || (distance - 1.5).abs() < 0.01 {
                    continue;
                }
                assert_eq!(
                    cleared[i],
                    distance > 1.5,
                    "pixel ({x}, {y}), {distance} px from the edge"
                );
            }
        }
        assert!(cleared.iter().filter(|&&c| c).count() < full.iter().filter(|&&c| c).count());
    }

    /// A square seen face-on is smooth inside and not beyond its border;
    /// where a second square in front of it ends, the depth jumps and the
    /// front is not smooth, while both squares' insides are.
    #[test]
    fn the_front_is_not_smooth_at_silhouettes() {
        let mut model = square();
        let scene = prepared(&model, [0.0, 0.0, 5.0], [0.0, 0.0, 0.0], 64, 48);
        let coverage = dense_coverage(&scene, 4);
        let smooth = smooth_front(&scene, 4, 4, 0.01);
        let covered_count = coverage.iter().filter(|&&c| c).count();
        assert!(
            smooth.iter().zip(&coverage).all(|(&s, &c)| !s || c),
            "smooth only where covered"
        );
        assert!(smooth.iter().filter(|&&s| s).count() * 10 > covered_count * 9);
        // Along the middle row, the first covered pixel's left neighbour
        // (partly covered) is not smooth, and the next pixel in is.
        let row = 24 * 64;
        let first = (0..64)
            .find(|&x| coverage[row + x])
            .expect("the square is in view");
        assert!(!smooth[row + first - 1] && smooth[row + first + 1]);

        // Half of a smaller square 1 unit in front (20% nearer): its left
        // edge at x = 0 is a depth jump.
        model.patches.push(Patch {
            points: model.patches[0]
                .points
                .map(|p| [p.x * 0.5 + 0.5, p.y * 0.5, 1.0].into()),
        });
        let scene = prepared(&model, [0.0, 0.0, 5.0], [0.0, 0.0, 0.0], 64, 48);
        let smooth = smooth_front(&scene, 4, 4, 0.01);
        let jump = scene
            .camera
            .to_pixel(scene.camera.to_clip([0.0, 0.0, 1.0].into()));
        let (x, y) = (jump.x as usize, jump.y as usize);
        assert!(
            !smooth[y * 64 + x] && !smooth[y * 64 + x - 1],
            "the depth jump at x = {}",
            jump.x
        );
        assert!(smooth[y * 64 + x - 4] && smooth[y * 64 + x + 4]);
    }

    /// The sphere's reference is the disc of its silhouette: a sphere of
    /// radius 1 seen from distance `d` subtends a half-angle `asin(1 / d)`.
    #[test]
    fn a_sphere_covers_its_silhouette_disc() {
        let sphere = crate::shapes::bezier_sphere();
        let (width, height) = (160u32, 120u32);
        let scene = prepared(&sphere, [0.0, 0.0, 4.0], [0.0, 0.0, 0.0], width, height);
        let mask = dense_coverage(&scene, 24);
        let camera = &scene.camera;
        let half_angle = (1.0f32 / 4.0).asin();
        let radius_px = half_angle.tan() / (camera.fov_y_radians * 0.5).tan() * height as f32 * 0.5;
        let (cx, cy) = (width as f32 / 2.0, height as f32 / 2.0);
        let mut wrong = 0;
        for y in 0..height {
            for x in 0..width {
                let distance =
                    ((x as f32 + 0.5 - cx).powi(2) + (y as f32 + 0.5 - cy).powi(2)).sqrt();
                if (distance - radius_px).abs() < 0.5 {
                    continue;
                }
                wrong += usize::from(mask[(y * width + x) as usize] != (distance < radius_px));
            }
        }
        assert!(radius_px > 20.0, "the sphere is {radius_px} px");
        assert_eq!(
            wrong, 0,
            "pixels off the silhouette disc of radius {radius_px}"
        );
    }
}
