//! The sampling algorithms as published, on the CPU reference: INTERVAL's
//! UV-T pairing, the quad boxes on sample strata, Interleave UVT's tile
//! sizes and Adaptive's cost model. (The GPU follows every one of them:
//! `tests/tests/reyes_blur.rs` and `reyes_tiles.rs` compare it with the
//! reference in every mode.)

use glam::Vec3;
use reyes::prepare::PreparedScene;
use reyes::reference::raster5d::{Mode5d, adaptive_choice, adaptive_costs};
use reyes::reference::{self, ReferenceOptions};
use reyes::scene::{Sampling, Scene, SceneError, Transform};

/// The default teapot at `side x side` pixels and `spp`, its camera framed.
fn teapot(side: u32, spp: u32) -> Scene {
    let mut scene = Scene::default_teapot();
    scene.resolution.width = side;
    scene.resolution.height = side;
    scene.spp = spp;
    scene
}

fn render(scene: &Scene) -> reference::Rendered {
    reference::render(&PreparedScene::load(scene).expect("scene prepares"))
}

/// Fatahalian et al.'s UV-T pairing: with a lens and no motion, each of
/// INTERVAL's boxes grows by the circle of confusion over its own lens
/// region only, so it tests far fewer samples than the bounding box, whose
/// box grows by the whole circle of confusion; both read the same sample
/// table, so the images are the same. Without the pairing (every
/// interval's box grown by the whole lens), INTERVAL tested exactly the
/// bounding box's samples.
#[test]
fn interval_with_a_lens_alone_tests_far_fewer_samples_than_the_bounding_box() {
    let mut scene = teapot(128, 16);
    scene.lens.aperture = 0.5;
    scene.sampling = Sampling::Bbox;
    let bbox = render(&scene);
    scene.sampling = Sampling::Interval;
    let interval = render(&scene);
    let (b, i) = (bbox.stats.samples_tested, interval.stats.samples_tested);
    eprintln!("lens alone, 16 spp: bbox tests {b}, INTERVAL tests {i}");
    assert!(bbox.image == interval.image, "the two modes sample alike");
    assert_eq!(bbox.stats.samples_hit, interval.stats.samples_hit);
    assert!(i * 3 < b, "INTERVAL tested {i}, the bounding box {b}");
}

/// The quad boxes on strata render the image of the box per triangle over
/// whole pixels, with a quarter of the tests or fewer.
#[test]
fn quad_boxes_render_the_triangle_boxes_image_with_far_fewer_tests() {
    let prepared = PreparedScene::load(&teapot(160, 16)).expect("scene prepares");
    let quads = reference::render(&prepared);
    let triangles = reference::try_render_with(
        &prepared,
        &ReferenceOptions {
            triangle_boxes: true,
            ..ReferenceOptions::unbounded_work()
        },
    )
    .expect("renders");
    let (q, t) = (quads.stats.samples_tested, triangles.stats.samples_tested);
    eprintln!("still teapot, 16 spp: quad boxes test {q}, triangle boxes {t}");
    assert!(quads.image == triangles.image);
    assert!(q * 3 < t, "quad boxes tested {q}, triangle boxes {t}");
}

/// Samples looked up and skipped without a test: the bounding box and
/// Simple UVT loop over their boxes' strata only and skip none; Interleave
/// UVT looks one sample up in each tile of each tuple's box, and most lie
/// in a stratum outside it, more so the larger the tile. Counting them, its
/// efficiency falls to the order of Fatahalian et al.'s 5%, while its
/// efficiency per test stays the bounding box's (a still frame tests the
/// same samples in every mode).
#[test]
fn skipped_lookups_show_interleave_uvt_cost_on_a_still_teapot() {
    let mut scene = teapot(96, 16);
    let mut rendered = |sampling, tile| {
        scene.sampling = sampling;
        scene.interleave_tile = tile;
        render(&scene).stats
    };
    let bbox = rendered(Sampling::Bbox, 2);
    let simple = rendered(Sampling::Simple, 2);
    let interleave: Vec<_> = [2, 3, 4]
        .map(|tile| rendered(Sampling::Interleave, tile))
        .into();
    assert_eq!((bbox.samples_skipped, simple.samples_skipped), (0, 0));
    let mut last = bbox.sample_lookup_efficiency();
    for (tile, stats) in [2, 3, 4].into_iter().zip(&interleave) {
        let lookups = stats.sample_lookup_efficiency();
        eprintln!(
            "Interleave {tile}x{tile}: tested {}, skipped {}, efficiency per test {:.4}, per lookup {lookups:.4}",
            stats.samples_tested,
            stats.samples_skipped,
            stats.sample_test_efficiency()
        );
        assert_eq!(stats.samples_tested, bbox.samples_tested);
        assert!(
            stats.samples_skipped > stats.samples_tested,
            "{tile}: {stats:?}"
        );
        assert!(lookups < last, "tile {tile}: {lookups} not below {last}");
        last = lookups;
    }
}

