//! The golden RIB scenes of `reyes/tests/data/rib_golden/` (the camera from
//! the transforms, handedness, attribute stacking, `ReadArchive`, object
//! and camera motion blur) rendered on the GPU against the CPU reference.
//! `reyes/tests/rib_golden.rs` checks the same scenes against their
//! hand-written TOML twins on the CPU.
//!
//! The thresholds are those of `reyes_gpu.rs` for still frames and of
//! `reyes_blur.rs` for motion blur (the GPU's float contraction can move an
//! edge test by one step, and a moving edge crosses more samples).

use std::path::PathBuf;

use gpu_test::gpu_test;
use reyes::reference;
use reyes::rib::RibScene;
use tests::reyes_support::{agreement, gpu_turn, patient_renderer};

fn golden(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../reyes/tests/data/rib_golden")
        .join(name)
}

/// Each scene with its IoU and within-2/255 floors.
const SCENES: [(&str, f64, f64); 7] = [
    ("camera", 0.995, 0.99),
    ("handedness", 0.995, 0.99),
    ("attributes", 0.995, 0.99),
    ("archive", 0.995, 0.99),
    ("motion", 0.99, 0.98),
    ("camera_motion", 0.99, 0.98),
    ("materials", 0.995, 0.99),
];

#[gpu_test]
fn golden_rib_scenes_match_the_reference_on_the_gpu() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    // One renderer (one set of options) for every scene: one megakernel
    // compile.
    let mut renderer = patient_renderer(gpu);
    for (name, iou, within_2) in SCENES {
        let rib = RibScene::load(golden(&format!("{name}.rib")))
            .unwrap_or_else(|e| panic!("{name}.rib: {e}"));
        let prepared = rib.prepare().expect("the RIB scene prepares");
        let frame = renderer
            .render(&prepared)
            .unwrap_or_else(|e| panic!("{name}: GPU render: {e}"));
        let cpu = reference::render(&prepared);
        let a = agreement(&frame, &cpu);
        eprintln!("{name}: {a:?}");
        assert!(a.coverage >= 0.05, "{name}: GPU coverage {:.3}", a.coverage);
        a.assert_at_least(name, iou, within_2);
    }
}
