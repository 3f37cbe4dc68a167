//! Issue 19, D17 and D10: input patches beyond one run's queue are rendered
//! in batches that compose into the unbatched frame, and the loop-limit
//! error gives advice that follows from the frame's configuration.

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::gpu::renderer::RENDER_ATTEMPTS;
use reyes::gpu::{GpuOptions, GpuRendered, LoopLimitHint, RenderError};
use reyes::model::{Model, Patch};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Dicing, Sampling, Scene, SceneObject, Transform};
use reyes::stats::RenderStats;
use scheduler::wgpu;
use tests::reyes_support::{agreement, camera_down_z, gpu_turn, renderer};
use tests::shapes::bezier_sphere;

/// Three overlapping spheres (72 patches) at different depths, the far one
/// first so that later batches hold the nearer patches and the depth test
/// has to compose runs both ways (the middle sphere is nearer than the
/// first and farther than the last).
fn spheres(width: u32, height: u32) -> (Scene, Vec<Model>) {
    let mut scene = Scene::default();
    scene.resolution.width = width;
    scene.resolution.height = height;
    scene.spp = 1;
    // Each pixel the mean of its own samples: the tiles render no margin,
    // so the caps below are the tiles' own sizes.
    scene.pixel_filter = reyes::filter::PixelFilter::PIXEL_BOX;
    scene.camera = Some(camera_down_z());
    let mut models = Vec::new();
    for (centre, color) in [
        (Vec3::new(-0.4, 0.1, -6.0), Vec3::new(0.9, 0.3, 0.2)),
        (Vec3::new(0.5, -0.2, -4.5), Vec3::new(0.8, 0.8, 0.8)),
        (Vec3::new(0.0, 0.0, -5.0), Vec3::new(0.2, 0.5, 0.9)),
    ] {
        scene.objects.push(SceneObject {
            model: "sphere".into(),
            subdivision: None,
            transform: Transform {
                translate: centre,
                ..Transform::default()
            },
            color,
            surface: None,
            shading_rate: None,
            displacement: None,
            transform_close: None,
            keys: Vec::new(),
            sides: 2,
            reverse_orientation: false,
        });
        models.push(bezier_sphere());
    }
    (scene, models)
}

/// The counters without the frame time, which differs between runs.
fn counts(frame: &GpuRendered) -> RenderStats {
    RenderStats {
        frame_time_ms: None,
        ..frame.stats.clone()
    }
}

/// Renders `prepared` unbatched and in batches of `batch` patches (with
/// the same tiling) and checks the batched frame is the unbatched one.
fn assert_batches_compose(
    gpu: &scheduler::Gpu,
    prepared: &PreparedScene,
    batch: u32,
    max_tile_samples: Option<u64>,
) -> (GpuRendered, GpuRendered) {
    let options = GpuOptions {
        max_tile_samples,
        ..GpuOptions::default()
    };
    let whole = renderer(gpu, options.clone())
        .render(prepared)
        .expect("unbatched render");
    let batched = renderer(
        gpu,
        GpuOptions {
            max_batch_patches: Some(batch),
            ..options
        },
    )
    .render(prepared)
    .expect("batched render");
    let per_tile = prepared.patches.len().div_ceil(batch as usize) as u32;
    assert_eq!(whole.batches, whole.tiles, "one run per tile unbatched");
    assert_eq!(batched.tiles, whole.tiles);
    assert_eq!(batched.batches, per_tile * batched.tiles);
    assert!(batched.batches > batched.tiles, "the test needs batches");
    assert_eq!(counts(&batched), counts(&whole), "counters add up");
    assert_eq!(batched.stats.input_patches, prepared.patches.len() as u64);
    assert_eq!(batched.coverage, whole.coverage);
    assert_eq!(batched.covered_samples, whole.covered_samples);
    assert!(
        batched.image.as_raw() == whole.image.as_raw(),
        "batched and unbatched images differ"
    );
    (whole, batched)
}

#[gpu_test]
fn patches_beyond_the_batch_limit_render_the_unbatched_frame() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let (scene, models) = spheres(64, 48);
    let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    assert_eq!(prepared.patches.len(), 72);
    // 72 patches in batches of 10 (a Bound queue of 16): 8 runs.
    let (whole, batched) = assert_batches_compose(gpu, &prepared, 10, None);
    eprintln!(
        "{} batches: {} grids, {} micropolygons, {} samples hit",
        batched.batches,
        batched.stats.grids_diced,
        batched.stats.micropolygons,
        batched.stats.samples_hit
    );
    assert!(whole.stats.micropolygons > 0 && whole.stats.samples_hit > 0);
    // One patch per run works too.
    let single = renderer(
        gpu,
        GpuOptions {
            max_batch_patches: Some(1),
            ..GpuOptions::default()
        },
    )
    .render(&prepared)
    .expect("one patch per batch");
    assert_eq!(single.batches, 72);
    assert_eq!(counts(&single), counts(&whole));
    assert!(single.image.as_raw() == whole.image.as_raw());
    // The CPU reference is an independent check of the composed frame.
    let cpu = reference::render(&prepared);
    agreement(&batched, &cpu).assert_at_least("batched", 0.99, 0.98);
}

