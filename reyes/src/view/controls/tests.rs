//! Tests of [`super`].

use super::*;

fn camera() -> Camera {
    Camera::new(
        Vec3::new(0.0, -10.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        0.8,
        640,
        480,
        0.1,
        100.0,
    )
}

fn settings() -> Settings {
    Settings {
        spp: 4,
        sampling: Sampling::Bbox,
        dicing: Dicing::Rate,
        shading_rate: 1.0,
        dice_threshold: 16.0,
        motion_blur: true,
        aperture: 0.0,
        aov: Aov::Shaded,
        shadows: true,
    }
}

fn controls() -> Controls {
    Controls::new(
        Orbit::from_camera(&camera()),
        settings(),
        (Vec3::splat(-1.0), Vec3::splat(1.0)),
    )
}

fn drag(c: &mut Controls, button: Button, from: (f32, f32), to: (f32, f32)) -> Outcome {
    let size = (640, 480);
    c.handle(Input::CursorMoved(from.0, from.1), size);
    c.handle(Input::Pressed(button), size);
    let out = c.handle(Input::CursorMoved(to.0, to.1), size);
    c.handle(Input::Released(button), size);
    out
}

#[test]
fn the_orbit_reproduces_the_camera() {
    let orbit = Orbit::from_camera(&camera());
    assert_eq!(orbit.eye, Vec3::new(0.0, -10.0, 0.0));
    assert_eq!(orbit.camera(&camera(), 640, 480), camera());
}

#[test]
fn a_left_drag_orbits_about_the_up_axis_by_the_drag() {
    let mut c = controls();
    let out = drag(&mut c, Button::Left, (100.0, 100.0), (200.0, 100.0));
    assert!(out.camera_moved && !out.settings_changed);
    // 100 px to the right: the eye turns 1 radian clockwise seen from +z.
    let eye = c.orbit.eye;
    let angle = (-1.0f32).sin_cos();
    assert!((eye.x - (-10.0 * -angle.0)).abs() < 1e-3, "{eye}");
    assert!((eye.y - (-10.0 * angle.1)).abs() < 1e-3, "{eye}");
    assert!(eye.z.abs() < 1e-4);
    assert!((c.orbit.distance() - 10.0).abs() < 1e-4);
    assert_eq!(c.orbit.target, Vec3::ZERO);
}

#[test]
fn a_vertical_drag_stops_short_of_the_pole() {
    let mut c = controls();
    drag(&mut c, Button::Left, (0.0, 0.0), (0.0, 10.0));
    assert!(
        c.orbit.eye.z > 0.9,
        "a drag down raises the eye: {}",
        c.orbit.eye
    );
    drag(&mut c, Button::Left, (0.0, 0.0), (0.0, 1000.0));
    let polar = c.orbit.direction().dot(Vec3::Z).acos();
    assert!((polar - POLE_MARGIN).abs() < 1e-3, "{polar}");
    assert!(crate::camera::pose_problem(c.orbit.eye, c.orbit.target, c.orbit.up).is_none());
}

#[test]
fn a_right_drag_pans_the_point_under_the_cursor() {
    let mut c = controls();
    let out = drag(&mut c, Button::Right, (0.0, 0.0), (48.0, 0.0));
    assert!(out.camera_moved);
    // 48 px of 480 at distance 10 and fov 0.8: 0.1 of the visible height.
    let expected = 2.0 * 10.0 * 0.4f32.tan() * 0.1;
    assert!(
        (c.orbit.target.x + expected).abs() < 1e-4,
        "{}",
        c.orbit.target
    );
    assert!((c.orbit.eye.x + expected).abs() < 1e-4);
}

#[test]
fn the_wheel_zooms_and_f_frames_the_bounds() {
    let mut c = controls();
    assert!(c.handle(Input::Wheel(2.0), (640, 480)).camera_moved);
    assert!((c.orbit.distance() - 10.0 * 0.81).abs() < 1e-4);
    assert!(c.handle(Input::Key(Key::Frame), (640, 480)).camera_moved);
    let radius = 3f32.sqrt();
    assert!((c.orbit.distance() - radius / 0.4f32.sin()).abs() < 1e-4);
    assert_eq!(c.orbit.target, Vec3::ZERO);
}

#[test]
fn a_move_without_a_button_does_nothing() {
    let mut c = controls();
    let before = c.orbit;
    assert_eq!(
        c.handle(Input::CursorMoved(5.0, 5.0), (640, 480)),
        Outcome::default()
    );
    assert_eq!(
        c.handle(Input::CursorMoved(50.0, 5.0), (640, 480)),
        Outcome::default()
    );
    assert_eq!(c.orbit, before);
}

#[test]
fn keys_step_the_settings() {
    let mut c = controls();
    let size = (640, 480);
    assert!(c.handle(Input::Key(Key::MoreSpp), size).settings_changed);
    assert_eq!(c.settings.spp, 9);
    c.handle(Input::Key(Key::FewerSpp), size);
    c.handle(Input::Key(Key::FewerSpp), size);
    c.handle(Input::Key(Key::FewerSpp), size);
    assert_eq!(c.settings.spp, 1);
    // The steps go past 64 to 256 (16 x 16) and stop there.
    c.settings.spp = 64;
    c.handle(Input::Key(Key::MoreSpp), size);
    assert_eq!(c.settings.spp, 81);
    c.settings.spp = 225;
    c.handle(Input::Key(Key::MoreSpp), size);
    c.handle(Input::Key(Key::MoreSpp), size);
    assert_eq!(c.settings.spp, 256);
    c.settings.spp = 1;
    c.handle(Input::Key(Key::NextSampling), size);
    assert_eq!(c.settings.sampling, Sampling::Simple);
    c.handle(Input::Key(Key::Finer), size);
    assert_eq!(c.settings.shading_rate, 0.5);
    c.handle(Input::Key(Key::ToggleMotion), size);
    assert!(!c.settings.motion_blur);
    assert!(c.handle(Input::Key(Key::ToggleShadows), size).settings_changed);
    assert!(!c.settings.shadows);
    c.handle(Input::Key(Key::WiderAperture), size);
    assert!(c.settings.aperture > 0.0);
    c.handle(Input::Key(Key::NextAov), size);
    assert_eq!(c.settings.aov, Aov::Grids);
    // Already a pinhole twice over: no change, no new frame.
    c.settings.aperture = 0.0;
    assert!(
        !c.handle(Input::Key(Key::NarrowerAperture), size)
            .settings_changed
    );
    assert!(c.handle(Input::Key(Key::Save), size).save);
    assert!(c.handle(Input::Key(Key::Quit), size).quit);
}
