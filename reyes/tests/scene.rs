//! Scene format tests: parsing, defaults, every error variant, framing.

mod common;

use glam::Vec3;
use reyes::camera::Camera;
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::scene::{ModelSource, Sampling, Scale, Scene, SceneError};

const FULL: &str = r#"
spp = 16
sampling = "nearest"
jitter = true
background = [0.1, 0.2, 0.3]
ambient = 0.2
dice_threshold = 8.0
max_split_depth = 20

[resolution]
width = 320
height = 200

[camera]
eye = [0, -10, 4]
target = [0.0, 0.0, 1.0]
up = [0.0, 0.0, 1.0]
fov_y_degrees = 35.0
near = 0.5
far = 50.0

[specular]
strength = 0.5
shininess = 16.0

[[objects]]
model = "teapot"
color = [0.9, 0.1, 0.1]
[objects.transform]
translate = [1.0, 2.0, 3.0]
rotate_degrees = [0.0, 0.0, 90.0]
scale = 2.0

[[objects]]
model = "models/thing.bez"
transform = { scale = [1.0, 2.0, 3.0] }

[[lights]]
direction = [0.0, 0.0, -1.0]
color = [1.0, 0.9, 0.8]
intensity = 2.0

[[lights]]
direction = [1.0, 0.0, 0.0]
"#;

#[test]
fn full_example_parses() {
    let scene = Scene::from_toml_str(FULL).unwrap();
    assert_eq!(scene.spp, 16);
    assert_eq!(scene.sampling, Sampling::Nearest);
    assert!(scene.jitter);
    assert_eq!(
        (scene.resolution.width, scene.resolution.height),
        (320, 200)
    );
    let camera = scene.camera.unwrap();
    assert_eq!(camera.eye, Vec3::new(0.0, -10.0, 4.0));
    assert_eq!(camera.fov_y_degrees, 35.0);
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.objects[0].transform.scale, Scale::Uniform(2.0));
    assert_eq!(
        scene.objects[1].transform.scale,
        Scale::PerAxis(Vec3::new(1.0, 2.0, 3.0))
    );
    assert_eq!(scene.objects[1].color, Vec3::splat(0.8));
    assert_eq!(scene.lights.len(), 2);
    assert_eq!(scene.lights[1].intensity, 1.0);
    assert_eq!(scene.specular.shininess, 16.0);
    // Serialization round trip.
    let again = Scene::from_toml_str(&scene.to_toml_string()).unwrap();
    assert_eq!(again, scene);
}

#[test]
fn the_documented_example_parses() {
    // The example in docs/reyes-scene.md must stay valid.
    let doc = include_str!("../../docs/reyes-scene.md");
    let start = doc.find("```toml\n").expect("a toml block") + "```toml\n".len();
    let end = start + doc[start..].find("```").unwrap();
    let scene = Scene::from_toml_str(&doc[start..end]).unwrap();
    assert!(!scene.objects.is_empty());
}

#[test]
fn defaults() {
    let scene = Scene::from_toml_str("[[objects]]\nmodel = \"teapot\"\n").unwrap();
    assert_eq!(scene.spp, 4);
    assert_eq!(scene.sampling, Sampling::Bbox);
    assert!(!scene.jitter);
    assert_eq!(scene.dice_threshold, 16.0);
    assert_eq!(scene.max_split_depth, 24);
    assert_eq!(
        (scene.resolution.width, scene.resolution.height),
        (800, 600)
    );
    assert!(scene.camera.is_none());
    assert_eq!(scene.lights.len(), 1, "a default light");
    assert_eq!(scene.objects[0].transform.matrix(), glam::Mat4::IDENTITY);
    let empty = Scene::from_toml_str("").unwrap();
    assert_eq!(empty, Scene::default());
    let dark = Scene::from_toml_str("lights = []").unwrap();
    assert!(dark.lights.is_empty());
    let camera = Scene::from_toml_str("[camera]\neye = [1, 2, 3]\ntarget = [0, 0, 0]\n")
        .unwrap()
        .camera
        .unwrap();
    assert_eq!(
        (camera.up, camera.fov_y_degrees, camera.near, camera.far),
        (Vec3::Z, 40.0, 0.1, 1000.0)
    );
}

