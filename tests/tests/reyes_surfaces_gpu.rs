//! Every standard surface under every standard light on the GPU against
//! the CPU reference: six spheres (`constant`, `matte`, `metal`, a plastic
//! with a coloured highlight, `defaultsurface` and `null`) lit by a
//! coloured ambient light, a distant light, a point light and a spotlight
//! whose cone edge crosses two of them, at 1 and 16 samples per pixel, each
//! sphere at its own shading rate, whole and in screen tiles.
//! The formulas themselves are checked against arithmetic in
//! `reyes/tests/shading_formulas.rs` and `reyes/src/reference/shade.rs`.

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::gpu::GpuOptions;
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Light, Scene, SceneObject, Surface, Transform};
use tests::reyes_support::{agreement, camera_down_z, gpu_turn, renderer, tiled_renderer};
use tests::shapes::bezier_sphere;

/// The six spheres in two rows of three, 5 units in front of the camera.
fn scene(spp: u32) -> (Scene, Vec<Model>) {
    let mut scene = Scene::default();
    scene.resolution.width = 160;
    scene.resolution.height = 120;
    scene.spp = spp;
    scene.camera = Some(camera_down_z());
    scene.ambient = 0.0;
    let surfaces = [
        Surface::Constant,
        Surface::Matte { ka: 0.5, kd: 0.9 },
        Surface::Metal {
            ka: 0.3,
            ks: 0.9,
            roughness: 0.15,
        },
        Surface::Plastic {
            ka: 1.0,
            kd: 0.6,
            ks: 0.8,
            roughness: 0.05,
            specular_color: Vec3::new(1.0, 0.6, 0.2),
        },
        Surface::DEFAULT_SURFACE,
        Surface::Null,
    ];
    let mut models = Vec::new();
    for (i, surface) in surfaces.into_iter().enumerate() {
        let column = (i % 3) as f32 - 1.0;
        let row = if i < 3 { 0.6 } else { -0.6 };
        scene.objects.push(SceneObject {
            model: format!("sphere-{i}"),
            subdivision: None,
            transform: Transform {
                translate: Vec3::new(column * 1.2, row, -5.0),
                scale: reyes::scene::Scale::Uniform(0.5),
                ..Transform::default()
            },
            color: Vec3::new(0.9, 0.5 + 0.1 * i as f32, 0.3),
            surface: Some(surface),
            // Each object its own shading rate: 0.25 to 8 pixels.
            shading_rate: Some([0.25, 1.0, 4.0, 0.5, 8.0, 1.0][i]),
            displacement: None,
            transform_close: None,
            keys: Vec::new(),
            sides: 2,
            reverse_orientation: false,
        });
        models.push(bezier_sphere());
    }
    let mut spot = Light::spot(
        Vec3::new(0.0, 2.0, -1.0),
        Vec3::new(0.0, -2.0, -4.0),
        Vec3::new(0.8, 0.9, 1.0),
        12.0,
    );
    spot.cone_angle_degrees = 18.0;
    spot.cone_delta_degrees = 6.0;
    scene.lights = vec![
        Light::ambient(Vec3::new(0.2, 0.15, 0.1), 1.0),
        Light {
            direction: Vec3::new(1.0, -1.0, -1.0),
            intensity: 0.6,
            ..Light::default()
        },
        Light::point(Vec3::new(-2.0, 0.0, -3.0), Vec3::new(1.0, 0.8, 0.6), 2.0),
        spot,
    ];
    (scene, models)
}

/// On wgpu's GL backend, which has no 64-bit atomics, this runs the
/// two-pass 32-bit depth test (`.ci/gl-tests.sh`).
#[gpu_test]
fn every_standard_surface_and_light_matches_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut whole = renderer(gpu, GpuOptions::default());
    for spp in [1, 16] {
        // A third of the frame's samples: six tiles of 64 x 64 pixels, whose
        // edge at row 64 crosses the bottom row of spheres.
        let mut tiled = tiled_renderer(gpu, 160 * 120 / 3 * u64::from(spp));
        let (scene, models) = scene(spp);
        let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
        let cpu = reference::render(&prepared);
        // Five spheres are drawn, the null one is not: the bottom right
        // sphere's centre (x = 80 + 60 * (1.2 / 5) / tan 30, y = 60 + 60 *
        // (0.6 / 5) / tan 30) shows the background.
        // (Compared as the resolve's floats: the 8-bit codes carry a
        // dither that differs from pixel to pixel.)
        let shows_background = |what: &str, linear: &image::Rgba32FImage| {
            let background = linear.get_pixel(105, 72);
            let corner = linear.get_pixel(0, 0);
            assert!(
                (0..3).all(|c| (background[c] - corner[c]).abs() < 1e-6),
                "{what}: the null sphere is not drawn: {background:?} vs {corner:?}"
            );
        };
        shows_background(&format!("CPU at spp {spp}"), &cpu.linear);
        // The constant sphere is its colour exactly, whatever the lights.
        let constant = cpu.image.get_pixel(55, 47);
        let cs = reyes::color::linear_to_srgb8(0.9);
        assert!(constant[0].abs_diff(cs) <= 1, "{constant:?} vs {cs}");
        for (mode, renderer) in [("whole", &mut whole), ("tiled", &mut tiled)] {
            let gpu_frame = renderer.render(&prepared).expect("GPU render");
            let what = format!("surfaces at spp {spp}, {mode}");
            let a = agreement(&gpu_frame, &cpu);
            eprintln!("{what} ({} tile(s)): {a:?}", gpu_frame.tiles);
            assert_eq!(
                gpu_frame.tiles > 1,
                mode == "tiled",
                "{what}: {} tile(s)",
                gpu_frame.tiles
            );
            a.assert_at_least(&what, 0.995, 0.99);
            shows_background(&what, &gpu_frame.linear);
            if gpu_frame.tiles == 1 {
                // Diced at each object's own rate, as the reference dices
                // them (in tiles, each tile dices the spheres it overlaps,
                // so a sphere across a tile edge is diced more than once).
                tests::reyes_support::assert_counts_close(
                    "grids diced",
                    gpu_frame.stats.grids_diced,
                    cpu.stats.grids_diced,
                );
                tests::reyes_support::assert_counts_close(
                    "micropolygons",
                    gpu_frame.stats.micropolygons,
                    cpu.stats.micropolygons,
                );
            }
        }
    }
}
