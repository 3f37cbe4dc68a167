//! The process-wide input caps: their documented defaults, and that
//! [`input::set_limits`] reaches every loader. One test only, because the
//! caps are global to this test process.

mod files;

use files::TempDir;
use reyes::displacement::{DisplacementError, HeightMap};
use reyes::input::{self, GIB, InputError, InputKind, Limits, MIB};
use reyes::load::{LoadError, bpt};
use reyes::model::Model;
use reyes::scene::{Scene, SceneError};

#[test]
fn set_limits_reaches_every_loader() {
    assert_eq!(input::limits(), Limits::DEFAULT);
    assert_eq!(InputKind::Model.limit(), GIB);
    assert_eq!(InputKind::Scene.limit(), 16 * MIB);
    assert_eq!(InputKind::Wgsl.limit(), 16 * MIB);
    assert_eq!(InputKind::HeightMap.limit(), 64 * MIB);

    let dir = TempDir::new("limits");
    let model = dir.path("teapot.bpt");
    std::fs::write(&model, bpt::write(&Model::teapot())).unwrap();
    let scene = dir.path("scene.toml");
    std::fs::write(&scene, "[[objects]]\nmodel = \"teapot.bpt\"\n").unwrap();
    let map = dir.path("bumps.png");
    std::fs::write(&map, include_bytes!("../assets/bumps.png")).unwrap();

    input::set_limits(Limits::all(20));
    let too_large = |e: &InputError| matches!(e, InputError::TooLarge { limit: 20, .. });
    let e = Scene::load(&scene).unwrap_err();
    assert!(matches!(&e, SceneError::Input(e) if too_large(e)), "{e:?}");
    let e = Model::load(&model).unwrap_err();
    assert!(matches!(&e, LoadError::Input(e) if too_large(e)), "{e:?}");
    let e = HeightMap::load(&map).unwrap_err();
    assert!(
        matches!(&e, DisplacementError::Input(e) if too_large(e)),
        "{e:?}"
    );
    let e = input::read_text(&scene, InputKind::Wgsl, InputKind::Wgsl.limit()).unwrap_err();
    assert!(too_large(&e), "{e:?}");

    input::set_limits(Limits::DEFAULT);
    let loaded = Scene::load(&scene).unwrap();
    assert_eq!(loaded.load_models().unwrap()[0], Model::teapot());
    assert!(HeightMap::load(&map).is_ok());
}
