//! Motion blur and depth of field (the 5D sampling modes of
//! `reyes::scene::Sampling`), checked against independent references:
//!
//! * a stationary, in-focus frame samples the same in every mode as on the
//!   plain path;
//! * every mode on the GPU agrees with the CPU reference
//!   (`reyes::reference::raster5d`) on a spinning, defocused teapot;
//! * a moving card's streak spans its motion vector, as projected by the
//!   camera, to within a pixel;
//! * depth of field keeps the focal plane sharp and blurs a card off it by
//!   about its circle of confusion;
//! * a card that is off screen at shutter open and moves into view is not
//!   culled;
//! * a bounding-box frame whose sample loops exceed llvmpipe's loop limit is
//!   a typed error there, and Interleave UVT renders it;
//! * a moving camera is the world moving the other way, and a panning
//!   camera's streak spans the card's projections through the cameras at
//!   open and at close (each built on its own), on the GPU and on the CPU;
//! * invalid motion and lens settings are typed errors.

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::gpu::{GpuOptions, GpuRendered, GpuRenderer};
use reyes::model::{Model, Patch};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{CameraPose, Sampling, Scene, SceneError, SceneObject, Transform};
use tests::reyes_support::{
    agreement, as_reference, assert_counts_close, camera_down_z, framed_teapot, gpu_turn, renderer,
};

/// The modes that sample time and lens.
const MODES: [Sampling; 5] = Sampling::TIME_AND_LENS;

/// Image side of the card scenes.
const SIDE: u32 = 128;

fn render_gpu(renderer: &mut GpuRenderer<'_>, scene: &PreparedScene) -> GpuRendered {
    let rendered = renderer.render(scene).expect("GPU render");
    eprintln!(
        "{:?}: tested {}, hit {}, efficiency {:.4}, interleave grids {}",
        scene.sampling,
        rendered.stats.samples_tested,
        rendered.stats.samples_hit,
        rendered.stats.sample_test_efficiency(),
        rendered.stats.interleave_grids
    );
    rendered
}

#[gpu_test]
fn a_still_sharp_frame_samples_alike_in_every_mode() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    let mut scene = framed_teapot(128, 128, 4);
    let plain = PreparedScene::load(&scene).expect("scene prepares");
    assert!(!plain.samples_time_and_lens());
    let plain = render_gpu(&mut renderer, &plain);
    assert!(plain.stats.samples_hit > 10_000);
    for mode in MODES {
        scene.sampling = mode;
        let prepared = PreparedScene::load(&scene).expect("scene prepares");
        let rendered = render_gpu(&mut renderer, &prepared);
        let cpu = reference::render(&prepared);
        let a = agreement(&rendered, &as_reference(&plain));
        a.assert_at_least(&format!("{mode:?}"), 0.995, 0.99);
        // Still and sharp, every mode tests each sample against the same
        // triangles as the plain path, just grouped differently: the hits
        // are the same, on the GPU and in the reference.
        assert_eq!(
            rendered.stats.samples_hit, plain.stats.samples_hit,
            "{mode:?}"
        );
        assert_eq!(
            cpu.stats.samples_hit, rendered.stats.samples_hit,
            "{mode:?}"
        );
        assert!(rendered.stats.samples_tested >= rendered.stats.samples_hit);
    }
}

/// The 96 x 96, 4-spp teapot spinning 20 degrees, focused on the camera
/// target (its centre): grids near the spin axis and the focal plane stay
/// sharp, the spout and handle blur.
fn spinning_defocused_teapot() -> Scene {
    let mut scene = framed_teapot(96, 96, 4);
    for object in &mut scene.objects {
        object.transform_close = Some(Transform {
            rotate_degrees: Vec3::new(0.0, 0.0, 20.0),
            ..object.transform
        });
    }
    scene.lens.aperture = 0.1;
    scene
}

