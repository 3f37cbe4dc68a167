//! Validation of what a scene derives, not only what it writes (issue 19,
//! D14 and D16): the automatically framed camera, the view direction and
//! matrices, transformed control points, tiny models and degenerate patches.

mod files;

use files::{TempDir, run_cli};
use glam::Vec3;
use reyes::load::bpt;
use reyes::model::{Model, Patch};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{FramingError, Scene, SceneError};

/// The teapot scaled by `scale`, with `camera` (a `[camera]` table's
/// lines) if given, at 96 x 72.
fn teapot_scene(scale: &str, camera: Option<&str>) -> String {
    let mut text = format!(
        "[resolution]\nwidth = 96\nheight = 72\n[[objects]]\nmodel = \"teapot\"\n[objects.transform]\nscale = {scale}\n"
    );
    if let Some(camera) = camera {
        text.push_str("[camera]\n");
        text.push_str(camera);
    }
    text
}

/// Parses and prepares a scene text.
fn prepare(text: &str) -> Result<PreparedScene, SceneError> {
    PreparedScene::load(&Scene::from_toml_str(text)?)
}

#[test]
fn a_model_at_1e19_gets_the_framing_error() {
    let error = prepare(&teapot_scene("1e19", None)).unwrap_err();
    assert!(
        matches!(
            &error,
            SceneError::Framing {
                objects: 1,
                source: FramingError::TooLarge { .. }
            }
        ),
        "{error:?}"
    );
    let text = error.to_string();
    assert!(
        text.contains("the model's bounds") && text.contains("too large to frame automatically"),
        "{text}"
    );
    assert!(
        !text.contains("camera.eye"),
        "the user gave no camera: {text}"
    );
}

