//! Dicing to a shading rate on the GPU against the CPU reference, against
//! the fixed dicer's pictures, one-sided objects and the AOV pictures.
//! (Watertightness is `reyes_watertight.rs`.)

use std::path::PathBuf;

use glam::Vec3;
use gpu_test::gpu_test;
use image::RgbaImage;
use reyes::aov::{Aov, grid_colors};
use reyes::model::{Model, Patch};
use reyes::prepare::PreparedScene;
use reyes::reference::{self, Rendered};
use reyes::scene::{CameraDesc, Dicing, Scene, SceneObject, ShadingInterpolation};
use tests::reyes_support::{
    agreement, as_reference, assert_counts_close, camera_down_z, framed_teapot, gpu_turn,
    patient_renderer,
};

fn killeroo() -> Option<Scene> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/killeroo.bpt");
    if !path.exists() {
        eprintln!(
            "NOTICE: {} not found; skipping the Killeroo part",
            path.display()
        );
        return None;
    }
    let model = Model::load(&path).expect("the Killeroo loads");
    let mut scene = Scene::for_model(path.to_string_lossy(), &model);
    scene.resolution.width = 320;
    scene.resolution.height = 240;
    let (lo, hi) = model.bounds();
    scene.camera = Some(CameraDesc::framing(lo, hi, 320.0 / 240.0));
    Some(scene)
}

/// `scene` diced by `dicing` at `shading_rate`, each pixel the mean of its
/// own samples (a box over one pixel): the pictures are compared pixel by
/// pixel, and the table in docs/reyes.md ("Shade") was measured so.
fn with(mut scene: Scene, dicing: Dicing, shading_rate: f32) -> PreparedScene {
    scene.dicing = dicing;
    scene.shading_rate = shading_rate;
    scene.pixel_filter = reyes::filter::PixelFilter::PIXEL_BOX;
    PreparedScene::load(&scene).expect("scene prepares")
}

/// At every shading rate the GPU dices, shades and samples like the CPU
/// reference: the same grids of the same sizes, images within 2/255.
#[gpu_test]
fn rate_dicing_matches_the_reference_at_every_rate() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = patient_renderer(gpu);
    for rate in [0.25, 1.0, 4.0, 16.0] {
        let prepared = with(framed_teapot(160, 120, 4), Dicing::Rate, rate);
        let g = renderer.render(&prepared).expect("GPU render");
        let c = reference::render(&prepared);
        let a = agreement(&g, &c);
        eprintln!(
            "shading rate {rate}: GPU {:?}\n  CPU {:?}\n  {a:?}",
            g.stats, c.stats
        );
        a.assert_at_least(&format!("shading rate {rate}"), 0.995, 0.99);
        for (what, gpu, cpu) in [
            ("grids", g.stats.grids_diced, c.stats.grids_diced),
            (
                "micropolygons",
                g.stats.micropolygons,
                c.stats.micropolygons,
            ),
            ("samples hit", g.stats.samples_hit, c.stats.samples_hit),
            ("dice threads", g.stats.dice_threads, c.stats.dice_threads),
        ] {
            assert_counts_close(&format!("rate {rate}: {what}"), gpu, cpu);
        }
        assert_eq!(
            g.stats.grids_by_class.iter().sum::<u64>(),
            g.stats.grids_diced
        );
        assert_eq!(g.stats.depth_guard_drops, 0);
    }
}

/// At shading rate 1 and below the pictures are the previous renderer's
/// (the fixed dicer with constant shading), on the teapot and the
/// Killeroo: the same coverage (IoU >= 0.995), with fewer micropolygons.
/// Their colours are compared with an independent, converged picture (the
/// CPU reference at shading rate 1/32): on the teapot, at shading rates 0.5
/// and 1, rate dicing with smooth shading has no more interior pixels off
/// by more than 2/255 than the previous renderer (10% slack). At this size the Killeroo's fixed grids have
/// more than 100 micropolygons per pixel, finer than any shading rate
/// here: its counts are printed, not asserted
/// (`smooth_shading_approaches_the_converged_picture` compares its colours
/// at the benchmark's 800 x 600).
#[gpu_test]
fn rate_dicing_draws_the_fixed_dicers_pictures() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = patient_renderer(gpu);
    let mut scenes = vec![("teapot", framed_teapot(320, 240, 4), true)];
    scenes.extend(killeroo().map(|s| ("killeroo", s, false)));
    for (name, scene, colours_asserted) in scenes {
        let converged = reference::render(&with(scene.clone(), Dicing::Rate, 1.0 / 32.0));
        // The previous renderer's picture: the fixed dicer, one colour per
        // micropolygon.
        let mut previous = scene.clone();
        previous.shading_interpolation = ShadingInterpolation::Constant;
        let fixed = renderer
            .render(&with(previous, Dicing::Fixed, 1.0))
            .expect("GPU render");
        let fixed_off = off_pixels(&fixed.image, &fixed.covered_samples, &converged, scene.spp);
        for (rate, slack) in [(0.5, 1.1), (1.0, 1.1)] {
            let rated = renderer
                .render(&with(scene.clone(), Dicing::Rate, rate))
                .expect("GPU render");
            let a = agreement(&rated, &as_reference(&fixed));
            let off = off_pixels(&rated.image, &rated.covered_samples, &converged, scene.spp);
            eprintln!(
                "{name} at shading rate {rate}: vs fixed {a:?}; interior pixels off the converged picture by > 2/255: {off} (fixed: {fixed_off}); micropolygons {} (fixed {})",
                rated.stats.micropolygons, fixed.stats.micropolygons
            );
            assert!(
                a.iou >= 0.995,
                "{name} at shading rate {rate}: IoU {}",
                a.iou
            );
            assert!(
                !colours_asserted || off as f64 <= slack * fixed_off as f64 + 10.0,
                "{name} at shading rate {rate}: {off} interior pixels off by > 2/255, the fixed dicer {fixed_off}"
            );
            assert!(rated.stats.micropolygons < fixed.stats.micropolygons);
        }
    }
}