#[gpu_test]
fn every_mode_matches_the_cpu_reference_with_motion_and_depth_of_field() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    let mut scene = spinning_defocused_teapot();
    let mut interleave_grids = Vec::new();
    for mode in MODES {
        scene.sampling = mode;
        let prepared = PreparedScene::load(&scene).expect("scene prepares");
        let g = render_gpu(&mut renderer, &prepared);
        let c = reference::render(&prepared);
        let a = agreement(&g, &c);
        eprintln!("{mode:?}: {a:?}");
        assert!(a.coverage >= 0.1, "{mode:?}: coverage {:.3}", a.coverage);
        a.assert_at_least(&format!("{mode:?}"), 0.99, 0.98);
        assert_counts_close("grids diced", g.stats.grids_diced, c.stats.grids_diced);
        assert_counts_close(
            "samples tested",
            g.stats.samples_tested,
            c.stats.samples_tested,
        );
        assert_counts_close("samples hit", g.stats.samples_hit, c.stats.samples_hit);
        assert_counts_close(
            "samples skipped",
            g.stats.samples_skipped,
            c.stats.samples_skipped,
        );
        assert_counts_close(
            "interleave grids",
            g.stats.interleave_grids,
            c.stats.interleave_grids,
        );
        interleave_grids.push(c.stats.interleave_grids);
    }
    eprintln!("interleave grids per mode: {interleave_grids:?}");
    // Interleave UVT samples every grid with it; the others none; Adaptive
    // decides per grid (this frame has both small and large blur).
    let grids = interleave_grids[2];
    assert!(grids > 0);
    assert_eq!(
        interleave_grids[0] + interleave_grids[1] + interleave_grids[3],
        0
    );
    assert!(
        interleave_grids[4] > 0 && interleave_grids[4] < grids,
        "adaptive sent {} of {grids} grids to Interleave UVT",
        interleave_grids[4]
    );
}

/// Interleave UVT with 3 x 3 and 4 x 4 tiles (and Adaptive, which uses
/// them), and with one permutation for every tile as well as the default
/// 64, agrees with the CPU reference, sample counts included.
#[gpu_test]
fn larger_interleave_tiles_match_the_cpu_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    let mut scene = spinning_defocused_teapot();
    scene.jitter = true;
    for (mode, tile, permutations) in [
        (Sampling::Interleave, 3, 64),
        (Sampling::Interleave, 4, 64),
        (Sampling::Adaptive, 3, 64),
        (Sampling::Interleave, 2, 1),
        (Sampling::Adaptive, 4, 1),
    ] {
        scene.sampling = mode;
        scene.interleave_tile = tile;
        scene.interleave_permutations = permutations;
        let prepared = PreparedScene::load(&scene).expect("scene prepares");
        let g = render_gpu(&mut renderer, &prepared);
        let c = reference::render(&prepared);
        let a = agreement(&g, &c);
        let mode = format!("{mode:?}, K = {tile}, P = {permutations}");
        eprintln!("{mode}: {a:?}");
        assert!(a.coverage >= 0.1, "{mode}: coverage {:.3}", a.coverage);
        a.assert_at_least(&mode, 0.99, 0.98);
        assert_counts_close(
            "samples tested",
            g.stats.samples_tested,
            c.stats.samples_tested,
        );
        assert_counts_close("samples hit", g.stats.samples_hit, c.stats.samples_hit);
    }
}

