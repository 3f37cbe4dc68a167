//! Unit tests of animated scenes: keys as written, the still scene of a
//! frame, and the errors of bad keys.

use glam::Vec3;

use super::{Scale, Scene, SceneError};

/// A teapot spinning and sliding over keys at frames 0, 10 and 20 (24 fps),
/// with a camera that dollies in over a second given in seconds.
const SPINNING: &str = r#"
shutter = 0.5
[animation]
fps = 24
[camera]
eye = [0.0, -10.0, 2.0]
target = [0.0, 0.0, 1.0]
fov_y_degrees = 40.0
[[animation.camera]]
time = 0.0
eye = [0.0, -10.0, 2.0]
fov_y_degrees = 40.0
[[animation.camera]]
time = 1.0
eye = [0.0, -6.0, 2.0]
fov_y_degrees = 30.0
aperture = 0.2

[[objects]]
model = "teapot"
transform = { scale = 2.0 }
[[objects.keys]]
frame = 0
rotate_degrees = [0.0, 0.0, 0.0]
translate = [0.0, 0.0, 0.0]
[[objects.keys]]
frame = 10
rotate_degrees = [0.0, 0.0, 90.0]
[[objects.keys]]
frame = 20
rotate_degrees = [0.0, 0.0, 360.0]
translate = [4.0, 0.0, 0.0]
"#;

fn close(a: Vec3, b: Vec3) -> bool {
    a.abs_diff_eq(b, 1e-4)
}

#[test]
fn a_frame_places_objects_and_camera_by_hand_computed_keys() {
    let scene = Scene::from_toml_str(SPINNING).unwrap();
    assert!(scene.is_animated());
    // Frame 5 opens at 5/24 s and closes half a frame later, at frame 5.5.
    let frame = scene.frame(5).unwrap();
    assert_eq!(frame.sampling_seed, 5);
    assert!(frame.animation.is_none() && frame.objects[0].keys.is_empty());
    assert_eq!(
        frame.shutter, 1.0,
        "the keys' poses at open and close are the motion"
    );
    let object = &frame.objects[0];
    // Rotation: 0 -> 90 over frames 0..10: 45 at 5, 49.5 at 5.5.
    assert!(close(
        object.transform.rotate_degrees,
        Vec3::new(0.0, 0.0, 45.0)
    ));
    let at_close = object.transform_close.unwrap();
    assert!(close(at_close.rotate_degrees, Vec3::new(0.0, 0.0, 49.5)));
    // Translation: keys at frames 0 and 20 only: 4 * 5/20 = 1, 4 * 5.5/20 = 1.1.
    assert!(close(object.transform.translate, Vec3::new(1.0, 0.0, 0.0)));
    assert!(close(at_close.translate, Vec3::new(1.1, 0.0, 0.0)));
    // Scale has no key: the transform's stays.
    assert_eq!(object.transform.scale, Scale::Uniform(2.0));
    // Camera: eye y from -10 to -6 over 1 s: at 5/24 s, -10 + 4 * 5/24.
    let camera = frame.camera.unwrap();
    let y = -10.0 + 4.0 * 5.0 / 24.0;
    assert!(close(camera.eye, Vec3::new(0.0, y, 2.0)), "{}", camera.eye);
    assert!((camera.fov_y_degrees - (40.0 - 10.0 * 5.0 / 24.0)).abs() < 1e-4);
    // The target has no key: the [camera]'s.
    assert_eq!(camera.target, Vec3::new(0.0, 0.0, 1.0));
    let pose = frame.camera_close.unwrap();
    assert!(close(
        pose.eye,
        Vec3::new(0.0, -10.0 + 4.0 * 5.5 / 24.0, 2.0)
    ));
    // One aperture key: held at every time.
    assert_eq!(frame.lens.aperture, 0.2);
    // Past the last key every value holds: 360 degrees, x = 4.
    let late = scene.frame(40).unwrap();
    assert!(close(
        late.objects[0].transform.rotate_degrees,
        Vec3::new(0.0, 0.0, 360.0)
    ));
    assert!(close(
        late.objects[0].transform.translate,
        Vec3::new(4.0, 0.0, 0.0)
    ));
}

#[test]
fn a_smooth_key_follows_catmull_rom() {
    let text = SPINNING.replace(
        "frame = 10\nrotate_degrees",
        "frame = 10\ninterpolation = \"smooth\"\nrotate_degrees",
    );
    let scene = Scene::from_toml_str(&text).unwrap();
    // Segment frames 10..20, angles 90 -> 360, tangents (per frame)
    // m10 = (360 - 0) / 20 = 18 and m20 = (360 - 90) / 10 = 27 (one-sided).
    // At frame 15, s = 0.5: 0.5 * 90 + 0.125 * 10 * 18 + 0.5 * 360
    // - 0.125 * 10 * 27 = 45 + 22.5 + 180 - 33.75 = 213.75.
    let frame = scene.frame(15).unwrap();
    let z = frame.objects[0].transform.rotate_degrees.z;
    assert!((z - 213.75).abs() < 1e-3, "{z}");
    // The segment before key 10 stays linear (key 0's interpolation).
    let frame = scene.frame(5).unwrap();
    assert!((frame.objects[0].transform.rotate_degrees.z - 45.0).abs() < 1e-4);
}