/// Smooth shading against constant shading, on the CPU reference: on the
/// teapot and the Killeroo at shading rates 0.5 and 1, blending the corner
/// colours leaves fewer interior pixels off an independent, converged
/// picture (shading rate 1/32) by more than 2/255 than one colour per
/// micropolygon does, and at shading rate 0.5 no more than the fixed
/// dicer's 16 x 16 grids with constant shading (the previous renderer):
/// 10% slack on the teapot, 50% on the Killeroo, where the fixed dicer's
/// 24 micropolygons per sample come closer to the converged colours
/// at its many small features.
#[test]
fn smooth_shading_approaches_the_converged_picture() {
    let mut scenes = vec![("teapot", framed_teapot(320, 240, 4), 1.1)];
    // The Killeroo as the dicing benchmark draws it (800 x 600, 1 spp):
    // smaller, its fixed grids would be finer than the converged picture's.
    scenes.extend(killeroo().map(|mut s| {
        (s.resolution.width, s.resolution.height, s.spp) = (800, 600, 1);
        s.camera = None;
        ("killeroo", s, 1.5)
    }));
    let render = |scene: &Scene, dicing, rate, interpolation| {
        let mut scene = scene.clone();
        scene.shading_interpolation = interpolation;
        reference::render(&with(scene, dicing, rate))
    };
    for (name, scene, slack) in scenes {
        let converged = render(
            &scene,
            Dicing::Rate,
            1.0 / 32.0,
            ShadingInterpolation::Smooth,
        );
        let off = |frame: &Rendered| {
            off_pixels(&frame.image, &frame.covered_samples, &converged, scene.spp)
        };
        let fixed = off(&render(
            &scene,
            Dicing::Fixed,
            1.0,
            ShadingInterpolation::Constant,
        ));
        for rate in [0.5, 1.0] {
            let constant = off(&render(
                &scene,
                Dicing::Rate,
                rate,
                ShadingInterpolation::Constant,
            ));
            let smooth = off(&render(
                &scene,
                Dicing::Rate,
                rate,
                ShadingInterpolation::Smooth,
            ));
            eprintln!(
                "{name} at shading rate {rate}: interior pixels off the converged picture by > 2/255: smooth {smooth}, constant {constant}, fixed dicer (constant) {fixed}"
            );
            assert!(
                smooth * 2 < constant,
                "{name} at rate {rate}: smooth {smooth} vs constant {constant}"
            );
            if rate == 0.5 {
                assert!(
                    smooth as f64 <= slack * fixed as f64 + 10.0,
                    "{name} at rate {rate}: smooth {smooth} vs the fixed dicer {fixed}"
                );
            }
        }
    }
}

/// Pixels whose every sample both a frame (`image`, `covered_samples`) and
/// `converged` cover (the shading, without the silhouettes, where
/// different tessellations cover different samples of a pixel: the
/// coverage IoU measures those) and whose colours differ by more than 2/255.
fn off_pixels(image: &RgbaImage, covered: &[u16], converged: &Rendered, spp: u32) -> usize {
    let full = u16::try_from(spp).expect("spp <= 256");
    covered
        .iter()
        .zip(&converged.covered_samples)
        .enumerate()
        .filter(|&(i, (&a, &b))| {
            a == full
                && b == full
                && (0..3).any(|ch| {
                    image.as_raw()[4 * i + ch].abs_diff(converged.image.as_raw()[4 * i + ch]) > 2
                })
        })
        .count()
}