/// A flat square card facing +z, `2 * half` wide, centred at `centre`.
fn card(centre: Vec3, half: f32) -> Model {
    let points = std::array::from_fn(|k| {
        let (u, v) = ((k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0);
        centre + Vec3::new(-half + 2.0 * half * u, half - 2.0 * half * v, 0.0)
    });
    Model::new(vec![Patch { points }])
}

/// The card scene: the eye at the origin looking down -z with a 60 degree
/// view, `SIDE x SIDE` pixels, spp 64, white light from the eye, one object
/// per card (moving from `transform` by `motion`).
fn card_scene(cards: &[(Vec3, f32, Vec3)], sampling: Sampling) -> (Scene, Vec<Model>) {
    let mut scene = Scene::default();
    scene.resolution.width = SIDE;
    scene.resolution.height = SIDE;
    scene.spp = 64;
    scene.sampling = sampling;
    scene.camera = Some(camera_down_z());
    scene.lights[0].direction = Vec3::new(0.0, 0.0, -1.0);
    scene.specular.strength = 0.0;
    let mut models = Vec::new();
    for &(centre, half, motion) in cards {
        scene.objects.push(SceneObject {
            model: "card".into(),
            subdivision: None,
            transform: Transform::default(),
            color: Vec3::ONE,
            surface: None,
            shading_rate: None,
            displacement: None,
            transform_close: (motion != Vec3::ZERO).then(|| Transform {
                translate: motion,
                ..Transform::default()
            }),
            keys: Vec::new(),
            sides: 2,
            reverse_orientation: false,
        });
        models.push(card(centre, half));
    }
    (scene, models)
}

/// The pixel x (or y) of a world point in the card scene.
fn project(scene: &PreparedScene, p: Vec3) -> Vec3 {
    scene.camera.to_pixel(scene.camera.to_clip(p))
}

/// The covered pixel columns and rows: `(x_lo, x_hi, y_lo, y_hi)` as pixel
/// edges (the covered pixels span `[x_lo, x_hi)`).
fn covered_extent(coverage: &[bool]) -> (f32, f32, f32, f32) {
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (u32::MAX, 0, u32::MAX, 0);
    for (i, _) in coverage.iter().enumerate().filter(|(_, c)| **c) {
        let (x, y) = (i as u32 % SIDE, i as u32 / SIDE);
        x_lo = x_lo.min(x);
        x_hi = x_hi.max(x + 1);
        y_lo = y_lo.min(y);
        y_hi = y_hi.max(y + 1);
    }
    assert!(x_lo < x_hi, "nothing covered");
    (x_lo as f32, x_hi as f32, y_lo as f32, y_hi as f32)
}

/// The screen box `(left, right, top, bottom)` of pixel positions.
fn pixel_box(pixels: &[Vec3]) -> (f32, f32, f32, f32) {
    let fold = |f: fn(f32, f32) -> f32, start: f32, axis: fn(&Vec3) -> f32| {
        pixels.iter().map(axis).fold(start, f)
    };
    (
        fold(f32::min, f32::INFINITY, |p| p.x),
        fold(f32::max, f32::NEG_INFINITY, |p| p.x),
        fold(f32::min, f32::INFINITY, |p| p.y),
        fold(f32::max, f32::NEG_INFINITY, |p| p.y),
    )
}

/// Asserts that the covered pixels span the `expected` screen box (from
/// [`pixel_box`]) to within a pixel on every side.
fn assert_streak(what: &str, coverage: &[bool], expected: (f32, f32, f32, f32)) {
    let (left, right, top, bottom) = expected;
    let (x_lo, x_hi, y_lo, y_hi) = covered_extent(coverage);
    eprintln!(
        "{what}: x {x_lo}..{x_hi} (expected {left:.2}..{right:.2}), y {y_lo}..{y_hi} (expected {top:.2}..{bottom:.2})"
    );
    for (got, want, side) in [
        (x_lo, left, "left"),
        (x_hi, right, "right"),
        (y_lo, top, "top"),
        (y_hi, bottom, "bottom"),
    ] {
        assert!(
            (got - want).abs() <= 1.0,
            "{what}: streak {side} edge at {got}, expected at {want:.2}"
        );
    }
}

#[gpu_test]
fn a_moving_card_streaks_along_its_motion_vector() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    // A card 1 unit wide at depth 5 (about 22 pixels) moving 1.2 units right
    // and 0.3 up during the shutter.
    let (centre, half, motion) = (Vec3::new(-0.5, -0.2, -5.0), 0.5, Vec3::new(1.2, 0.3, 0.0));
    for sampling in [Sampling::Bbox, Sampling::Interleave, Sampling::Interval] {
        let (scene, models) = card_scene(&[(centre, half, motion)], sampling);
        let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
        // The screen box of the card's corners at open and at close.
        let corners = [-half, half].into_iter().flat_map(|dx| {
            [-half, half].into_iter().flat_map(move |dy| {
                [Vec3::ZERO, motion].map(|m| centre + Vec3::new(dx, dy, 0.0) + m)
            })
        });
        let pixels: Vec<Vec3> = corners.map(|p| project(&prepared, p)).collect();
        let expected = pixel_box(&pixels);
        let (left, right, ..) = expected;
        let gpu = render_gpu(&mut renderer, &prepared);
        let cpu = reference::render(&prepared);
        for (who, coverage) in [("GPU", &gpu.coverage), ("CPU", &cpu.coverage)] {
            assert_streak(&format!("{sampling:?} {who}"), coverage, expected);
        }
        // The still card covers only its own square: the streak is the motion.
        let (still, models) = card_scene(&[(centre, half, Vec3::ZERO)], sampling);
        let still = reference::render(&PreparedScene::new(&still, &models).unwrap());
        let (x_lo, x_hi, _, _) = covered_extent(&still.coverage);
        assert!((x_hi - x_lo) < (right - left) - 20.0, "{x_lo}..{x_hi}");
    }
}