#[gpu_test]
fn batches_compose_within_screen_tiles() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let (scene, models) = spheres(128, 96);
    let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    // 64 x 64 samples per tile: 2 x 2 tiles of the 128 x 96 frame.
    let (whole, batched) = assert_batches_compose(gpu, &prepared, 25, Some(64 * 64));
    assert!(whole.tiles > 1, "the test needs tiles");
    assert_eq!(batched.batches, 3 * batched.tiles);
    let cpu = reference::render(&prepared);
    agreement(&batched, &cpu).assert_at_least("tiled batches", 0.99, 0.98);
}

/// A batched frame whose work queues are far too small: the scheduler's
/// retry grows them after the first batch overflows, the statistics are
/// restored before each retry and the framebuffer's depth test makes a
/// repeated batch harmless, so the frame and its counters are those of an
/// unforced render. The grown queues stay for the later batches.
#[gpu_test]
fn an_overflow_retried_within_batches_loses_and_doubles_nothing() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let (scene, models) = spheres(64, 48);
    let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    let options = GpuOptions {
        max_batch_patches: Some(10),
        ..GpuOptions::default()
    };
    let unforced = renderer(gpu, options.clone())
        .render(&prepared)
        .expect("unforced render");
    let forced = renderer(
        gpu,
        GpuOptions {
            work_capacity: 8,
            ..options
        },
    )
    .render(&prepared)
    .expect("render with overflows");
    eprintln!(
        "{} batches, {} overflow and {} loop retries",
        forced.batches, forced.overflow_retries, forced.loop_retries
    );
    assert_eq!(unforced.overflow_retries, 0);
    assert!(forced.overflow_retries > 0, "the test needs an overflow");
    assert!(
        forced.overflow_retries < forced.batches,
        "grown queues are kept for later batches"
    );
    assert_eq!(forced.batches, unforced.batches);
    assert_eq!(
        counts(&forced),
        counts(&unforced),
        "counters neither lost nor doubled"
    );
    assert_eq!(forced.coverage, unforced.coverage);
    assert_eq!(forced.covered_samples, unforced.covered_samples);
    assert!(
        forced.image.as_raw() == unforced.image.as_raw(),
        "forced and unforced images differ"
    );
}

/// A card at depth 5 with the focus at depth 1 and a lens of radius 1: a
/// circle of confusion of about 33 pixels at 64 x 48, so each micropolygon's
/// bounding box holds thousands of pixels, each tested at 64 samples: more
/// loop iterations than llvmpipe allows one invocation.
fn defocused_card(dicing: Dicing, dice_threshold: f32) -> PreparedScene {
    let mut scene = Scene::default();
    scene.resolution.width = 64;
    scene.resolution.height = 48;
    scene.spp = 64;
    scene.sampling = Sampling::Bbox;
    scene.dicing = dicing;
    scene.dice_threshold = dice_threshold;
    scene.camera = Some(camera_down_z());
    scene.lens.aperture = 1.0;
    scene.lens.focus_distance = Some(1.0);
    scene.objects.push(SceneObject {
        color: Vec3::ONE,
        ..SceneObject::new("card")
    });
    let (centre, half) = (Vec3::new(0.0, 0.0, -5.0), 0.5);
    let points = std::array::from_fn(|k| {
        let (u, v) = ((k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0);
        centre + Vec3::new(-half + 2.0 * half * u, half - 2.0 * half * v, 0.0)
    });
    let model = Model::new(vec![Patch { points }]);
    PreparedScene::new(&scene, &[model]).expect("scene prepares")
}

/// Renders `prepared`; on llvmpipe expects the loop-limit error and returns
/// it, elsewhere expects an image and returns `None`.
fn loop_limit(
    gpu: &scheduler::Gpu,
    prepared: &PreparedScene,
) -> Option<reyes::gpu::LoopLimitError> {
    let on_llvmpipe = gpu_test::expect(gpu).loops_capped();
    match renderer(gpu, GpuOptions::default()).render(prepared) {
        Err(RenderError::LoopLimit(error)) if on_llvmpipe => {
            eprintln!("{error}");
            assert!(error.rasterization + error.waits > 0);
            assert_eq!(
                error.runs, RENDER_ATTEMPTS,
                "every attempt of the scheduler's retry"
            );
            assert!(error.workgroups > 0);
            assert_eq!(
                error.iteration_budget,
                Some(1),
                "the budget halved by the retries"
            );
            assert_eq!(error.batch, (1, 1));
            assert!(!error.context.user_displacement);
            let message = error.to_string();
            let attempts = format!("{RENDER_ATTEMPTS} attempt(s)");
            for fact in ["workgroups", "iteration budget", attempts.as_str()] {
                assert!(message.contains(fact), "{fact:?} missing: {message}");
            }
            assert!(!message.contains("displacement function"), "{message}");
            Some(*error)
        }
        Err(e) => panic!("expected the loop-limit error on llvmpipe, or an image elsewhere: {e}"),
        Ok(_) if on_llvmpipe => panic!("llvmpipe rendered loops longer than its limit"),
        Ok(_) => None,
    }
}

#[gpu_test]
fn long_sample_loops_advise_fewer_samples() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let prepared = defocused_card(Dicing::Rate, 16.0);
    let Some(error) = loop_limit(gpu, &prepared) else {
        return;
    };
    assert!(error.context.blurred && error.context.spp == 64);
    assert!(
        matches!(error.hints[..], [LoopLimitHint::LongRasterization { .. }]),
        "{:?}",
        error.hints
    );
    let message = error.to_string();
    assert!(message.contains("samples per pixel") && message.contains("Interleave"));
    assert!(!message.contains("LARGER"), "{message}");
}