/// A square card of one patch at depth 3, facing the eye with its
/// `dP/du x dP/dv` pointing away from it (u along +x, v along -y).
fn card_scene() -> (Scene, Vec<Model>) {
    let points = std::array::from_fn(|k| {
        let (u, v) = ((k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0);
        Vec3::new(-1.0 + 2.0 * u, 1.0 - 2.0 * v, -3.0)
    });
    let mut scene = Scene::default();
    scene.resolution.width = 64;
    scene.resolution.height = 64;
    scene.camera = Some(camera_down_z());
    scene.objects.push(SceneObject {
        transform: Default::default(),
        color: Vec3::splat(0.8),
        ..SceneObject::new("card")
    });
    (scene, vec![Model::new(vec![Patch { points }])])
}

/// A one-sided card facing away is culled in Bound and draws nothing; with
/// its orientation reversed it draws like the two-sided card. A one-sided
/// closed teapot seen from outside draws nearly what the two-sided one
/// does, with fewer micropolygons sampled; reversed, it shows its inside.
/// On the GPU and the CPU alike.
#[gpu_test]
fn one_sided_objects_cull_their_back_faces() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = patient_renderer(gpu);
    let (scene, models) = card_scene();
    let prepare = |sides: u8, reverse: bool| {
        let mut scene = scene.clone();
        scene.objects[0].sides = sides;
        scene.objects[0].reverse_orientation = reverse;
        PreparedScene::new(&scene, &models).expect("card prepares")
    };
    let two = renderer.render(&prepare(2, false)).expect("GPU render");
    assert!(two.coverage.iter().filter(|&&c| c).count() > 500);
    let away = prepare(1, false);
    let g = renderer.render(&away).expect("GPU render");
    let c = reference::render(&away);
    assert_eq!(g.stats.culled_patches, 1);
    assert_eq!(c.stats.culled_patches, 1);
    assert!(!g.coverage.iter().any(|&c| c) && !c.coverage.iter().any(|&c| c));
    let reversed = renderer.render(&prepare(1, true)).expect("GPU render");
    assert_eq!(reversed.image, two.image);

    let teapot = framed_teapot(160, 120, 4);
    let sided = |sides: u8, reverse: bool| {
        let mut scene = teapot.clone();
        scene.objects[0].sides = sides;
        scene.objects[0].reverse_orientation = reverse;
        PreparedScene::load(&scene).expect("teapot prepares")
    };
    let both = renderer.render(&sided(2, false)).expect("GPU render");
    let front = sided(1, false);
    let g = renderer.render(&front).expect("GPU render");
    let c = reference::render(&front);
    agreement(&g, &c).assert_at_least("one-sided GPU vs CPU", 0.995, 0.99);
    let a = agreement(&g, &as_reference(&both));
    eprintln!(
        "one-sided vs two-sided: {a:?}; tested {} vs {}",
        g.stats.samples_tested, both.stats.samples_tested
    );
    assert!(a.iou > 0.98, "the outside is drawn: IoU {}", a.iou);
    assert!(g.stats.culled_patches > both.stats.culled_patches);
    assert!(g.stats.samples_tested < both.stats.samples_tested * 3 / 4);
    let inside = renderer.render(&sided(1, true)).expect("GPU render");
    let a = agreement(&inside, &as_reference(&both));
    assert!(
        a.within_2 < 0.5,
        "reversed, the inside is drawn instead: {a:?}"
    );
}

/// The AOV pictures: the GPU's grids, depth and normal images equal the
/// CPU reference's, and the grids picture uses only the palette (each
/// size's colour and its checker) over the background.
#[gpu_test]
fn aov_pictures_match_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = patient_renderer(gpu);
    for aov in [Aov::Grids, Aov::Depth, Aov::Normal] {
        let mut scene = framed_teapot(160, 120, 1);
        scene.aov = aov;
        let prepared = PreparedScene::load(&scene).expect("teapot prepares");
        let g = renderer.render(&prepared).expect("GPU render");
        let c = reference::render(&prepared);
        let a = agreement(&g, &c);
        eprintln!("{}: {a:?}", aov.name());
        a.assert_at_least(aov.name(), 0.995, 0.99);
        if aov == Aov::Grids {
            let palette: Vec<[u8; 3]> = grid_colors()
                .iter()
                .map(|&packed| {
                    let c = reyes::color::unpack_rgb10(packed);
                    [c.x, c.y, c.z].map(reyes::color::linear_to_srgb8)
                })
                .collect();
            for (pixel, &covered) in g.image.pixels().zip(&g.coverage) {
                if covered {
                    let rgb = [pixel.0[0], pixel.0[1], pixel.0[2]];
                    assert!(palette.contains(&rgb), "{rgb:?} is not a grid colour");
                }
            }
        }
    }
}