/// Gradient energy of a row band's luminance across one vertical edge:
/// the sum of squared horizontal differences over `x0..x1`, rows `y0..y1`.
fn gradient_energy(rendered: &GpuRendered, x0: u32, x1: u32, y0: u32, y1: u32) -> f64 {
    let luminance = |x: u32, y: u32| {
        let p = rendered.image.get_pixel(x, y).0;
        f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2])
    };
    let mut energy = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            let d = luminance(x + 1, y) - luminance(x, y);
            energy += d * d;
        }
    }
    energy
}

#[gpu_test]
fn depth_of_field_keeps_the_focal_plane_sharp_and_blurs_the_rest() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    // A near card at depth 4 (in focus) left of centre, a far card at
    // depth 12 right of centre; both about 28 pixels wide.
    let cards = [
        (Vec3::new(-1.0, 0.0, -4.0), 0.5, Vec3::ZERO),
        (Vec3::new(3.0, 0.0, -12.0), 1.5, Vec3::ZERO),
    ];
    for sampling in [Sampling::Bbox, Sampling::Interleave, Sampling::Adaptive] {
        let (mut scene, models) = card_scene(&cards, sampling);
        let pinhole = PreparedScene::new(&scene, &models).expect("scene prepares");
        scene.lens.aperture = 0.25;
        scene.lens.focus_distance = Some(4.0);
        let lens = PreparedScene::new(&scene, &models).expect("scene prepares");
        let far_coc = lens.lens.coc(12.0);
        assert!(
            far_coc > 4.0,
            "the far card's circle of confusion is {far_coc} px"
        );
        assert_eq!(lens.lens.coc(4.0), 0.0);
        let sharp = render_gpu(&mut renderer, &pinhole);
        let blurred = render_gpu(&mut renderer, &lens);
        // Each card's left edge, and a band of rows through its middle.
        let near_edge = project(&lens, Vec3::new(-1.5, 0.0, -4.0)).x as u32;
        let far_edge_x = project(&lens, Vec3::new(1.5, 0.0, -12.0)).x;
        let far_edge = far_edge_x as u32;
        let (y0, y1) = (SIDE / 2 - 6, SIDE / 2 + 6);
        let window = |edge: u32| (edge - 8, edge + 8);
        let energy = |r: &GpuRendered, edge: u32| {
            let (x0, x1) = window(edge);
            gradient_energy(r, x0, x1, y0, y1)
        };
        let near = energy(&blurred, near_edge) / energy(&sharp, near_edge);
        let far = energy(&blurred, far_edge) / energy(&sharp, far_edge);
        eprintln!(
            "{sampling:?}: gradient energy with the lens / pinhole: near {near:.3}, far {far:.3}"
        );
        assert!(
            near > 0.9,
            "{sampling:?}: the focal plane lost sharpness ({near:.3})"
        );
        assert!(
            far < 0.5,
            "{sampling:?}: the far card stayed sharp ({far:.3})"
        );
        // The blur spreads the far card's edge over about 2 * coc pixels.
        let (x0, x1) = window(far_edge);
        let row = SIDE / 2;
        let covered: Vec<bool> = (x0..x1)
            .map(|x| blurred.coverage[(row * SIDE + x) as usize])
            .collect();
        let first = covered
            .iter()
            .position(|&c| c)
            .expect("the far card is covered") as f32;
        let expected = far_edge_x - far_coc - x0 as f32;
        assert!(
            (first - expected).abs() <= 1.5,
            "{sampling:?}: blurred edge starts {first} px into the window, the circle of confusion puts it at {expected:.2}"
        );
    }
}

