//! Golden RIB scenes: each small RIB in `tests/data/rib_golden/` is the
//! same picture as the TOML scene next to it, written by hand (not by
//! `reyes convert`) from the RenderMan conventions, with hand-written
//! `.bpt` models: the camera from the transforms before `WorldBegin`,
//! handedness, `AttributeBegin`/`TransformBegin` stacking, `ReadArchive`,
//! object and camera motion blur. Both are rendered by the CPU reference
//! and must agree: coverage IoU >= 0.995, and the colours of the pixels
//! both cover within 2/255 for at least 99% of them.
//!
//! The `tests` crate renders the same RIB scenes on the GPU
//! (`tests/tests/rib_golden_gpu.rs`).

use std::path::PathBuf;

use reyes::prepare::PreparedScene;
use reyes::reference::{self, Rendered};
use reyes::rib::RibScene;
use reyes::scene::Scene;

fn golden(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/rib_golden")
        .join(name)
}

/// The RIB scene `name.rib`, read without warnings.
fn rib(name: &str) -> RibScene {
    let rib = RibScene::load(golden(&format!("{name}.rib")))
        .unwrap_or_else(|e| panic!("{name}.rib: {e}"));
    let warnings: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    assert!(warnings.is_empty(), "{name}.rib warns: {warnings:#?}");
    rib
}

fn render_rib(name: &str) -> Rendered {
    reference::render(&rib(name).prepare().expect("the RIB scene prepares"))
}

fn render_toml(name: &str) -> Rendered {
    let scene =
        Scene::load(golden(&format!("{name}.toml"))).unwrap_or_else(|e| panic!("{name}.toml: {e}"));
    reference::render(&PreparedScene::load(&scene).expect("the TOML scene prepares"))
}

/// How closely two renders agree.
#[derive(Debug)]
struct Agreement {
    /// Fraction of the pixels the first render covers.
    coverage: f64,
    /// Intersection over union of the coverage masks.
    iou: f64,
    /// Fraction of the pixels both cover whose channels differ by <= 2.
    within_2: f64,
    /// Largest channel difference over the pixels both cover.
    max_diff: u8,
}

fn agreement(a: &Rendered, b: &Rendered) -> Agreement {
    assert_eq!(a.image.dimensions(), b.image.dimensions());
    let (mut both, mut either, mut within, mut max_diff) = (0usize, 0usize, 0usize, 0u8);
    for (i, (&p, &q)) in a.coverage.iter().zip(&b.coverage).enumerate() {
        either += usize::from(p || q);
        if p && q {
            both += 1;
            let diff = (0..3)
                .map(|c| a.image.as_raw()[4 * i + c].abs_diff(b.image.as_raw()[4 * i + c]))
                .max()
                .unwrap_or(0);
            max_diff = max_diff.max(diff);
            within += usize::from(diff <= 2);
        }
    }
    let ratio = |n: usize, d: usize| if d == 0 { 1.0 } else { n as f64 / d as f64 };
    Agreement {
        coverage: ratio(a.coverage.iter().filter(|&&c| c).count(), a.coverage.len()),
        iou: ratio(both, either),
        within_2: ratio(within, both),
        max_diff,
    }
}

/// `rendered` mirrored left to right.
fn mirrored(rendered: &Rendered) -> Rendered {
    let (w, h) = rendered.image.dimensions();
    let mut out = rendered.clone();
    out.image = image::imageops::flip_horizontal(&rendered.image);
    for y in 0..h as usize {
        for x in 0..w as usize {
            out.coverage[y * w as usize + x] =
                rendered.coverage[y * w as usize + (w as usize - 1 - x)];
        }
    }
    out
}

/// Renders `name.rib` and `name.toml`, checks that they agree and returns
/// both (RIB first).
fn check_golden(name: &str, min_coverage: f64) -> (Rendered, Rendered) {
    let from_rib = render_rib(name);
    let by_hand = render_toml(name);
    let a = agreement(&from_rib, &by_hand);
    eprintln!("{name}: {a:?}");
    assert!(
        a.coverage >= min_coverage,
        "{name}: the RIB covers only {:.3} of the image",
        a.coverage
    );
    assert!(a.iou >= 0.995, "{name}: coverage IoU {:.5} < 0.995", a.iou);
    assert!(
        a.within_2 >= 0.99,
        "{name}: only {:.4} of the shared pixels within 2/255 (max diff {})",
        a.within_2,
        a.max_diff
    );
    (from_rib, by_hand)
}

#[test]
fn camera_from_the_transforms_matches_the_hand_written_scene() {
    let (from_rib, _) = check_golden("camera", 0.1);
    // The bump (front right) and the wall (back left) make the picture
    // asymmetric: a camera mirrored or turned the wrong way would not match.
    let a = agreement(&from_rib, &mirrored(&from_rib));
    assert!(a.iou < 0.95 || a.within_2 < 0.9, "mirror-symmetric: {a:?}");
}

