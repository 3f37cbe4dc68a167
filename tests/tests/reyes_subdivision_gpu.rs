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
