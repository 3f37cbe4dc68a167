//! Back-face culling under motion (Fatahalian et al., the papers' 004): a
//! one-sided micropolygon is culled only when it faces away at both ends
//! of the shutter. A one-sided square that turns from facing away to
//! facing the camera during the shutter is drawn (it was lost when only
//! the shutter-open orientation counted), on the GPU and in the CPU
//! reference alike; one that faces away throughout stays culled.

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::gpu::GpuOptions;
use reyes::model::{Model, Patch};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Scene, SceneObject, Surface, Transform};
use tests::reyes_support::{agreement, camera_down_z, gpu_turn, renderer};

/// A flat unit square in z = 0 whose front (dP/du x dP/dv) is +z.
fn square() -> Model {
    Model {
        patches: vec![Patch {
            points: std::array::from_fn(|k| {
                Vec3::new((k % 4) as f32 / 3.0 - 0.5, (k / 4) as f32 / 3.0 - 0.5, 0.0)
            }),
        }],
        ..Model::default()
    }
}

/// The square 3 units in front of the camera, one-sided, turned by
/// `open` degrees about y at shutter open and `close` at close.
fn scene(open: f32, close: f32) -> PreparedScene {
    let mut scene = Scene::default();
    scene.resolution.width = 64;
    scene.resolution.height = 48;
    scene.spp = 16;
    scene.camera = Some(camera_down_z());
    scene.ambient = 1.0;
    scene.background = Vec3::ZERO;
    let placed = |degrees: f32| Transform {
        translate: Vec3::new(0.0, 0.0, -3.0),
        rotate_degrees: Vec3::new(0.0, degrees, 0.0),
        ..Transform::default()
    };
    scene.objects.push(SceneObject {
        transform: placed(open),
        color: Vec3::ONE,
        surface: Some(Surface::Constant),
        transform_close: Some(placed(close)),
        sides: 1,
        ..SceneObject::new("square")
    });
    PreparedScene::new(&scene, &[square()]).expect("scene prepares")
}

fn covered(image: &image::RgbaImage) -> usize {
    image.pixels().filter(|p| p[0] > 0).count()
}

#[gpu_test]
fn a_face_turning_towards_the_camera_during_the_shutter_is_drawn() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = renderer(gpu, GpuOptions::default());
    // From facing away (150 degrees) to facing the camera (30 degrees).
    let turning = scene(150.0, 30.0);
    let cpu = reference::try_render(&turning).expect("the reference renders");
    let frame = renderer.render(&turning).expect("GPU render");
    let (cpu_covered, gpu_covered) = (covered(&cpu.image), covered(&frame.image));
    eprintln!("turning towards: CPU {cpu_covered} px, GPU {gpu_covered} px");
    assert!(cpu_covered > 100, "the reference draws the turning face");
    assert!(gpu_covered > 100, "the GPU draws the turning face");
    let a = agreement(&frame, &cpu);
    eprintln!("{a:?}");
    a.assert_at_least("a face turning during the shutter", 0.99, 0.99);
    // Facing away at both ends: culled on both.
    let away = scene(150.0, 120.0);
    let cpu = reference::try_render(&away).expect("the reference renders");
    let frame = renderer.render(&away).expect("GPU render");
    assert_eq!(covered(&cpu.image), 0, "the reference culls it");
    assert_eq!(covered(&frame.image), 0, "the GPU culls it");
}