#[test]
fn handedness_matches_the_hand_written_scene() {
    let (from_rib, by_hand) = check_golden("handedness", 0.08);
    let a = agreement(&from_rib, &mirrored(&by_hand));
    assert!(
        a.iou < 0.8,
        "the scene is too symmetric to test handedness: {a:?}"
    );
    // The square whose back faces the camera is not drawn: nothing in the
    // lower right corner (x > 0.6 w, y > 0.6 h).
    let (w, h) = from_rib.image.dimensions();
    let lower_right = (0..h as usize)
        .flat_map(|y| (0..w as usize).map(move |x| (x, y)))
        .filter(|&(x, y)| x as f64 > 0.6 * f64::from(w) && y as f64 > 0.6 * f64::from(h))
        .filter(|&(x, y)| from_rib.coverage[y * w as usize + x])
        .count();
    assert_eq!(lower_right, 0, "the back-facing one-sided square is drawn");
}

#[test]
fn attribute_stacking_matches_the_hand_written_scene() {
    let (from_rib, _) = check_golden("attributes", 0.1);
    // Lit by the ambient light alone, every covered pixel is one of the
    // five colours (or a blend at an edge): the restored colours are the
    // exact ones.
    let colours = from_rib
        .image
        .pixels()
        .zip(&from_rib.coverage)
        .filter(|(_, c)| **c)
        .filter(|(p, _)| {
            [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0]]
                .iter()
                .any(|c| p[0] == c[0] && p[1] == c[1] && p[2] == c[2])
        })
        .count();
    let covered = from_rib.coverage.iter().filter(|&&c| c).count();
    assert!(
        colours as f64 >= 0.8 * covered as f64,
        "{colours} of {covered} covered pixels have one of the squares' colours"
    );
}

#[test]
fn read_archive_matches_the_hand_written_scene() {
    check_golden("archive", 0.1);
}

#[test]
fn object_motion_blur_matches_the_hand_written_scene() {
    let (from_rib, _) = check_golden("motion", 0.05);
    // The blur is seen: the moving square covers more than when still.
    let text = std::fs::read_to_string(golden("motion.rib")).unwrap();
    let still = RibScene::from_text(
        &text.replace("Shutter 0 0.5", "Shutter 0 0"),
        golden("still.rib"),
    )
    .unwrap();
    assert_eq!(still.scene.shutter, 0.0);
    let still = reference::render(&still.prepare().unwrap());
    let count = |r: &Rendered| r.coverage.iter().filter(|&&c| c).count();
    assert!(
        count(&from_rib) as f64 > 1.3 * count(&still) as f64,
        "moving {} pixels, still {}",
        count(&from_rib),
        count(&still)
    );
}

#[test]
fn camera_motion_blur_matches_the_hand_written_scene() {
    let (from_rib, _) = check_golden("camera_motion", 0.1);
    assert!(rib("camera_motion").scene.camera_close.is_some());
    // The blur is seen: the squares cover more than with a still camera.
    let text = std::fs::read_to_string(golden("camera_motion.rib")).unwrap();
    let still = RibScene::from_text(
        &text.replace("Translate 0.5 0 8", "Translate 0 0 8"),
        golden("still.rib"),
    )
    .unwrap();
    assert!(still.scene.camera_close.is_none());
    let still = reference::render(&still.prepare().unwrap());
    let count = |r: &Rendered| r.coverage.iter().filter(|&&c| c).count();
    assert!(
        count(&from_rib) as f64 > 1.2 * count(&still) as f64,
        "moving {} pixels, still {}",
        count(&from_rib),
        count(&still)
    );
}

/// Materials per attribute block: five copies of one patch, each block
/// with its own `Surface`, `Color` and `ShadingRate`, against the TOML
/// scene that gives each object its surface table, colour and shading
/// rate by hand. The materials differ visibly (a RIB that gave every object
/// one surface fails the comparison), and each object keeps its block's
/// attributes.
#[test]
fn materials_per_block_match_the_hand_written_scene() {
    let (from_rib, _) = check_golden("materials", 0.1);
    let rib = rib("materials");
    let objects = &rib.scene.objects;
    let names: Vec<&str> = objects
        .iter()
        .map(|o| o.surface.as_ref().map_or("none", |s| s.name()))
        .collect();
    assert_eq!(
        names,
        ["matte", "plastic", "metal", "constant", "defaultsurface"]
    );
    let rates: Vec<Option<f32>> = objects.iter().map(|o| o.shading_rate).collect();
    assert_eq!(
        rates,
        [Some(4.0), Some(1.0), Some(0.5), Some(2.0), Some(8.0)]
    );
    assert_eq!(objects[1].color, glam::Vec3::new(0.2, 0.9, 0.2));
    // `constant` is its colour exactly, unlit: (0.3, 0.3, 1) in sRGB codes.
    let constant = [
        reyes::color::linear_to_srgb8(0.3),
        reyes::color::linear_to_srgb8(0.3),
        255,
    ];
    let (w, h) = from_rib.image.dimensions();
    let centre_of = |x_world: f32| {
        // The patch spans x .. x + 1.5 at depth 8 with a 45-degree field:
        // 1 world unit is h / (2 * 8 * tan(22.5)) pixels.
        let scale = h as f32 / (2.0 * 8.0 * 22.5_f32.to_radians().tan());
        ((w as f32 / 2.0 + (x_world + 0.75) * scale) as u32, h / 2)
    };
    let (x, y) = centre_of(1.0);
    let pixel = from_rib.image.get_pixel(x, y);
    for c in 0..3 {
        assert!(
            pixel[c].abs_diff(constant[c]) <= 1,
            "constant at ({x}, {y}): {pixel:?}, expected {constant:?}"
        );
    }
}
