//! Motion blur and depth of field: how far things move and blur, shared by
//! the CPU reference and the GPU path.
//!
//! * **Motion.** An object is placed by its `transform` at shutter open and
//!   by the transform interpolated (translation, slerp, scale) at the
//!   scene's `shutter` fraction at shutter close. Patches are kept at their
//!   open positions; the affine map [`ObjectMotion::matrix`] takes an open
//!   world position to its close position. Grid points are positioned at
//!   open and at close, and a sample at time `t` in `[0, 1]` sees each
//!   grid point at the linear interpolation of its two *pixel* positions
//!   (the constant-velocity assumption of the papers).
//! * **Lens.** A thin lens of radius `aperture` focused at `focus` (view
//!   depth): a point at view depth `w` seen through lens position `l` (unit
//!   disk) moves on screen by `l * coc(w)` pixels, with the signed circle of
//!   confusion `coc(w) = aperture * (1 / focus - 1 / w) * pixel_scale` and
//!   `pixel_scale = height / (2 tan(fov_y / 2))` pixels per unit of
//!   `x / w`. The same shift is a lateral world-space move of
//!   `|l| * aperture * |w / focus - 1|`, which is how the bound test grows
//!   its boxes for depth of field ([`cull_radius`]).

use glam::{Mat4, Vec3};

use crate::camera::Camera;

/// The thin lens of a prepared scene.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PreparedLens {
    /// Lens radius in world units (0: a pinhole).
    pub aperture: f32,
    /// View depth of the plane in focus (> 0).
    pub focus: f32,
    /// Pixels per unit of `x / w` on screen, of the full image (tiles share it).
    pub pixel_scale: f32,
}

impl PreparedLens {
    /// The lens for `camera` with `aperture` and an optional focus distance
    /// (default: the eye-to-target distance).
    pub fn new(camera: &Camera, aperture: f32, focus_distance: Option<f32>) -> PreparedLens {
        PreparedLens {
            aperture,
            focus: focus_distance.unwrap_or_else(|| camera.eye.distance(camera.target)),
            pixel_scale: camera.height as f32 / (2.0 * (camera.fov_y_radians * 0.5).tan()),
        }
    }

    /// The signed circle of confusion, in pixels, of a point at view depth
    /// (clip `w`) `w`: 0 on the focal plane and for a pinhole.
    pub fn coc(&self, w: f32) -> f32 {
        if self.aperture == 0.0 {
            return 0.0;
        }
        self.aperture * (1.0 / self.focus - 1.0 / w) * self.pixel_scale
    }

    /// The largest lateral world-space shift the lens gives a point whose
    /// view depth lies in `[w - e, w + e]`: `aperture * |w' / focus - 1|`,
    /// largest at an end of the interval (the function is convex in `w'`).
    pub fn world_shift(&self, w: f32, e: f32) -> f32 {
        if self.aperture == 0.0 {
            return 0.0;
        }
        let at = |depth: f32| (depth / self.focus - 1.0).abs();
        self.aperture * at(w - e).max(at(w + e))
    }
}

/// How one object moves during the shutter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObjectMotion {
    /// Open world position to close world position: `close * open^-1`.
    pub matrix: Mat4,
    /// An upper bound (at least 1) of how much the motion stretches lengths:
    /// the Frobenius norm of the linear part of `matrix`. A displacement of
    /// `b` at open is at most `stretch * b` at close.
    pub stretch: f32,
}

impl ObjectMotion {
    /// The motion from the `open` to the `close` placement matrix, or `None`
    /// when they are equal (the object does not move).
    pub fn new(open: Mat4, close: Mat4) -> Option<ObjectMotion> {
        if open == close {
            return None;
        }
        let matrix = close * open.inverse();
        let linear = [matrix.x_axis, matrix.y_axis, matrix.z_axis]
            .iter()
            .map(|c| c.truncate().length_squared())
            .sum::<f32>()
            .sqrt();
        Some(ObjectMotion {
            matrix,
            stretch: linear.max(1.0),
        })
    }

    /// Where a world-space point at shutter open is at shutter close.
    pub fn close(&self, open: Vec3) -> Vec3 {
        self.matrix.transform_point3(open)
    }
}

/// The view a fraction `t` of the way from view `open` to view `close`
/// (world-to-view matrices of rigid cameras): the eye interpolated linearly,
/// the orientation by slerp (the shorter way). `t = 0` and `t = 1` give
/// `open` and `close` exactly.
pub fn interpolate_view(open: Mat4, close: Mat4, t: f32) -> Mat4 {
    if t == 0.0 {
        return open;
    }
    if t == 1.0 {
        return close;
    }
    // The inverse of a view is the camera's placement: its rotation and eye.
    let (_, rotation_open, eye_open) = open.inverse().to_scale_rotation_translation();
    let (_, rotation_close, eye_close) = close.inverse().to_scale_rotation_translation();
    Mat4::from_rotation_translation(
        rotation_open.slerp(rotation_close, t),
        eye_open.lerp(eye_close, t),
    )
    .inverse()
}