/// Interleave UVT with every tile size renders the teapot close to the
/// bounding box's image (same coverage within 1%), and a larger tile costs
/// more placements and so more time, never fewer samples hit.
#[test]
fn every_interleave_tile_size_renders_the_moving_teapot() {
    let mut scene = teapot(96, 4);
    scene.objects[0].transform_close = Some(Transform {
        rotate_degrees: Vec3::new(0.0, 0.0, 20.0),
        ..scene.objects[0].transform
    });
    scene.sampling = Sampling::Bbox;
    let bbox = render(&scene);
    let covered =
        |r: &reference::Rendered| r.covered_samples.iter().map(|&c| u64::from(c)).sum::<u64>();
    for tile in [2, 3, 4] {
        scene.sampling = Sampling::Interleave;
        scene.interleave_tile = tile;
        let interleave = render(&scene);
        let (a, b) = (covered(&interleave) as f64, covered(&bbox) as f64);
        eprintln!("K = {tile}: covered samples {a} against the bounding box's {b}");
        assert!((a - b).abs() < 0.01 * b, "K = {tile}: {a} against {b}");
    }
}

#[test]
fn the_interleave_tile_is_2_3_or_4() {
    let mut scene = teapot(32, 4);
    assert_eq!(scene.interleave_tile, 2, "the default");
    for tile in [0, 1, 5, 8] {
        scene.interleave_tile = tile;
        match scene.validate() {
            Err(SceneError::InvalidValue { field, .. }) => assert_eq!(field, "interleave_tile"),
            other => panic!("interleave_tile = {tile}: {other:?}"),
        }
    }
    let parsed: Scene = toml::from_str("interleave_tile = 3").expect("parses");
    assert_eq!(parsed.interleave_tile, 3);
}

/// Interleave UVT's permutations: 64 by default, 1 to 256, anything else a
/// typed error naming the value; the TOML key sets it.
#[test]
fn the_interleave_permutations_are_1_to_256() {
    let mut scene = teapot(32, 4);
    assert_eq!(scene.interleave_permutations, 64, "the default");
    for permutations in [1, 2, 64, 255, 256] {
        scene.interleave_permutations = permutations;
        scene.validate().expect("in range");
    }
    for permutations in [0, 257, u32::MAX] {
        scene.interleave_permutations = permutations;
        match scene.validate() {
            Err(SceneError::InvalidInterleavePermutations { permutations: p }) => {
                assert_eq!(p, permutations);
            }
            other => panic!("interleave_permutations = {permutations}: {other:?}"),
        }
    }
    let parsed: Scene = toml::from_str("interleave_permutations = 1").expect("parses");
    assert_eq!(parsed.interleave_permutations, 1);
}

/// With one permutation every Interleave tile repeats the same pattern, so
/// the image differs from the default 64's, and the reference renders both.
#[test]
fn one_interleave_permutation_changes_the_moving_teapots_image() {
    let mut scene = teapot(96, 4);
    scene.objects[0].transform_close = Some(Transform {
        rotate_degrees: Vec3::new(0.0, 0.0, 20.0),
        ..scene.objects[0].transform
    });
    scene.sampling = Sampling::Interleave;
    let many = render(&scene);
    scene.interleave_permutations = 1;
    let one = render(&scene);
    assert!(many.image != one.image);
}