#[gpu_test]
fn a_card_moving_into_view_is_not_culled() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    // Off screen to the left at open (the view is +-2.9 units wide at depth
    // 5), in the middle at close.
    let (centre, half, motion) = (Vec3::new(-4.0, 0.0, -5.0), 0.5, Vec3::new(4.0, 0.0, 0.0));
    let (scene, models) = card_scene(&[(centre, half, motion)], Sampling::Adaptive);
    let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    let right = project(&prepared, centre + Vec3::new(half, 0.0, 0.0) + motion).x;
    let gpu = render_gpu(&mut renderer, &prepared);
    let cpu = reference::render(&prepared);
    for (who, coverage, stats) in [
        ("GPU", &gpu.coverage, &gpu.stats),
        ("CPU", &cpu.coverage, &cpu.stats),
    ] {
        assert_eq!(stats.culled_patches, 0, "{who}");
        let (x_lo, x_hi, _, _) = covered_extent(coverage);
        assert_eq!(x_lo, 0.0, "{who}: the streak enters from the left edge");
        assert!(
            (x_hi - right).abs() <= 1.0,
            "{who}: streak ends at {x_hi}, expected {right:.2}"
        );
    }
    // A still card there is culled.
    let (still, models) = card_scene(&[(centre, half, Vec3::ZERO)], Sampling::Adaptive);
    let still = reference::render(&PreparedScene::new(&still, &models).unwrap());
    assert_eq!(still.stats.culled_patches, 1);
}

/// A bounding-box frame whose micropolygon boxes need more loop iterations
/// than llvmpipe allows one invocation: on llvmpipe the renderer, after its
/// retries, returns `RenderError::LoopLimit` naming the remedies instead of
/// an image with samples missing, and one of those remedies (Interleave
/// UVT, which does a bounded amount of work per micropolygon) renders the
/// same scene as the CPU reference does. A GPU without the limit renders
/// the bounding-box frame as the reference does.
#[gpu_test]
fn a_sample_loop_too_long_for_llvmpipe_is_a_typed_error_not_a_partial_image() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    // A card at depth 5 with the focus at depth 1 and a lens of radius
    // 0.5: a circle of confusion of about 44 pixels, so each micropolygon's
    // box holds thousands of pixels, each tested at 64 samples.
    let (centre, half) = (Vec3::new(0.0, 0.0, -5.0), 0.5);
    let (mut scene, models) = card_scene(&[(centre, half, Vec3::ZERO)], Sampling::Bbox);
    scene.lens.aperture = 0.5;
    scene.lens.focus_distance = Some(1.0);
    let focal = SIDE as f32 / 2.0 / 30f32.to_radians().tan();
    let coc = scene.lens.aperture * (1.0 / 1.0 - 1.0 / 5.0) * focal;
    let box_tests = (2.0 * coc).powi(2) * scene.spp as f32;
    assert!(
        box_tests > 4.0 * 65_535.0,
        "premise: {box_tests} tests per micropolygon"
    );
    let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    let on_llvmpipe = gpu_test::expect(gpu).loops_capped();
    match renderer.render(&prepared) {
        Err(reyes::gpu::RenderError::LoopLimit(error)) if on_llvmpipe => {
            eprintln!("{error}");
            assert!(error.rasterization + error.waits > 0);
            assert_eq!(
                error.runs,
                reyes::gpu::renderer::RENDER_ATTEMPTS,
                "every attempt of the scheduler's retry"
            );
            // The message names what to change: the sampling, since the
            // micropolygons' sample loops are the long ones.
            let message = error.to_string();
            assert!(
                message.contains("samples per pixel") && message.contains("Interleave"),
                "{message}"
            );
        }
        Err(e) => panic!("expected a loop limit on llvmpipe, or an image elsewhere; got: {e}"),
        Ok(rendered) if !on_llvmpipe => {
            let cpu = reference::render(&prepared);
            agreement(&rendered, &cpu).assert_at_least("Bbox", 0.99, 0.98);
        }
        Ok(_) => panic!("llvmpipe rendered loops longer than its limit: is the limit gone?"),
    }
    scene.sampling = Sampling::Interleave;
    let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    let rendered = render_gpu(&mut renderer, &prepared);
    let cpu = reference::render(&prepared);
    agreement(&rendered, &cpu).assert_at_least("Interleave", 0.99, 0.98);
    assert!(rendered.stats.samples_hit > 0);
}

