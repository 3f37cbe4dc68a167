//! Unit tests of the scene module: its documented example and camera motion.

use glam::Vec3;

use super::*;
use crate::camera::Camera;
use crate::test_random::{fresh_rng, random_vec3};

/// The full example in this module's documentation stays valid.
#[test]
fn module_doc_example_parses() {
    let source = include_str!("mod.rs");
    let marker = "//! ```toml\n//! spp = 4";
    let start = source.find(marker).expect("the full example") + "//! ```toml\n".len();
    let end = start + source[start..].find("//! ```").unwrap();
    let text: String = source[start..end]
        .lines()
        .map(|l| {
            l.strip_prefix("//!")
                .unwrap_or(l)
                .strip_prefix(' ')
                .unwrap_or("")
        })
        .collect::<Vec<_>>()
        .join("\n");
    let scene = Scene::from_toml_str(&text).unwrap();
    assert_eq!(scene.objects.len(), 2);
    let mut spot = Light::spot(
        Vec3::new(0.0, -6.0, 6.0),
        Vec3::new(0.0, 1.0, -1.0),
        Vec3::ONE,
        40.0,
    );
    spot.cone_angle_degrees = 30.0;
    assert_eq!(
        scene.lights,
        vec![
            Light::default(),
            Light::point(Vec3::new(0.0, 3.0, 4.0), Vec3::ONE, 20.0),
            spot,
            Light::ambient(Vec3::new(0.2, 0.2, 0.3), 0.5),
        ]
    );
    assert_eq!(scene.specular, Specular::default());
    assert_eq!(scene.objects[0].surface, Some(Surface::PLASTIC));
    assert_eq!(scene.objects[1].surface, None);
}

/// A moved and panned camera (fresh random poses, the seed printed):
/// the eye moves by the vector, the view direction keeps its length and
/// its component along up and turns by the pan about up, and for a
/// positive pan the point the camera looked at lands right of the
/// image's centre, at the angle's tangent on the image plane.
#[test]
fn a_moved_camera_pans_about_its_up_axis() {
    use rand::Rng;
    let (seed, mut rng) = fresh_rng("a_moved_camera_pans_about_its_up_axis");
    for _ in 0..50 {
        let eye = random_vec3(&mut rng, 10.0);
        let by = random_vec3(&mut rng, 3.0);
        // Level views (target at the eye's height), so that the
        // image's horizontal axis is the pan's plane.
        let ahead =
            random_vec3(&mut rng, 5.0) * Vec3::new(1.0, 1.0, 0.0) + Vec3::new(0.3, 0.0, 0.0);
        let camera = CameraDesc {
            eye,
            target: eye + ahead,
            up: Vec3::Z,
            fov_y_degrees: 50.0,
            near: 0.1,
            far: 100.0,
            projection: Projection::Perspective,
            ortho_height: None,
        };
        let pan = rng.random_range(1.0f32..40.0);
        let close = camera.moved(by, pan);
        assert!(close.eye.abs_diff_eq(eye + by, 1e-5), "seed {seed}");
        assert_eq!(close.up, None, "seed {seed}");
        let turned = close.target - close.eye;
        assert!((turned.length() - ahead.length()).abs() < 1e-4 * ahead.length());
        assert!(turned.z.abs() < 1e-4, "seed {seed}: {turned}");
        let turn = ahead.angle_between(turned).to_degrees();
        assert!((turn - pan).abs() < 1e-2, "seed {seed}: {turn} vs {pan}");
        assert!(ahead.cross(turned).z > 0.0, "seed {seed}: counterclockwise");

        let (width, height) = (200, 100);
        let fov = camera.fov_y_degrees.to_radians();
        let at_close = Camera::new(
            close.eye,
            close.target,
            Vec3::Z,
            fov,
            width,
            height,
            0.1,
            100.0,
        );
        let old_target = close.eye + ahead;
        let pixel = at_close.to_pixel(at_close.to_clip(old_target));
        let focal = height as f32 / 2.0 / (fov / 2.0).tan();
        let want = width as f32 / 2.0 + focal * pan.to_radians().tan();
        assert!(
            (pixel.x - want).abs() < 0.05,
            "seed {seed}: x {} vs {want}",
            pixel.x
        );
        assert!(
            (pixel.y - height as f32 / 2.0).abs() < 0.05,
            "seed {seed}: y {}",
            pixel.y
        );
    }
}

/// `shadow_map_space` is 16 numbers in `ConcatTransform` order, survives a
/// round trip through TOML, and must be finite and invertible.
#[test]
fn the_shadow_maps_space_reads_round_trips_and_is_checked() {
    let scene = Scene::from_toml_str(
        "lights = []\nshadow_map_space = [-1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  2, 3, 4, 1]",
    )
    .unwrap();
    let space = scene.shadow_map_space.expect("given");
    assert_eq!(
        space.transform_point3(Vec3::new(1.0, 0.0, 0.0)),
        Vec3::new(1.0, 3.0, 4.0),
        "x mirrored, then moved by the last column"
    );
    let again = Scene::from_toml_str(&scene.to_toml_string()).unwrap();
    assert_eq!(again.shadow_map_space, Some(space));
    assert!(
        !Scene::default()
            .to_toml_string()
            .contains("shadow_map_space")
    );
    for (numbers, expected) in [
        (
            "nan, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1",
            "finite",
        ),
        (
            "1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 0, 0,  0, 0, 0, 1",
            "invertible",
        ),
    ] {
        let error = Scene::from_toml_str(&format!("lights = []\nshadow_map_space = [{numbers}]"))
            .expect_err("refused");
        let message = error.to_string();
        assert!(
            message.contains("shadow_map_space") && message.contains(expected),
            "{message}"
        );
    }
}