/// Adaptive's cost model: a still, sharp grid goes to INTERVAL (one box per
/// interval, hardly larger than the micropolygon), a grid moving or
/// blurring far goes to Interleave UVT (whose cost does not grow with
/// blur), and larger Interleave tiles move the crossing to more blur.
#[test]
fn adaptive_picks_interval_for_sharp_grids_and_interleave_for_blurred_ones() {
    for spp in [4, 16, 64] {
        assert_eq!(
            adaptive_choice(0.0, 0.0, 1.0, spp, 2),
            Mode5d::Interval,
            "spp {spp}"
        );
        assert_eq!(
            adaptive_choice(40.0 * spp as f32, 0.0, 1.0, spp, 2),
            Mode5d::Interleave,
            "spp {spp}"
        );
        assert_eq!(
            adaptive_choice(0.0, 40.0, 1.0, spp, 2),
            Mode5d::Interleave,
            "spp {spp}"
        );
        // NaN extents (a point behind the eye) are treated as a still grid.
        assert_eq!(
            adaptive_choice(f32::NAN, 0.0, 1.0, spp, 2),
            Mode5d::Interval
        );
    }
    // The motion at which Interleave UVT becomes cheaper grows with K.
    let crossing = |tile| {
        (0..10_000)
            .map(|m| m as f32 * 0.1)
            .find(|&m| adaptive_choice(m, 0.0, 1.0, 16, tile) == Mode5d::Interleave)
            .expect("a crossing")
    };
    let (k2, k3, k4) = (crossing(2), crossing(3), crossing(4));
    eprintln!("motion crossings at 16 spp: K=2 {k2}, K=3 {k3}, K=4 {k4} pixels");
    assert!(k2 < k3 && k3 < k4);
    // Interleave UVT's cost grows with the sample count and does not
    // depend on blur; INTERVAL's grows with blur.
    let (i4, l4) = adaptive_costs(10.0, 1.0, 1.0, 4, 2);
    let (i16, l16) = adaptive_costs(10.0, 1.0, 1.0, 16, 2);
    assert!(i4 > 0.0 && l4 > 0.0 && l16 > l4);
    let (i16_blurred, l16_blurred) = adaptive_costs(10.0, 5.0, 1.0, 16, 2);
    assert!(i16_blurred > i16 && l16_blurred == l16);
}

/// A still teapot and, beside it, one spinning 60 degrees over the shutter,
/// under Adaptive sampling, with the camera framing both.
fn mixed_teapots(side: u32, spp: u32) -> Scene {
    let mut scene = teapot(side, spp);
    scene.sampling = Sampling::Adaptive;
    let still = scene.objects[0].clone();
    let mut spinning = still.clone();
    spinning.transform.translate += Vec3::new(4.0, 0.0, 0.0);
    spinning.transform_close = Some(Transform {
        rotate_degrees: spinning.transform.rotate_degrees + Vec3::new(0.0, 0.0, 60.0),
        ..spinning.transform
    });
    scene.objects = vec![still, spinning];
    scene.camera = None;
    scene
}

/// Adaptive gives every sample the time and lens position of the Interleave
/// tuple it carries, in the grids it sends to INTERVAL too; the two modes
/// then differ only in how they find the samples a micropolygon may cover,
/// and Adaptive renders Interleave UVT's image exactly, with motion and a
/// lens, grids of both modes sharing edges. With the per-pixel table for
/// its INTERVAL grids, a sample had two times and lens positions, and the
/// edges between grids of different modes left gaps and overlaps under
/// motion (Adaptive's noise 2.96 against Interleave's 2.23 in the noise
/// table of docs/performance.md).
#[test]
fn adaptive_renders_interleave_uvts_image_with_grids_of_both_modes() {
    let mut scene = mixed_teapots(128, 16);
    scene.lens.aperture = 0.05;
    let adaptive = render(&scene);
    let stats = &adaptive.stats;
    eprintln!(
        "mixed, with a lens: {} of {} grids to Interleave UVT",
        stats.interleave_grids, stats.grids_diced
    );
    assert!(stats.interleave_grids > 0 && stats.interleave_grids < stats.grids_diced);
    scene.sampling = Sampling::Interleave;
    let interleave = render(&scene);
    assert_eq!(stats.samples_hit, interleave.stats.samples_hit);
    let differing = adaptive
        .image
        .pixels()
        .zip(interleave.image.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differing, 0, "pixels differing from Interleave UVT's image");
}

/// A mixed scene: a still teapot and a fast-spinning one. Adaptive sends
/// some grids to each mode, and with the still teapot alone it sends none
/// to Interleave UVT. (Which is faster is measured by `blur-bench`, not
/// here: a test's time is no measure.)
#[test]
fn adaptive_splits_a_mixed_scene() {
    let mut scene = mixed_teapots(128, 16);
    let still = scene.objects[0].clone();
    let mixed = render(&scene).stats;
    eprintln!(
        "mixed: interleave grids {} of {}",
        mixed.interleave_grids, mixed.grids_diced
    );
    assert!(mixed.interleave_grids > 0 && mixed.interleave_grids < mixed.grids_diced);
    scene.objects = vec![still];
    let alone = render(&scene).stats;
    assert_eq!(alone.interleave_grids, 0, "{} grids", alone.grids_diced);
}