#[test]
fn a_moving_camera_is_the_world_moving_the_other_way() {
    let seed = tests::seed("a_moving_camera_is_the_world_moving_the_other_way");
    let mut rng = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(seed);
    let mut component = || rand::Rng::random_range(&mut rng, -0.5f32..0.5);
    let by = Vec3::new(component(), component(), component());
    let (centre, half) = (Vec3::new(-0.5, -0.2, -5.0), 0.5);
    let (moving_card, models) = card_scene(&[(centre, half, -by)], Sampling::Interval);
    let (mut moving_camera, _) = card_scene(&[(centre, half, Vec3::ZERO)], Sampling::Interval);
    let camera = moving_camera
        .camera
        .expect("the card scene places its camera");
    moving_camera.camera_close = Some(CameraPose {
        eye: camera.eye + by,
        target: camera.target + by,
        up: None,
    });
    let motion_of = |scene: &Scene| {
        PreparedScene::new(scene, &models)
            .expect("scene prepares")
            .objects[0]
            .motion
            .expect("the card moves relative to the camera")
    };
    let (world, camera) = (motion_of(&moving_card), motion_of(&moving_camera));
    assert!(
        world.matrix.abs_diff_eq(camera.matrix, 1e-5),
        "seed {seed}: by {by}: {} vs {}",
        world.matrix,
        camera.matrix
    );
    // A half shutter sees half the camera's path.
    moving_camera.shutter = 0.5;
    let half_way = motion_of(&moving_camera).close(centre) - centre;
    assert!(
        half_way.abs_diff_eq(-by * 0.5, 1e-5),
        "seed {seed}: {half_way}"
    );
}

#[gpu_test]
fn a_panning_camera_streaks_still_cards_between_its_two_views() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    // A still card at depth 5; the camera turns 8 degrees to the left about
    // its eye (a pan), so the card (22 pixels wide) sweeps right by about
    // 16 pixels.
    let (centre, half) = (Vec3::new(-0.3, 0.2, -5.0), 0.5);
    let turn = glam::Quat::from_rotation_y(8f32.to_radians());
    let pose = CameraPose {
        eye: Vec3::ZERO,
        target: turn * Vec3::new(0.0, 0.0, -1.0),
        up: None,
    };
    for sampling in [Sampling::Bbox, Sampling::Interleave, Sampling::Adaptive] {
        let (mut scene, models) = card_scene(&[(centre, half, Vec3::ZERO)], sampling);
        scene.camera_close = Some(pose);
        let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
        // The camera at close, built directly (not through the camera motion).
        let open = prepared.camera;
        let close_camera = open.looking(pose.eye, pose.target, pose.up.unwrap_or(open.up));
        let pixels: Vec<Vec3> = [-half, half]
            .into_iter()
            .flat_map(|dx| [-half, half].map(|dy| centre + Vec3::new(dx, dy, 0.0)))
            .flat_map(|p| [&prepared.camera, &close_camera].map(|c| c.to_pixel(c.to_clip(p))))
            .collect();
        let expected = pixel_box(&pixels);
        let (left, right, ..) = expected;
        assert!(
            right - left > 32.0,
            "the pan moves the card: {left}..{right}"
        );
        let gpu = render_gpu(&mut renderer, &prepared);
        let cpu = reference::render(&prepared);
        let a = agreement(&gpu, &cpu);
        eprintln!("{sampling:?}: {a:?}");
        a.assert_at_least(&format!("{sampling:?}"), 0.99, 0.98);
        for (who, coverage) in [("GPU", &gpu.coverage), ("CPU", &cpu.coverage)] {
            assert_streak(&format!("{sampling:?} {who}"), coverage, expected);
        }
    }
}