#[test]
fn transform_order_is_scale_rotate_xyz_translate() {
    let scene = Scene::from_toml_str(
        "[[objects]]\nmodel = \"teapot\"\ntransform = { translate = [10, 0, 0], rotate_degrees = [90, 0, 90], scale = 2 }\n",
    )
    .unwrap();
    let m = scene.objects[0].transform.matrix();
    // (1,0,0) -> scale (2,0,0) -> rot x: (2,0,0) -> rot z 90: (0,2,0) -> +10x.
    assert!((m.transform_point3(Vec3::X) - Vec3::new(10.0, 2.0, 0.0)).length() < 1e-5);
    // (0,1,0) -> (0,2,0) -> rot x 90: (0,0,2) -> rot z: (0,0,2) -> (10,0,2).
    assert!((m.transform_point3(Vec3::Y) - Vec3::new(10.0, 0.0, 2.0)).length() < 1e-5);
}

#[test]
fn parse_errors_carry_the_line() {
    let e = Scene::from_toml_str("spp = 4\nresolution = { width = \"wide\", height = 3 }\n")
        .unwrap_err();
    assert!(
        matches!(&e, SceneError::Parse { line: Some(2), .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains("line 2"), "{e}");
    let e = Scene::from_toml_str("spp = 4\n\nunknown_field = 1\n").unwrap_err();
    assert!(
        matches!(&e, SceneError::Parse { line: Some(3), message, .. } if message.contains("unknown_field")),
        "{e:?}"
    );
    let e = Scene::from_toml_str("sampling = \"random\"").unwrap_err();
    assert!(matches!(e, SceneError::Parse { .. }), "{e:?}");
    let e = Scene::from_toml_str("[[objects]]\ncolor = [1, 0, 0]\n").unwrap_err();
    assert!(
        matches!(&e, SceneError::Parse { message, .. } if message.contains("model")),
        "{e:?}"
    );
    let e = Scene::from_toml_str("this is not toml").unwrap_err();
    assert!(
        matches!(e, SceneError::Parse { line: Some(1), .. }),
        "{e:?}"
    );
}

#[test]
fn validation_errors() {
    let err = |text: &str| Scene::from_toml_str(text).unwrap_err();
    assert!(matches!(
        err("[resolution]\nwidth = 0\nheight = 10"),
        SceneError::InvalidResolution {
            width: 0,
            height: 10
        }
    ));
    assert!(matches!(
        err("[resolution]\nwidth = 10\nheight = 0"),
        SceneError::InvalidResolution { .. }
    ));
    for spp in [0, 2, 3, 8, 200, 289] {
        assert!(
            matches!(err(&format!("spp = {spp}")), SceneError::InvalidSpp { spp: s } if s == spp)
        );
    }
    // Squares up to 16 x 16.
    for spp in [81, 100, 225, 256] {
        let scene = Scene::from_toml_str(&format!("spp = {spp}")).expect("a valid spp");
        assert_eq!(scene.spp, spp);
    }
    assert!(matches!(err("ambient = nan"), SceneError::NonFinite { field } if field == "ambient"));
    assert!(
        matches!(err("background = [0, inf, 0]"), SceneError::NonFinite { field } if field == "background")
    );
    assert!(matches!(
        err("[[objects]]\nmodel = \"teapot\"\ntransform = { translate = [0, nan, 0] }"),
        SceneError::NonFinite { field } if field == "objects[0].transform.translate"
    ));
    assert!(matches!(
        err("[[lights]]\nintensity = inf"),
        SceneError::NonFinite { field } if field == "lights[0].intensity"
    ));
    let camera = |extra: &str| format!("[camera]\neye = [0, -10, 0]\ntarget = [0, 0, 0]\n{extra}");
    assert!(
        matches!(err(&camera("near = 0.0")), SceneError::InvalidCamera { reason } if reason.contains("near"))
    );
    assert!(matches!(
        err(&camera("near = -1.0")),
        SceneError::InvalidCamera { .. }
    ));
    assert!(
        matches!(err(&camera("near = 5.0\nfar = 5.0")), SceneError::InvalidCamera { reason } if reason.contains("far"))
    );
    assert!(
        matches!(err(&camera("fov_y_degrees = 0.0")), SceneError::InvalidCamera { reason } if reason.contains("fov"))
    );
    assert!(matches!(
        err(&camera("fov_y_degrees = 180.0")),
        SceneError::InvalidCamera { .. }
    ));
    assert!(
        matches!(err(&camera("up = [0, 1, 0]")), SceneError::InvalidCamera { reason } if reason.contains("up"))
    );
    assert!(
        matches!(err(&camera("far = nan")), SceneError::NonFinite { field } if field == "camera.far")
    );
    assert!(matches!(
        err("[camera]\neye = [1, 1, 1]\ntarget = [1, 1, 1]"),
        SceneError::InvalidCamera { reason } if reason.contains("differ")
    ));
    assert!(
        matches!(err("dice_threshold = 0.0"), SceneError::InvalidValue { field, .. } if field == "dice_threshold")
    );
    assert!(
        matches!(err("max_split_depth = 65"), SceneError::InvalidValue { field, .. } if field == "max_split_depth")
    );
    assert!(matches!(
        err("[specular]\nshininess = -1.0"),
        SceneError::InvalidValue { .. }
    ));
    assert!(matches!(
        err("[[lights]]\ndirection = [0, 0, 0]"),
        SceneError::InvalidValue { field, .. } if field == "lights[0].direction"
    ));
}

#[test]
fn file_errors_and_model_paths() {
    let e = Scene::load("/definitely/not/a/scene.toml").unwrap_err();
    assert!(
        matches!(&e, SceneError::Io { path, .. } if path.ends_with("scene.toml")),
        "{e:?}"
    );

    let dir = std::env::temp_dir().join(format!("reyes-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("models")).unwrap();
    std::fs::write(
        dir.join("models/pot.bpt"),
        reyes::load::bpt::write(&Model::teapot()),
    )
    .unwrap();
    std::fs::write(dir.join("bad.toml"), "spp = 4\nspp = 9\n").unwrap();
    let e = Scene::load(dir.join("bad.toml")).unwrap_err();
    assert!(
        matches!(&e, SceneError::Parse { path: Some(p), line: Some(2), .. } if p.ends_with("bad.toml")),
        "{e:?}"
    );
    assert!(e.to_string().contains("bad.toml"), "{e}");

    std::fs::write(
        dir.join("scene.toml"),
        "[[objects]]\nmodel = \"models/pot.bpt\"\n[[objects]]\nmodel = \"teapot\"\n[[objects]]\nmodel = \"/abs/x.bez\"\n",
    )
    .unwrap();
    let scene = Scene::load(dir.join("scene.toml")).unwrap();
    assert_eq!(
        scene.model_source(&scene.objects[0]),
        ModelSource::File(dir.join("models/pot.bpt"))
    );
    assert_eq!(scene.model_source(&scene.objects[1]), ModelSource::Teapot);
    assert_eq!(
        scene.model_source(&scene.objects[2]),
        ModelSource::File("/abs/x.bez".into())
    );
    let e = scene.load_models().unwrap_err();
    assert!(
        matches!(&e, SceneError::Model { index: 2, model, source: reyes::load::LoadError::Io { .. } } if model == "/abs/x.bez"),
        "{e:?}"
    );

    let mut two = scene.clone();
    two.objects.truncate(2);
    let models = two.load_models().unwrap();
    assert_eq!(models[0], models[1]);
    let e = PreparedScene::new(&two, &models[..1]).unwrap_err();
    assert!(
        matches!(
            e,
            SceneError::ModelCountMismatch {
                objects: 2,
                models: 1
            }
        ),
        "{e:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every control point of the model projects inside the image, with depth in (0, 1).
fn assert_framed(scene: &Scene, model: &Model) {
    let prepared = PreparedScene::new(scene, std::slice::from_ref(model)).unwrap();
    let cam: &Camera = &prepared.camera;
    let (w, h) = (cam.width as f32, cam.height as f32);
    let (lo, hi) = model.bounds();
    for &corner in model.patches.iter().flat_map(|p| p.points.iter()) {
        let p = cam.to_pixel(cam.to_clip(corner));
        assert!(
            p.x >= 0.0 && p.x <= w && p.y >= 0.0 && p.y <= h,
            "{corner} -> {p}"
        );
        assert!(p.z > 0.0 && p.z < 1.0, "{corner} depth {}", p.z);
    }
    // Front-above: the eye is above the model's centre.
    assert!(cam.eye.z > (lo.z + hi.z) * 0.5);
    assert_eq!(cam.up, Vec3::Z);
}

#[test]
fn default_teapot_and_for_model_frame_the_model() {
    let scene = Scene::default_teapot();
    scene.validate().unwrap();
    assert_eq!(scene.objects[0].model, "teapot");
    assert_framed(&scene, &Model::teapot());

    // A scene with no camera is framed automatically when prepared.
    let mut auto = scene.clone();
    auto.camera = None;
    assert_framed(&auto, &Model::teapot());

    if let Some(path) = common::killeroo_path() {
        let model = Model::load(&path).unwrap();
        let scene = Scene::for_model(path.to_string_lossy(), &model);
        assert_framed(&scene, &model);
    }
    // A tall, thin model is framed too.
    let mut tall = Model::teapot();
    for p in tall.patches.iter_mut().flat_map(|p| p.points.iter_mut()) {
        *p *= Vec3::new(0.1, 0.3, 5.0);
    }
    assert_framed(&Scene::for_model("tall.bpt", &tall), &tall);
}

/// The dicing, AOV and one-sided keys parse, default as documented, and
/// out-of-range values are errors that name the field.
#[test]
fn dicing_aov_and_sides_keys() {
    use reyes::aov::Aov;
    use reyes::scene::{Dicing, ShadingInterpolation};
    let defaults = Scene::from_toml_str("[[objects]]\nmodel = \"teapot\"").unwrap();
    assert_eq!(defaults.dicing, Dicing::Rate);
    assert_eq!(defaults.shading_rate, 1.0);
    assert_eq!(defaults.aov, Aov::Shaded);
    assert_eq!(defaults.shading_interpolation, ShadingInterpolation::Smooth);
    assert_eq!(defaults.objects[0].sides, 2);
    assert!(!defaults.objects[0].reverse_orientation);
    let scene = Scene::from_toml_str(
        "dicing = \"fixed\"\nshading_rate = 4.0\naov = \"grids\"\nshading_interpolation = \"constant\"\n[[objects]]\nmodel = \"teapot\"\nsides = 1\nreverse_orientation = true",
    )
    .unwrap();
    assert_eq!(scene.dicing, Dicing::Fixed);
    assert_eq!(scene.shading_rate, 4.0);
    assert_eq!(scene.aov, Aov::Grids);
    assert_eq!(scene.shading_interpolation, ShadingInterpolation::Constant);
    assert_eq!(scene.objects[0].sides, 1);
    assert!(scene.objects[0].reverse_orientation);
    let err = |text: &str| Scene::from_toml_str(text).unwrap_err();
    for rate in ["0.0", "-1.0", "1025.0"] {
        assert!(
            matches!(err(&format!("shading_rate = {rate}")), SceneError::InvalidValue { field, .. } if field == "shading_rate"),
            "shading_rate = {rate}"
        );
    }
    assert!(
        matches!(err("shading_rate = nan"), SceneError::NonFinite { field } if field == "shading_rate")
    );
    assert!(matches!(
        err("[[objects]]\nmodel = \"teapot\"\nsides = 3"),
        SceneError::InvalidValue { field, .. } if field == "objects[0].sides"
    ));
    assert!(matches!(
        err("dicing = \"adaptive\""),
        SceneError::Parse { .. }
    ));
    assert!(matches!(err("aov = \"colour\""), SceneError::Parse { .. }));
    assert!(matches!(
        err("shading_interpolation = \"phong\""),
        SceneError::Parse { .. }
    ));
}

#[test]
fn point_lights_have_a_position_instead_of_a_direction() {
    let scene = Scene::from_toml_str(
        "[[lights]]\nposition = [1, 2, 3]\nintensity = 20\n\n[[lights]]\ndirection = [0, 0, -1]\n",
    )
    .unwrap();
    assert_eq!(scene.lights[0].position, Some(Vec3::new(1.0, 2.0, 3.0)));
    assert_eq!(scene.lights[0].intensity, 20.0);
    assert_eq!(scene.lights[1].position, None);
    assert_eq!(scene.lights[1].direction, Vec3::new(0.0, 0.0, -1.0));
    // Written back, each light keeps its kind.
    let text = scene.to_toml_string();
    let again = Scene::from_toml_str(&text).unwrap();
    assert_eq!(again.lights, scene.lights, "{text}");
    assert!(!text.contains("direction = [0.4"), "{text}");

    let both = Scene::from_toml_str("[[lights]]\nposition = [1, 2, 3]\ndirection = [0, 0, -1]\n")
        .unwrap_err()
        .to_string();
    assert!(both.contains("not both"), "{both}");
    let nan = Scene::from_toml_str("[[lights]]\nposition = [1, nan, 3]\n").unwrap_err();
    assert!(
        matches!(&nan, SceneError::NonFinite { field } if field == "lights[0].position"),
        "{nan:?}"
    );
    // A point light's (default) direction is not validated.
    let mut scene = Scene::default_teapot();
    scene.lights = vec![reyes::scene::Light {
        direction: Vec3::ZERO,
        ..reyes::scene::Light::point(Vec3::ONE, Vec3::ONE, 1.0)
    }];
    scene.validate().unwrap();
}

#[test]
fn orthographic_cameras_parse_and_validate() {
    let base = "[camera]\neye = [0, -10, 0]\ntarget = [0, 0, 0]\nprojection = \"orthographic\"\n";
    let scene = Scene::from_toml_str(&format!("{base}ortho_height = 3.0\n")).unwrap();
    let camera = scene.camera.unwrap();
    assert_eq!(camera.projection, reyes::scene::Projection::Orthographic);
    assert_eq!(camera.view_height(), 3.0);
    let text = scene.to_toml_string();
    assert!(
        text.contains("projection = \"orthographic\"") && text.contains("ortho_height = 3.0"),
        "{text}"
    );
    // The default height is the field of view's at the target.
    let scene = Scene::from_toml_str(base).unwrap();
    let expected = 2.0 * 10.0 * 20f32.to_radians().tan();
    assert!((scene.camera.unwrap().view_height() - expected).abs() < 1e-4);
    // A perspective camera writes no projection keys.
    assert!(
        !Scene::default_teapot()
            .to_toml_string()
            .contains("projection")
    );
    let err = |text: &str| Scene::from_toml_str(text).unwrap_err().to_string();
    let zero = err(&format!("{base}ortho_height = 0.0\n"));
    assert!(zero.contains("orthographic view height 0"), "{zero}");
    let lens = err(&format!("{base}[lens]\naperture = 0.1\n"));
    assert!(
        lens.contains("lens.aperture") && lens.contains("orthographic"),
        "{lens}"
    );
    let unknown =
        err("[camera]\neye = [0, -10, 0]\ntarget = [0, 0, 0]\nprojection = \"fisheye\"\n");
    assert!(
        unknown.contains("fisheye") || unknown.contains("unknown variant"),
        "{unknown}"
    );
}

/// The automatic camera frames the objects at shutter open; its far plane
/// also covers where they move, so a teapot receding 200 units along the
/// view is not cut off at the framing's far plane (the distance plus four
/// radii, about 25 units here).
#[test]
fn the_automatic_far_plane_covers_the_motion() {
    let scene = Scene::from_toml_str(
        r#"
[[objects]]
model = "teapot"
[objects.transform_close]
translate = [0.0, 200.0, 0.0]
"#,
    )
    .unwrap();
    let prepared = PreparedScene::load(&scene).unwrap();
    let camera = &prepared.camera;
    let forward = (camera.target - camera.eye).normalize();
    let teapot = Model::teapot();
    let farthest_at_close = teapot
        .patches
        .iter()
        .flat_map(|p| p.points)
        .map(|p| (p + Vec3::new(0.0, 200.0, 0.0) - camera.eye).dot(forward))
        .fold(f32::NEG_INFINITY, f32::max);
    assert!(
        camera.far > farthest_at_close,
        "far plane {} in front of the farthest point at close, {farthest_at_close}",
        camera.far
    );
    // A still teapot keeps the framing's plane.
    let still = Scene::from_toml_str("[[objects]]\nmodel = \"teapot\"\n").unwrap();
    let still = PreparedScene::load(&still).unwrap();
    assert!(still.camera.far < 40.0, "{}", still.camera.far);
}

#[test]
fn a_matrix_places_an_object_after_its_other_placement() {
    // RenderMan's ConcatTransform order: the translation is numbers 13-15.
    let with_matrix = Scene::from_toml_str(
        "[[objects]]\nmodel = \"teapot\"\n\
         transform = { scale = 2.0, matrix = [0, 1, 0, 0,  -1, 0, 0, 0,  0, 0, 1, 0,  5, 6, 7, 1] }\n",
    )
    .unwrap();
    let matrix = with_matrix.objects[0].transform.matrix();
    // Scale by 2, then turn 90 degrees about z, then move by (5, 6, 7).
    let moved = matrix.transform_point3(Vec3::new(1.0, 0.0, 0.0));
    assert!(moved.abs_diff_eq(Vec3::new(5.0, 8.0, 7.0), 1e-6), "{moved}");
    let plain = Scene::from_toml_str(
        "[[objects]]\nmodel = \"teapot\"\n\
         transform = { scale = 2.0, rotate_degrees = [0, 0, 90], translate = [5, 6, 7] }\n",
    )
    .unwrap();
    assert!(
        matrix.abs_diff_eq(plain.objects[0].transform.matrix(), 1e-6),
        "{matrix} against {}",
        plain.objects[0].transform.matrix()
    );
    // Written back, the matrix round-trips.
    let again = Scene::from_toml_str(&with_matrix.to_toml_string()).unwrap();
    assert_eq!(again.objects[0].transform, with_matrix.objects[0].transform);
    // A non-finite matrix is named.
    let error = Scene::from_toml_str(
        "[[objects]]\nmodel = \"teapot\"\n\
         transform = { matrix = [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  nan, 0, 0, 1] }\n",
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("objects[0].transform.matrix"), "{error}");
    // Not 16 numbers: a parse error.
    assert!(
        Scene::from_toml_str(
            "[[objects]]\nmodel = \"teapot\"\ntransform = { matrix = [1, 0, 0] }\n"
        )
        .is_err()
    );
}

#[test]
fn objects_that_reuse_a_model_share_its_stored_patches() {
    let text = "[[objects]]\nmodel = \"teapot\"\n\
                [[objects]]\nmodel = \"teapot\"\ntransform = { translate = [4, 0, 0] }\n\
                [[objects]]\nmodel = \"teapot\"\ntransform = { translate = [8, 0, 0] }\n";
    let scene = PreparedScene::load(&Scene::from_toml_str(text).unwrap()).unwrap();
    let teapot = Model::teapot().patches.len();
    assert_eq!(scene.patches.len(), 3 * teapot);
    assert_eq!(scene.store.len as usize, teapot);
    assert_eq!(scene.store.shared.len(), teapot);
    assert!(scene.objects.iter().all(|o| o.placement.is_some()));
    let one = PreparedScene::load(&Scene::default_teapot()).unwrap();
    assert_eq!(one.store.len as usize, teapot);
    assert!(one.store.shared.is_empty() && one.objects[0].placement.is_none());
}

/// A colour below zero in any channel is refused with its key; above one
/// is light brighter than white and is kept.
#[test]
fn colours_below_zero_are_refused_with_their_key() {
    for (text, key) in [
        ("background = [2.0, -1.0, 0.0]\n", "background"),
        (
            "[[objects]]\nmodel = \"teapot\"\ncolor = [0.5, -0.1, 0.5]\n",
            "objects[0].color",
        ),
        (
            "[[lights]]\ndirection = [0.0, 0.0, -1.0]\ncolor = [-1.0, 1.0, 1.0]\n",
            "lights[0].color",
        ),
    ] {
        let error = reyes::scene::Scene::from_toml_str(text)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains(key) && error.contains("every channel must be >= 0"),
            "{text}: {error}"
        );
    }
    let bright = reyes::scene::Scene::from_toml_str("background = [2.0, 1.0, 0.0]\n").unwrap();
    assert_eq!(bright.background, glam::Vec3::new(2.0, 1.0, 0.0));
}
