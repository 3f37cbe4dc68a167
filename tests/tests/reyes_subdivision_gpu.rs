//! Catmull-Clark subdivision surfaces on the GPU against the CPU
//! reference: the creased cubes of `docs/scenes/subdivision-creases.rib`
//! (four `SubdivisionMesh` cubes, creases of sharpness 0, 1, 2 and 10).
//! The patches themselves are checked against an independent refinement
//! in `reyes/tests/subdivision.rs`; here the renderers must agree on them.

use gpu_test::gpu_test;
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::rib::RibScene;
use tests::reyes_support::{agreement, gpu_turn, patient_renderer};

#[gpu_test]
fn creased_subdivision_cubes_match_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../docs/scenes/subdivision-creases.rib");
    let rib = RibScene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(rib.warnings.is_empty(), "{:?}", rib.warnings);
    let scene = PreparedScene::new(&rib.scene, &rib.models).expect("scene prepares");
    assert!(
        scene.patches.len() > 4 * 6,
        "{} patches",
        scene.patches.len()
    );
    let cpu = reference::render(&scene);
    let mut renderer = patient_renderer(gpu);
    let frame = renderer.render(&scene).expect("GPU render");
    let a = agreement(&frame, &cpu);
    println!(
        "{} patches: {:.4} of {} pixels within 2/255 of the reference (max diff {}, IoU {:.5})",
        scene.patches.len(),
        a.within_2,
        a.both,
        a.max_diff,
        a.iou
    );
    a.assert_at_least("creased cubes", 0.995, 0.99);
}

/// The cube as an OBJ file: 8 corners, 6 quads facing outwards.
const CUBE_OBJ: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n\
                        v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
                        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

/// A Catmull-Clark cube read from an OBJ file, displaced (`sines`, along
/// the limit surface's normals), in `metal` and turning during the shutter,
/// renders on the GPU as in the CPU reference; the displacement and the
/// motion each change the picture, so both are in play.
#[gpu_test]
fn a_displaced_moving_subdivision_surface_matches_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let dir = std::env::temp_dir().join(format!("reyes-subdivision-gpu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("cube.obj"), CUBE_OBJ).unwrap();
    let scene_text = |displaced: bool, moving: bool| {
        let mut text = String::from(
            "spp = 16\nsampling = \"interleave\"\n\
             [resolution]\nwidth = 200\nheight = 150\n\
             [camera]\neye = [2.6, 2.2, 3.4]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\nfov_y_degrees = 40.0\n\
             [[lights]]\ndirection = [-1.0, -2.0, -1.5]\n\
             [[objects]]\nmodel = \"cube.obj\"\ncolor = [0.9, 0.7, 0.4]\n\
             surface = { shader = \"metal\", roughness = 0.2 }\n\
             transform = { rotate_degrees = [0.0, 10.0, 0.0] }\n",
        );
        if moving {
            text += "transform_close = { rotate_degrees = [0.0, 30.0, 0.0] }\n";
        }
        if displaced {
            text += "displacement = { source = \"sines\", scale = 0.08 }\n";
        }
        let path = dir.join(format!("cube-{displaced}-{moving}.toml"));
        std::fs::write(&path, text).unwrap();
        let scene = reyes::scene::Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        PreparedScene::load(&scene).unwrap_or_else(|e| panic!("{e}"))
    };
    let scene = scene_text(true, true);
    assert!(scene.patches.len() > 6, "{} patches", scene.patches.len());
    let cpu = reference::render(&scene);
    let mut renderer = patient_renderer(gpu);
    let frame = renderer.render(&scene).expect("GPU render");
    let a = agreement(&frame, &cpu);
    println!(
        "displaced, moving subdivision cube: {:.4} of {} pixels within 2/255 (max diff {}, IoU {:.5})",
        a.within_2, a.both, a.max_diff, a.iou
    );
    a.assert_at_least("displaced, moving subdivision cube", 0.99, 0.98);
    // Each of the two changes the reference's picture.
    let differing = |other: &reyes::reference::Rendered| {
        cpu.image
            .pixels()
            .zip(other.image.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 8))
            .count()
    };
    let still = reference::render(&scene_text(true, false));
    let smooth = reference::render(&scene_text(false, true));
    let (by_motion, by_displacement) = (differing(&still), differing(&smooth));
    println!("pixels changed by the motion: {by_motion}, by the displacement: {by_displacement}");
    assert!(by_motion > 500 && by_displacement > 500);
}