#[test]
fn invalid_motion_and_lens_settings_are_typed_errors() {
    let teapot = |edit: &dyn Fn(&mut Scene)| {
        let mut scene = Scene::default_teapot();
        edit(&mut scene);
        scene.validate()
    };
    let field_of = |result: Result<(), SceneError>| match result {
        Err(SceneError::InvalidValue { field, .. } | SceneError::NonFinite { field }) => field,
        other => panic!("expected an invalid value, got {other:?}"),
    };
    assert_eq!(field_of(teapot(&|s| s.shutter = 1.5)), "shutter");
    assert_eq!(field_of(teapot(&|s| s.shutter = f32::NAN)), "shutter");
    assert_eq!(
        field_of(teapot(&|s| s.lens.aperture = -0.1)),
        "lens.aperture"
    );
    assert_eq!(
        field_of(teapot(&|s| s.lens.focus_distance = Some(0.0))),
        "lens.focus_distance"
    );
    assert_eq!(
        field_of(teapot(&|s| {
            s.sampling = Sampling::Nearest;
            s.lens.aperture = 0.1;
        })),
        "sampling"
    );
    assert_eq!(
        field_of(teapot(&|s| {
            s.objects[0].transform_close = Some(Transform {
                scale: reyes::scene::Scale::Uniform(0.0),
                ..Transform::default()
            });
        })),
        "objects[0].transform_close"
    );
    assert_eq!(
        field_of(teapot(&|s| {
            s.objects[0].transform_close = Some(Transform {
                translate: Vec3::new(f32::INFINITY, 0.0, 0.0),
                ..Transform::default()
            });
        })),
        "objects[0].transform_close.translate"
    );
    let camera_moves = |pose: CameraPose| {
        move |s: &mut Scene| {
            s.camera_close = Some(pose);
        }
    };
    let camera = Scene::default_teapot()
        .camera
        .expect("the teapot scene has a camera");
    let shifted = CameraPose {
        eye: camera.eye + Vec3::X,
        target: camera.target + Vec3::X,
        up: None,
    };
    teapot(&camera_moves(shifted)).expect("a camera moved sideways is valid");
    assert_eq!(
        field_of(teapot(&|s| {
            s.camera = None;
            s.camera_close = Some(shifted);
        })),
        "camera_close"
    );
    assert_eq!(
        field_of(teapot(&camera_moves(CameraPose {
            eye: Vec3::new(f32::NAN, 0.0, 0.0),
            ..shifted
        }))),
        "camera_close.eye"
    );
    assert_eq!(
        field_of(teapot(&camera_moves(CameraPose {
            target: shifted.eye,
            ..shifted
        }))),
        "camera_close"
    );
    assert_eq!(
        field_of(teapot(&camera_moves(CameraPose {
            up: Some(shifted.target - shifted.eye),
            ..shifted
        }))),
        "camera_close"
    );
    assert_eq!(
        field_of(teapot(&|s| {
            s.sampling = Sampling::Nearest;
            s.camera_close = Some(shifted);
        })),
        "sampling"
    );
    // The TOML spelling parses and round-trips.
    let scene = Scene::from_toml_str(
        r#"
        sampling = "interleave"
        shutter = 0.5
        [lens]
        aperture = 0.2
        focus_distance = 8.0
        [camera]
        eye = [4.0, -12.0, 7.0]
        target = [0.2, 0.0, 1.5]
        [camera_close]
        eye = [4.5, -12.0, 7.0]
        target = [0.7, 0.0, 1.5]
        [[objects]]
        model = "teapot"
        [objects.transform_close]
        rotate_degrees = [0.0, 0.0, 30.0]
        "#,
    )
    .expect("scene parses");
    assert_eq!(scene.sampling, Sampling::Interleave);
    assert_eq!(
        scene.camera_close,
        Some(CameraPose {
            eye: Vec3::new(4.5, -12.0, 7.0),
            target: Vec3::new(0.7, 0.0, 1.5),
            up: None
        })
    );
    assert_eq!(
        Scene::from_toml_str(&scene.to_toml_string()).unwrap(),
        scene
    );
}
