//! Instancing on the GPU: 1,000 teapots that use one model store the
//! teapot's patches once (the buffer sizes are printed), and render as the
//! same scene written out as 1,000 objects, each with its own patches in
//! world space, and as the CPU reference.

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::gpu::buffers::texel_buffer_bytes;
use reyes::gpu::patch_store_bytes;
use reyes::model::{Model, Patch};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{CameraDesc, Scene, SceneObject, Transform};
use tests::reyes_support::{agreement, as_reference, gpu_turn, patient_renderer};

/// Teapots per side of the grid (40 x 25 = 1,000).
const COLUMNS: usize = 40;
const ROWS: usize = 25;

/// 1,000 teapots on a grid, each turned and coloured its own way, every
/// object naming the embedded teapot.
fn thousand_teapots() -> Scene {
    let mut scene = Scene::default_teapot();
    scene.resolution.width = 320;
    scene.resolution.height = 200;
    scene.spp = 4;
    let template = scene.objects[0].clone();
    scene.objects = (0..ROWS * COLUMNS)
        .map(|i| {
            let (column, row) = ((i % COLUMNS) as f32, (i / COLUMNS) as f32);
            SceneObject {
                transform: Transform {
                    translate: Vec3::new(column * 4.0, row * 4.0, 0.0),
                    rotate_degrees: Vec3::new(90.0, 0.0, 37.0 * i as f32),
                    ..Transform::default()
                },
                color: Vec3::new(0.3 + 0.7 * column / 40.0, 0.5, 0.3 + 0.7 * row / 25.0),
                ..template.clone()
            }
        })
        .collect();
    scene.camera = Some(CameraDesc {
        eye: Vec3::new(78.0, 48.0, 100.0),
        target: Vec3::new(78.0, 48.0, 0.0),
        up: Vec3::Y,
        fov_y_degrees: 58.0,
        near: 1.0,
        far: 300.0,
        projection: reyes::scene::Projection::Perspective,
        ortho_height: None,
    });
    scene
}

/// `scene` written out as separate objects: each object's model holds its
/// patches already placed in world space, under the identity transform.
fn written_out(scene: &Scene, models: &[Model]) -> (Scene, Vec<Model>) {
    let mut out = scene.clone();
    let mut placed = Vec::new();
    for (object, model) in out.objects.iter_mut().zip(models) {
        let matrix = object.transform.matrix();
        placed.push(Model {
            patches: model
                .patches
                .iter()
                .map(|p| Patch {
                    points: p.points.map(|q| matrix.transform_point3(q)),
                })
                .collect(),
            st: model.st.clone(),
        });
        object.transform = Transform::default();
    }
    (out, placed)
}

#[gpu_test]
fn a_thousand_instances_store_one_teapot_and_render_as_a_thousand_objects() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let scene = thousand_teapots();
    let models = scene.load_models().unwrap();
    let instanced = PreparedScene::new(&scene, &models).unwrap();
    let (out, placed) = written_out(&scene, &models);
    let separate = PreparedScene::new(&out, &placed).unwrap();
    let one = PreparedScene::load(&Scene::default_teapot()).unwrap();

    let teapot = Model::teapot().patches.len();
    assert_eq!(instanced.patches.len(), separate.patches.len());
    assert_eq!(instanced.store.len as usize, teapot);
    assert_eq!(separate.store.len as usize, 1000 * teapot);
    assert_eq!(patch_store_bytes(&instanced), patch_store_bytes(&one));
    println!(
        "patch store: {} bytes for 1,000 instances, {} for one teapot, {} written out as 1,000 objects; \
         height-texel buffer {} against {} bytes",
        patch_store_bytes(&instanced),
        patch_store_bytes(&one),
        patch_store_bytes(&separate),
        texel_buffer_bytes(&instanced),
        texel_buffer_bytes(&separate),
    );

    let mut renderer = patient_renderer(gpu);
    let shared = renderer.render(&instanced).expect("instanced render");
    let apart = renderer.render(&separate).expect("written-out render");
    // For the record, not a check (benchmarks time things): the frames'
    // GPU times, the instanced one placing its patches in Bound and dice.
    println!(
        "frame time: instanced {:?} ms, written out {:?} ms",
        shared.stats.frame_time_ms, apart.stats.frame_time_ms
    );
    let covered = shared.coverage.iter().filter(|&&c| c).count();
    assert!(covered > 20_000, "the teapots cover {covered} pixels");
    assert_eq!(shared.stats.input_patches, apart.stats.input_patches);
    // The instanced frame places its patches on the GPU, the written-out
    // one on the CPU: the same points up to float contraction.
    let same = agreement(&shared, &as_reference(&apart));
    println!(
        "instanced against written out: IoU {:.5}, {:.5} of {} pixels within 2/255, max diff {}",
        same.iou, same.within_2, same.both, same.max_diff
    );
    same.assert_at_least("instanced against written out", 0.999, 0.995);
    let cpu = reference::render(&instanced);
    let against_cpu = agreement(&shared, &cpu);
    println!(
        "instanced against the CPU reference: IoU {:.5}, {:.5} within 2/255, max diff {}",
        against_cpu.iou, against_cpu.within_2, against_cpu.max_diff
    );
    against_cpu.assert_at_least("instanced against the CPU reference", 0.995, 0.99);
}