/// Camera motion as a motion of the world: the rigid map `open^-1 * close`
/// that takes a world point to where the camera at view `open` sees what
/// the camera at view `close` sees at the point (see the module
/// documentation). `None` when the views are equal.
pub fn camera_motion(open: Mat4, close: Mat4) -> Option<Mat4> {
    (open != close).then(|| open.inverse() * close)
}

/// The world-space radius the bound test grows a control point `p` by so
/// that the surface it stands for stays inside at every time and lens
/// position: the displacement bound (stretched by the motion), the point's
/// motion, and the lens shift over the view depths the point can reach.
/// `w` is the point's clip `w` (its view depth) at open.
pub fn cull_radius(
    p: Vec3,
    w: f32,
    displacement_bound: f32,
    motion: Option<&ObjectMotion>,
    lens: &PreparedLens,
) -> f32 {
    let (stretch, moved) = motion.map_or((1.0, 0.0), |m| (m.stretch, m.close(p).distance(p)));
    let reach = displacement_bound * stretch + moved;
    reach + lens.world_shift(w, reach)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Transform;
    use crate::test_random::{fresh_rng, random_vec3};

    #[test]
    fn slerp_keeps_a_spinning_object_at_its_size() {
        let open = Transform::default();
        let close = Transform {
            rotate_degrees: Vec3::new(0.0, 0.0, 170.0),
            ..Transform::default()
        };
        let p = Vec3::new(2.0, 0.0, 1.0);
        for k in 0..=10 {
            let t = k as f32 / 10.0;
            let q = open.interpolate(&close, t).transform_point3(p);
            assert!((q.length() - p.length()).abs() < 1e-5, "{t} {q}");
            let angle = q.y.atan2(q.x).to_degrees();
            assert!((angle - 170.0 * t).abs() < 1e-3, "{t} {angle}");
        }
        // Linear matrix interpolation would have shrunk it to cos(85) at t = 1/2.
        let lerped = (open.matrix() * 0.5 + close.matrix() * 0.5).transform_point3(p);
        assert!(lerped.truncate().length() < 0.2 * p.truncate().length());
    }

    #[test]
    fn interpolation_ends_at_both_transforms() {
        let open = Transform {
            translate: Vec3::new(1.0, 2.0, 3.0),
            rotate_degrees: Vec3::new(10.0, 20.0, 30.0),
            scale: crate::scene::Scale::PerAxis(Vec3::new(1.0, 2.0, 0.5)),
            matrix: None,
        };
        let close = Transform {
            translate: Vec3::new(-1.0, 0.0, 3.0),
            rotate_degrees: Vec3::new(10.0, 20.0, 60.0),
            scale: crate::scene::Scale::Uniform(1.5),
            matrix: None,
        };
        assert_eq!(open.interpolate(&close, 0.0), open.matrix());
        let end = open.interpolate(&close, 1.0);
        assert!(
            end.abs_diff_eq(close.matrix(), 1e-5),
            "{end} {}",
            close.matrix()
        );
    }

    #[test]
    fn motion_maps_open_to_close_positions() {
        let open = Transform {
            translate: Vec3::new(1.0, 0.0, 0.0),
            ..Transform::default()
        };
        let close = Transform {
            translate: Vec3::new(1.0, 3.0, 0.0),
            rotate_degrees: Vec3::new(0.0, 0.0, 90.0),
            scale: crate::scene::Scale::Uniform(2.0),
            matrix: None,
        };
        let motion = ObjectMotion::new(open.matrix(), close.matrix()).unwrap();
        let model = Vec3::new(0.5, -0.25, 2.0);
        let at_open = open.matrix().transform_point3(model);
        let at_close = close.matrix().transform_point3(model);
        assert!(motion.close(at_open).abs_diff_eq(at_close, 1e-5));
        assert!(motion.stretch >= 2.0);
        assert!(ObjectMotion::new(open.matrix(), open.matrix()).is_none());
    }

    /// A camera at a random pose (fov 50 degrees, 200x150) and its view.
    fn random_camera(rng: &mut rand::rngs::StdRng) -> Camera {
        let eye = random_vec3(rng, 10.0);
        let target = eye + random_vec3(rng, 5.0) + Vec3::splat(0.5);
        Camera::new(
            eye,
            target,
            Vec3::Z,
            50f32.to_radians(),
            200,
            150,
            0.1,
            100.0,
        )
    }

    /// What the camera at close sees, the camera at open sees at the
    /// camera motion's image of the point: the same clip coordinates.
    #[test]
    fn camera_motion_shows_the_close_view_through_the_open_camera() {
        let (seed, mut rng) =
            fresh_rng("camera_motion_shows_the_close_view_through_the_open_camera");
        for _ in 0..50 {
            let open = random_camera(&mut rng);
            let close = random_camera(&mut rng);
            let motion = camera_motion(open.view, close.view).expect("the views differ");
            for _ in 0..10 {
                let p = close.target + random_vec3(&mut rng, 2.0);
                let seen_at_close = close.to_clip(p);
                let seen_from_open = open.to_clip(motion.transform_point3(p));
                assert!(
                    seen_from_open.abs_diff_eq(seen_at_close, 1e-3 * (1.0 + seen_at_close.w.abs())),
                    "seed {seed}: {seen_from_open} {seen_at_close}"
                );
            }
        }
        let still = random_camera(&mut rng);
        assert_eq!(camera_motion(still.view, still.view), None);
    }

    /// The view in between is a rigid camera with the eye on the line and
    /// the orientation on the great arc between the two; both ends are exact.
    #[test]
    fn interpolated_views_move_the_eye_linearly_and_stay_rigid() {
        let (seed, mut rng) = fresh_rng("interpolated_views_move_the_eye_linearly_and_stay_rigid");
        for _ in 0..50 {
            let (open, close) = (random_camera(&mut rng), random_camera(&mut rng));
            assert_eq!(interpolate_view(open.view, close.view, 0.0), open.view);
            assert_eq!(interpolate_view(open.view, close.view, 1.0), close.view);
            let t = 0.25;
            let view = interpolate_view(open.view, close.view, t);
            let placement = view.inverse();
            let eye = placement.w_axis.truncate();
            let want = open.eye.lerp(close.eye, t);
            assert!(
                eye.abs_diff_eq(want, 1e-3 * (1.0 + want.length())),
                "seed {seed}: {eye} {want}"
            );
            for axis in [placement.x_axis, placement.y_axis, placement.z_axis] {
                assert!((axis.truncate().length() - 1.0).abs() < 1e-4, "seed {seed}");
            }
            // The camera turns by t of the whole rotation, about the same axis.
            let orientation = |v: Mat4| glam::Quat::from_mat4(&v.inverse());
            let whole = orientation(open.view).angle_between(orientation(close.view));
            let part = orientation(open.view).angle_between(orientation(view));
            let rest = orientation(view).angle_between(orientation(close.view));
            assert!(
                (part - whole * t).abs() < 1e-3,
                "seed {seed}: {part} of {whole}"
            );
            assert!(
                (part + rest - whole).abs() < 1e-3,
                "seed {seed}: off the arc"
            );
        }
    }

    #[test]
    fn coc_vanishes_on_the_focal_plane_and_changes_sign_across_it() {
        let camera = crate::camera::tests::camera();
        let lens = PreparedLens::new(&camera, 0.5, None);
        assert_eq!(lens.focus, 10.0);
        assert_eq!(lens.coc(10.0), 0.0);
        assert!(lens.coc(5.0) < 0.0 && lens.coc(20.0) > 0.0);
        // Far away the blur tends to aperture / focus * pixel_scale.
        let limit = 0.5 / 10.0 * lens.pixel_scale;
        assert!((lens.coc(1e6) - limit).abs() < 1e-3 * limit);
        assert_eq!(PreparedLens::new(&camera, 0.0, None).coc(3.0), 0.0);
    }

    /// The lens shift on screen, measured by projecting through a shifted,
    /// sheared pinhole, is `l * coc(w)` and at most the world shift the
    /// bound test assumes.
    #[test]
    fn coc_matches_a_pinhole_at_the_lens_position() {
        let camera = Camera::new(
            Vec3::new(0.0, -10.0, 0.0),
            Vec3::ZERO,
            Vec3::Z,
            50f32.to_radians(),
            160,
            120,
            0.5,
            100.0,
        );
        let lens = PreparedLens::new(&camera, 0.3, Some(8.0));
        for (p, l) in [
            (Vec3::new(0.5, -4.0, 0.2), 1.0f32),
            (Vec3::new(-1.0, 5.0, 0.7), -0.6),
            (Vec3::new(0.0, -2.0, 0.0), 0.25),
        ] {
            let clip = camera.to_clip(p);
            let w = clip.w;
            // Camera x is world +x here. Seen from lens point L = (l * aperture, 0)
            // with the focal plane fixed: x/w - L/w + L/focus.
            let shift_ndc = l * lens.aperture * (1.0 / lens.focus - 1.0 / w) * camera.proj.x_axis.x;
            let shift_px = shift_ndc * 0.5 * camera.width as f32;
            assert!(
                (shift_px - l * lens.coc(w)).abs() < 1e-3,
                "{shift_px} {}",
                l * lens.coc(w)
            );
            let world = (l * lens.aperture * (w / lens.focus - 1.0)).abs();
            assert!(world <= lens.world_shift(w, 0.0) * 1.0001 + 1e-6);
        }
    }
}