#[gpu_test]
fn a_small_dice_threshold_is_not_told_to_shrink() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let prepared = defocused_card(Dicing::Fixed, 0.5);
    let Some(error) = loop_limit(gpu, &prepared) else {
        return;
    };
    assert_eq!(
        error.hints[0],
        LoopLimitHint::LargerDiceThreshold {
            threshold: 0.5,
            default: reyes::params::DEFAULT_DICE_THRESHOLD
        }
    );
    let message = error.to_string();
    assert!(message.contains("LARGER dice threshold"), "{message}");
    assert!(!message.contains("smaller dice threshold"), "{message}");
}

/// Issue 19, D6: a chunk count whose megakernel llvmpipe would compile for
/// minutes (2 chunks: 96 s on a cold shader cache; 8: 324 s) is refused before any
/// compile, with the most it accepts; other drivers take any count.
#[gpu_test(expect_fail(
    adapter = "llvmpipe",
    message = "TooManyChunks { chunks: 8, max: 4 }",
    reason = "llvmpipe refuses more than 4 chunks per batch: it would compile that megakernel for minutes"
))]
fn chunk_counts_llvmpipe_compiles_too_slowly_are_refused(gpu: &scheduler::Gpu) {
    let options = GpuOptions {
        chunks_per_batch: Some(8),
        ..GpuOptions::default()
    };
    reyes::gpu::GpuRenderer::new(gpu, options).expect("the renderer takes 8 chunks per batch");
}

/// Issue D27: a frame 1,000,000 pixels wide and 1 high has 125,000 resolve
/// tiles in its row, more workgroups than one dispatch dimension allows
/// (65,535); the resolve spreads them over two dimensions. A sphere of 100
/// pixels around column 900,000 (an orthographic view one unit per pixel)
/// must show there, beyond the 524,280 columns one dimension reaches, as
/// the CPU reference draws it.
#[gpu_test]
fn a_frame_wider_than_one_dispatch_dimension_resolves_every_column() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let width = 1_000_000;
    let mut scene = Scene::default();
    scene.resolution.width = width;
    scene.resolution.height = 1;
    scene.spp = 1;
    scene.pixel_filter = reyes::filter::PixelFilter::PIXEL_BOX;
    scene.camera = Some(reyes::scene::CameraDesc {
        far: 1000.0,
        projection: reyes::scene::Projection::Orthographic,
        ortho_height: Some(1.0),
        ..camera_down_z()
    });
    scene.objects.push(SceneObject {
        model: "sphere".into(),
        subdivision: None,
        transform: Transform {
            translate: Vec3::new(400_000.0, 0.0, -200.0),
            scale: reyes::scene::Scale::Uniform(50.0),
            ..Transform::default()
        },
        color: Vec3::new(0.9, 0.3, 0.2),
        surface: None,
        shading_rate: None,
        displacement: None,
        transform_close: None,
        keys: Vec::new(),
        sides: 2,
        reverse_orientation: false,
    });
    let prepared = PreparedScene::new(&scene, &[bezier_sphere()]).expect("scene prepares");
    let frame = renderer(gpu, GpuOptions::default())
        .render(&prepared)
        .expect("the wide frame renders");
    assert_eq!(frame.coverage.len(), width as usize);
    let covered: Vec<usize> = (0..frame.coverage.len())
        .filter(|&x| frame.coverage[x])
        .collect();
    let (first, last) = (covered[0], covered[covered.len() - 1]);
    eprintln!("{} columns covered, {first}..={last}", covered.len());
    assert!(
        (899_940..=899_960).contains(&first) && (900_040..=900_060).contains(&last),
        "the sphere covers columns {first}..={last}, not about 899,950..900,050"
    );
    let cpu = reference::render(&prepared);
    agreement(&frame, &cpu).assert_at_least("wide", 0.95, 0.95);
}

/// A validation error no error scope catches (here a dispatch over the
/// device's limit per dimension, encoded without a scope) is recorded on the
/// device's [`scheduler::UncapturedErrors`] and logged, not handed to wgpu's
/// default handler, which panics.
#[gpu_test]
fn an_uncaptured_validation_error_is_recorded_not_a_panic() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("empty"),
        source: wgpu::ShaderSource::Wgsl("@compute @workgroup_size(1) fn main() {}".into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("empty"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let over = device.limits().max_compute_workgroups_per_dimension + 1;
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.dispatch_workgroups(over, 1, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    let error = gpu.uncaptured.take().expect("the error is recorded");
    assert!(error.contains(&over.to_string()), "{error}");
}