#[test]
fn a_closed_shutter_gives_a_still_frame() {
    let scene = Scene::from_toml_str(&SPINNING.replace("shutter = 0.5", "shutter = 0.0")).unwrap();
    let frame = scene.frame(5).unwrap();
    assert!(frame.camera_close.is_none());
    assert!(frame.objects[0].transform_close.is_none());
    assert_eq!(frame.shutter, 0.0);
}

#[test]
fn a_scene_without_animation_is_its_frames_but_for_the_seed() {
    let scene = Scene::from_toml_str("[[objects]]\nmodel = \"teapot\"\n").unwrap();
    assert!(!scene.is_animated());
    let frame = scene.frame(9).unwrap();
    assert_eq!(frame.sampling_seed, 9);
    assert_eq!(
        Scene {
            sampling_seed: 0,
            ..frame
        },
        scene
    );
}

#[test]
fn animated_scenes_write_back_as_they_read() {
    let scene = Scene::from_toml_str(SPINNING).unwrap();
    let again = Scene::from_toml_str(&scene.to_toml_string()).unwrap();
    assert_eq!(again, scene);
}

/// The error of `SPINNING` with `from` replaced by `to`.
fn error_of(from: &str, to: &str) -> SceneError {
    assert!(SPINNING.contains(from), "{from}");
    Scene::from_toml_str(&SPINNING.replacen(from, to, 1)).unwrap_err()
}

#[test]
fn bad_keys_are_refused_naming_the_key() {
    let message = |from, to| error_of(from, to).to_string();
    // Out of order, and a repeated instant.
    let out_of_order = message("frame = 20", "frame = 8");
    assert!(
        out_of_order.contains("objects[0].keys[2]"),
        "{out_of_order}"
    );
    assert!(out_of_order.contains("out of order"), "{out_of_order}");
    assert!(message("frame = 20", "frame = 10").contains("objects[0].keys[2]"));
    assert!(message("time = 1.0", "time = 0.0").contains("animation.camera[1]"));
    // NaN and infinity.
    let nan = message("frame = 10", "frame = nan");
    assert_eq!(nan, "objects[0].keys[1].frame must be finite");
    let nan = message(
        "rotate_degrees = [0.0, 0.0, 90.0]",
        "rotate_degrees = [0.0, nan, 90.0]",
    );
    assert_eq!(nan, "objects[0].keys[1].rotate_degrees must be finite");
    let inf = message("eye = [0.0, -6.0, 2.0]", "eye = [0.0, -inf, 2.0]");
    assert_eq!(inf, "animation.camera[1].eye must be finite");
    // When: exactly one of frame and time.
    assert!(message("frame = 10\n", "").contains("needs its frame"));
    assert!(message("frame = 10\n", "frame = 10\ntime = 0.4\n").contains("not both"));
    // The frame rate.
    assert!(message("fps = 24", "fps = 0").contains("animation.fps"));
    assert!(message("fps = 24", "fps = nan").contains("animation.fps must be finite"));
    assert!(message("fps = 24", "fps = 1e9").contains("animation.fps"));
    // A pose at close besides the keys; camera keys without a camera.
    assert!(
        message(
            "transform = { scale = 2.0 }",
            "transform_close = { scale = 2.0 }"
        )
        .contains("objects[0].transform_close")
    );
    let no_camera = message(
        "[camera]\neye = [0.0, -10.0, 2.0]\ntarget = [0.0, 0.0, 1.0]\nfov_y_degrees = 40.0\n",
        "",
    );
    assert!(no_camera.contains("[camera] table"), "{no_camera}");
    // An unknown key field is a parse error with its line.
    assert!(matches!(
        error_of("frame = 10\n", "frame = 10\nspin = 3\n"),
        SceneError::Parse { line: Some(_), .. }
    ));
}

#[test]
fn keys_that_make_a_frames_camera_unusable_fail_that_frame() {
    // At frame 12 (0.5 s) the eye reaches the target.
    let text = SPINNING.replace("eye = [0.0, -6.0, 2.0]", "eye = [0.0, 10.0, 0.0]");
    let scene = Scene::from_toml_str(&text).unwrap();
    assert!(scene.frame(0).is_ok());
    // The eye's z goes 2 -> 0 and y -10 -> 10 over 24 frames: at 12 it is
    // (0, 0, 1), the target.
    assert!(matches!(
        scene.frame(12),
        Err(SceneError::InvalidCamera { .. })
    ));
}

#[test]
fn the_documented_animation_parses_and_makes_frames() {
    let doc = include_str!("../../../docs/reyes-scene.md");
    let section = &doc[doc.find("### Animation").expect("the section")..];
    let start = section.find("```toml\n").expect("its example") + "```toml\n".len();
    let example = &section[start..start + section[start..].find("```").unwrap()];
    let scene = Scene::from_toml_str(example).unwrap();
    assert!(scene.is_animated());
    // Frame 24 is half way through the turn between the keys at frames 1
    // and 48 (linear): 360 * 23 / 47 degrees.
    let frame = scene.frame(24).unwrap();
    let z = frame.objects[0].transform.rotate_degrees.z;
    assert!((z - 360.0 * 23.0 / 47.0).abs() < 1e-3, "{z}");
}