#[test]
fn a_bare_model_file_with_huge_coordinates_names_its_bounds() {
    let dir = TempDir::new("huge-model");
    let mut model = Model::teapot();
    for patch in &mut model.patches {
        for p in &mut patch.points {
            *p *= 1e19;
        }
    }
    let path = dir.path("huge.bpt");
    std::fs::write(&path, bpt::write(&model)).unwrap();
    let out = dir.path("out.png");
    let (ok, stderr) = run_cli(&[
        "render",
        path.to_str().unwrap(),
        "--cpu",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains("the model's bounds")
            && stderr.contains("too large to frame automatically"),
        "{stderr}"
    );
    assert!(!stderr.contains("camera.eye must be finite"), "{stderr}");
}

#[test]
fn an_eye_at_3e38_is_refused_naming_the_eye() {
    for eye in [
        "[3e38, 0.0, 0.0]",
        "[3e38, 3e38, 3e38]",
        "[0.0, -3e38, 1.0]",
    ] {
        let camera = format!("eye = {eye}\ntarget = [0.0, 0.0, 0.0]\n");
        let error = Scene::from_toml_str(&teapot_scene("1.0", Some(&camera))).unwrap_err();
        let text = error.to_string();
        assert!(
            matches!(error, SceneError::InvalidCamera { .. }) && text.contains("camera.eye"),
            "eye {eye}: {text}"
        );
        assert!(!text.contains("parallel"), "eye {eye}: {text}");
    }
}

#[test]
fn an_eye_at_1e30_is_refused_naming_the_eye_not_up() {
    let camera = "eye = [1e30, 0.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\n";
    let text = Scene::from_toml_str(&teapot_scene("1.0", Some(camera)))
        .unwrap_err()
        .to_string();
    assert!(text.contains("camera.eye"), "{text}");
    assert!(!text.contains("parallel"), "{text}");
    // Each within range, but too far apart to square their distance.
    let camera = "eye = [1.5e19, 0.0, 0.0]\ntarget = [-1.5e19, 0.0, 0.0]\n";
    let text = Scene::from_toml_str(&teapot_scene("1.0", Some(camera)))
        .unwrap_err()
        .to_string();
    assert!(
        text.contains("camera.eye and camera.target are too far apart"),
        "{text}"
    );
    // Distinct, but too close to normalize the view direction.
    let camera = "eye = [1e-30, 0.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\n";
    let text = Scene::from_toml_str(&teapot_scene("1.0", Some(camera)))
        .unwrap_err()
        .to_string();
    assert!(
        text.contains("camera.eye and camera.target are too close"),
        "{text}"
    );
}

#[test]
fn the_command_line_eye_is_checked_like_the_scenes() {
    let dir = TempDir::new("cli-eye");
    let out = dir.path("out.png");
    let (ok, stderr) = run_cli(&[
        "render",
        "--cpu",
        "--eye",
        "1e30,0,0",
        "--target",
        "0,0,0",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!ok, "{stderr}");
    assert!(stderr.contains("camera.eye"), "{stderr}");
    assert!(!stderr.contains("parallel"), "{stderr}");
}

#[test]
fn an_up_of_extreme_length_is_accepted() {
    for up in ["[0.0, 0.0, 1e30]", "[0.0, 0.0, 1e-30]"] {
        let camera = format!("eye = [0.0, -10.0, 3.0]\ntarget = [0.0, 0.0, 1.0]\nup = {up}\n");
        let prepared = prepare(&teapot_scene("1.0", Some(&camera))).unwrap();
        assert!(prepared.camera.view_proj().is_finite(), "up {up}");
        assert!(
            reference::try_render(&prepared).unwrap().stats.samples_hit > 0,
            "up {up}"
        );
    }
}

#[test]
fn a_projection_that_overflows_is_refused() {
    let camera = "eye = [0.0, -10.0, 3.0]\ntarget = [0.0, 0.0, 1.0]\nnear = 3e38\nfar = 3.4e38\n";
    let error = Scene::from_toml_str(&teapot_scene("1.0", Some(camera))).unwrap_err();
    assert!(
        matches!(&error, SceneError::InvalidCamera { reason } if reason.contains("projection matrix")),
        "{error:?}"
    );
}

#[test]
fn a_transform_whose_product_overflows_is_refused() {
    let camera = "eye = [0.0, -10.0, 3.0]\ntarget = [0.0, 0.0, 1.0]\n";
    // The teapot reaches x = 3.525: times 1e38 is beyond f32::MAX.
    for camera in [Some(camera), None] {
        let error = prepare(&teapot_scene("1e38", camera)).unwrap_err();
        assert!(
            matches!(
                &error,
                SceneError::TransformOverflow {
                    index: 0,
                    field: "transform",
                    ..
                }
            ),
            "{error:?}"
        );
        assert!(error.to_string().contains("objects[0].transform"));
    }
    // At shutter close.
    let text = format!(
        "{}[objects.transform_close]\nscale = 1e38\n",
        teapot_scene("1.0", Some(camera))
    );
    let error = prepare(&text).unwrap_err();
    assert!(
        matches!(
            &error,
            SceneError::TransformOverflow {
                field: "transform_close",
                ..
            }
        ),
        "{error:?}"
    );
}

#[test]
fn a_teapot_scaled_by_1e_30_is_refused_clearly() {
    let error = prepare(&teapot_scene("1e-30", None)).unwrap_err();
    assert!(
        matches!(
            &error,
            SceneError::Framing {
                source: FramingError::TooSmall { .. },
                ..
            }
        ),
        "{error:?}"
    );
    let text = error.to_string();
    assert!(
        text.contains("too small to frame automatically") && text.contains("scale the model up"),
        "{text}"
    );
}

#[test]
fn small_teapots_are_framed_like_the_full_size_one() {
    let full = reference::try_render(&prepare(&teapot_scene("1.0", None)).unwrap()).unwrap();
    assert!(full.stats.samples_hit > 0);
    for scale in ["1e-3", "1e-5"] {
        let small = reference::try_render(&prepare(&teapot_scene(scale, None)).unwrap()).unwrap();
        let (a, b) = (
            full.stats.samples_hit as f64,
            small.stats.samples_hit as f64,
        );
        assert!(
            (a - b).abs() <= 0.01 * a,
            "scale {scale}: {b} samples hit, {a} at full size"
        );
    }
}

/// A model of the teapot's first patch and `extra`.
fn with_patches(extra: &[[Vec3; 16]]) -> Model {
    let teapot = Model::teapot();
    let mut patches = vec![teapot.patches[0]];
    patches.extend(extra.iter().map(|&points| Patch { points }));
    Model::new(patches)
}

#[test]
fn degenerate_patches_are_skipped_with_a_count() {
    let point = [Vec3::new(0.5, 0.25, 1.0); 16];
    let line: [Vec3; 16] = std::array::from_fn(|k| Vec3::new(1.0, 2.0, 3.0) * (k as f32 * 0.1));
    let model = with_patches(&[point, line]);
    let scene = Scene::for_model("model.bpt", &model);
    let prepared = PreparedScene::new(&scene, &[model]).unwrap();
    assert_eq!(prepared.skipped_degenerate_patches, 2);
    assert_eq!(prepared.patches.len(), 1);
    assert!(!reyes::prepare::degenerate_patch(
        &Model::teapot().patches[0].points
    ));
    // Every patch of the teapot has an area (its collapsed edges are
    // edges, not whole patches).
    let teapot = PreparedScene::load(&Scene::default_teapot()).unwrap();
    assert_eq!(teapot.skipped_degenerate_patches, 0);
    assert_eq!(teapot.patches.len(), 32);
}

#[test]
fn a_patch_of_16_identical_points_renders_nothing() {
    // Alone in front of a camera: before, it rendered a blob of float noise.
    let model = Model::new(vec![Patch {
        points: [Vec3::ZERO; 16],
    }]);
    let mut scene = Scene::for_model("point.bpt", &model);
    scene.camera = Some(reyes::scene::CameraDesc {
        eye: Vec3::new(0.0, -5.0, 0.0),
        target: Vec3::ZERO,
        up: Vec3::Z,
        fov_y_degrees: 40.0,
        near: 0.1,
        far: 100.0,
        projection: reyes::scene::Projection::Perspective,
        ortho_height: None,
    });
    scene.resolution.width = 64;
    scene.resolution.height = 48;
    let prepared = PreparedScene::new(&scene, &[model]).unwrap();
    assert_eq!(prepared.skipped_degenerate_patches, 1);
    let rendered = reference::try_render(&prepared).unwrap();
    assert_eq!(rendered.stats.samples_hit, 0);
    assert_eq!(rendered.stats.input_patches, 0);
}
