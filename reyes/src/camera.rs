//! The pinhole (or orthographic) camera and the coordinate conventions of
//! the renderer.
//!
//! * World space is right-handed; the bundled models are z-up.
//! * View: [`Mat4::look_at_rh`]`(eye, target, up)`: the camera looks down its -z axis.
//! * Projection: [`Mat4::perspective_rh`]`(fov_y, width / height, near, far)`,
//!   which maps depth to NDC z in `[0, 1]` (the wgpu/D3D/Vulkan convention):
//!   z = 0 on the near plane, z = 1 on the far plane. An orthographic camera
//!   uses [`Mat4::orthographic_rh`] (the same depth range, clip `w = 1`)
//!   over a view `ortho_height` world units high.
//! * Pixels: `px = (ndc.x * 0.5 + 0.5) * width`, `py = (0.5 - ndc.y * 0.5) * height`.
//!   Pixel `(0, 0)` is the top-left pixel, x grows right, y grows *down*;
//!   pixel `(x, y)` covers `[x, x + 1) x [y, y + 1)`, so its centre is at
//!   `(x + 0.5, y + 0.5)`.

use glam::{Mat4, Vec3, Vec4};
use serde::{Deserialize, Serialize};

/// How a camera projects (`[camera] projection`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Projection {
    /// A pinhole: the field of view `fov_y`.
    #[default]
    Perspective,
    /// Parallel rays along the view direction, over `ortho_height` world
    /// units of view height (RenderMan's `Projection "orthographic"`).
    Orthographic,
}

impl Projection {
    /// Whether this is the default, perspective.
    pub fn is_perspective(&self) -> bool {
        *self == Projection::Perspective
    }
}

/// The part of the eye that shading and culling use, in homogeneous form:
/// `(eye, 1)` for a perspective camera, `(d, 0)` for an orthographic one,
/// `d` the unit direction towards the viewer. [`towards_eye`] is the
/// direction from a point towards the viewer in both cases.
pub type HomogeneousEye = Vec4;

/// The (unnormalized) direction from `position` towards the viewer
/// `eye` ([`Camera::homogeneous_eye`]): `eye.xyz - position * eye.w`, which
/// is exactly `eye - position` for a perspective camera. The WGSL
/// `towards_eye` mirrors it.
pub fn towards_eye(eye: HomogeneousEye, position: Vec3) -> Vec3 {
    eye.truncate() - position * eye.w
}

/// Why an eye, target and up direction (all finite) cannot make a view in
/// `f32` ([`pose_problem`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PoseProblem {
    /// The eye and the target are the same point.
    Coincident,
    /// The eye's squared length overflows `f32` (a coordinate beyond about
    /// 1e19), so view-space math overflows.
    EyeTooLarge,
    /// The target's squared length overflows `f32`.
    TargetTooLarge,
    /// The squared distance from the eye to the target overflows `f32`: the
    /// view direction cannot be normalized.
    TooFarApart,
    /// The squared distance from the eye to the target underflows `f32`'s
    /// normal range although they differ: the view direction cannot be
    /// normalized.
    TooClose,
    /// `up` is zero or parallel to the view direction.
    UpParallel,
}

impl PoseProblem {
    /// What is wrong, naming the fields of the pose as `{table}.eye`,
    /// `{table}.target` and `{table}.up` (e.g. `table = "camera"`).
    pub fn reason(self, table: &str) -> String {
        let (eye, target, up) = (
            format!("{table}.eye"),
            format!("{table}.target"),
            format!("{table}.up"),
        );
        match self {
            PoseProblem::Coincident => format!("{eye} and {target} must differ"),
            PoseProblem::EyeTooLarge => format!(
                "{eye} is too large: its squared length overflows f32; keep its coordinates below about 1e19 (move the scene closer to the origin)"
            ),
            PoseProblem::TargetTooLarge => format!(
                "{target} is too large: its squared length overflows f32; keep its coordinates below about 1e19 (move the scene closer to the origin)"
            ),
            PoseProblem::TooFarApart => format!(
                "{eye} and {target} are too far apart: the squared distance between them overflows f32, so the view direction cannot be computed; keep them within about 1e19 of each other"
            ),
            PoseProblem::TooClose => format!(
                "{eye} and {target} are too close together: the squared distance between them underflows f32, so the view direction cannot be computed; move them further apart (or scale the scene up)"
            ),
            PoseProblem::UpParallel => {
                format!("{up} must be non-zero and not parallel to the view direction")
            }
        }
    }
}

/// `v` scaled to unit length without overflow or underflow in the squared
/// length (zero for a zero vector).
pub fn unit(v: Vec3) -> Vec3 {
    let m = v.abs().max_element();
    if m > 0.0 && m.is_finite() {
        (v / m).normalize_or_zero()
    } else {
        Vec3::ZERO
    }
}

/// What keeps a finite `eye`, `target` and `up` from making a view in
/// `f32`, if anything: the view direction and `up` must be normalizable and
/// not parallel, and the squared lengths used by the view math must fit.
pub fn pose_problem(eye: Vec3, target: Vec3, up: Vec3) -> Option<PoseProblem> {
    if eye == target {
        return Some(PoseProblem::Coincident);
    }
    if !eye.length_squared().is_finite() {
        return Some(PoseProblem::EyeTooLarge);
    }
    if !target.length_squared().is_finite() {
        return Some(PoseProblem::TargetTooLarge);
    }
    let along = target - eye;
    let squared = along.length_squared();
    if !squared.is_finite() {
        return Some(PoseProblem::TooFarApart);
    }
    if squared < f32::MIN_POSITIVE {
        return Some(PoseProblem::TooClose);
    }
    if along.normalize().cross(unit(up)).length_squared() < 1e-12 {
        return Some(PoseProblem::UpParallel);
    }
    None
}

/// A perspective or orthographic camera for an image of `width x height`
/// pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// How it projects; [`Camera::new`] makes a perspective camera and
    /// [`Camera::orthographic`] turns it into an orthographic one.
    pub projection: Projection,
    /// The view's height in world units (orthographic cameras only).
    pub ortho_height: f32,
    /// Eye position (world space).
    pub eye: Vec3,
    /// Point looked at (world space).
    pub target: Vec3,
    /// Up direction (world space); need not be orthogonal to the view direction.
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub fov_y_radians: f32,
    /// Near plane distance (> 0).
    pub near: f32,
    /// Far plane distance (> near).
    pub far: f32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// World-to-view matrix.
    pub view: Mat4,
    /// View-to-clip matrix.
    pub proj: Mat4,
    /// Where this image's pixel (0, 0) lies in the full image: (0, 0)
    /// unless the camera is a [`Camera::crop`] of a larger one. Sampling
    /// hashes absolute pixel coordinates, so a tile samples exactly like
    /// the same pixels of the whole frame.
    pub origin: [u32; 2],
}

impl Camera {
    /// Builds a camera. The caller is responsible for sensible values (the
    /// scene validation checks them: `near > 0`, `far > near`, fov in (0, pi),
    /// `eye != target`, `up` not parallel to the view direction).
    #[allow(
        clippy::too_many_arguments,
        reason = "a camera is exactly these eight independent quantities"
    )]
    pub fn new(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_radians: f32,
        width: u32,
        height: u32,
        near: f32,
        far: f32,
    ) -> Camera {
        let aspect = width as f32 / height as f32;
        // An up direction of extreme length is scaled to unit length first,
        // so that the view's cross products neither overflow nor underflow
        // (ordinary ones are used as given, which keeps their views exact).
        let view_up = if (1e-6..=1e6).contains(&up.length_squared()) {
            up
        } else {
            unit(up)
        };
        Camera {
            projection: Projection::Perspective,
            ortho_height: 0.0,
            eye,
            target,
            up,
            fov_y_radians,
            near,
            far,
            width,
            height,
            view: Mat4::look_at_rh(eye, target, view_up),
            proj: Mat4::perspective_rh(fov_y_radians, aspect, near, far),
            origin: [0, 0],
        }
    }

    /// The same camera (lens, image, crop) placed at another pose: looking
    /// from `eye` at `target` with `up`.
    pub fn looking(&self, eye: Vec3, target: Vec3, up: Vec3) -> Camera {
        let placed = Camera {
            origin: self.origin,
            ..Camera::new(
                eye,
                target,
                up,
                self.fov_y_radians,
                self.width,
                self.height,
                self.near,
                self.far,
            )
        };
        match self.projection {
            Projection::Perspective => placed,
            Projection::Orthographic => placed.orthographic(self.ortho_height),
        }
    }

    /// The same camera with an orthographic projection over a view
    /// `height` world units high (and `height * width / height_px` wide),
    /// between the same near and far planes.
    pub fn orthographic(&self, height: f32) -> Camera {
        let half_h = 0.5 * height;
        let half_w = half_h * self.width as f32 / self.height as f32;
        Camera {
            projection: Projection::Orthographic,
            ortho_height: height,
            proj: Mat4::orthographic_rh(-half_w, half_w, -half_h, half_h, self.near, self.far),
            ..*self
        }
    }

    /// The eye in the homogeneous form shading and culling use
    /// ([`HomogeneousEye`]).
    pub fn homogeneous_eye(&self) -> HomogeneousEye {
        match self.projection {
            Projection::Perspective => self.eye.extend(1.0),
            Projection::Orthographic => (self.eye - self.target).normalize().extend(0.0),
        }
    }

    /// The direction from `position` towards the viewer ([`towards_eye`]).
    pub fn towards_eye(&self, position: Vec3) -> Vec3 {
        towards_eye(self.homogeneous_eye(), position)
    }

    /// What makes this camera's matrices unusable, if anything: the view,
    /// the projection or their product (the world-to-clip matrix) has a
    /// non-finite entry. A pose that passes [`pose_problem`] has a finite
    /// view; extreme `near`/`far` planes far from the origin can still
    /// overflow the product.
    pub fn matrix_problem(&self) -> Option<&'static str> {
        if !self.view.is_finite() {
            Some("the view matrix (from eye, target and up) is not finite in f32")
        } else if !self.proj.is_finite() {
            Some(
                "the projection matrix (from fov, near, far and the aspect ratio) is not finite in f32",
            )
        } else if !self.view_proj().is_finite() {
            Some(
                "the world-to-clip matrix overflows f32: near and far (or the eye) are too large; bring the scene closer to the origin or lower near and far",
            )
        } else {
            None
        }
    }

    /// World-to-clip matrix: `proj * view`.
    pub fn view_proj(&self) -> Mat4 {
        self.proj * self.view
    }

    /// How far each clip coordinate can move per world unit: component `r`
    /// is the length of `(m[0][r], m[1][r], m[2][r])`, the linear part of
    /// row `r` of [`Camera::view_proj`]. A world-space ball of radius `b`
    /// around a point with clip coordinates `c` lies within `c +- b * clip_pad()`
    /// in every clip coordinate (Cauchy-Schwarz), which is how the bound test
    /// grows control points by a displacement bound.
    pub fn clip_pad(&self) -> Vec4 {
        let m = self.view_proj();
        let row = |r: usize| Vec3::new(m.x_axis[r], m.y_axis[r], m.z_axis[r]).length();
        Vec4::new(row(0), row(1), row(2), row(3))
    }

    /// Transforms a world-space point to clip space: `view_proj * (p, 1)`.
    pub fn to_clip(&self, p: Vec3) -> Vec4 {
        self.view_proj() * p.extend(1.0)
    }

    /// The camera whose image is the sub-rectangle `[x0, x0 + width) x [y0,
    /// y0 + height)` of this camera's image, at the same pixel scale: a point
    /// at pixel `(px, py)` here is at `(px - x0, py - y0)` in the cropped
    /// camera, with the same depth.
    ///
    /// The projection is post-multiplied by a clip-space scale and translate
    /// of x and y only. Clip `w` (the view depth) and `z` are untouched, so
    /// NDC depth, the near/far tests and the key depths stay the same; the
    /// cropped frustum's side planes are those of the tile. From the pixel
    /// convention, `ndc'.x = ndc.x * W / w + (W - 2 x0 - w) / w` and
    /// `ndc'.y = ndc.y * H / h + (h - H + 2 y0) / h`, which is that map
    /// applied to `clip.x / clip.w` and `clip.y / clip.w`.
    ///
    /// The rectangle may reach beyond the image (it is a frustum, not a
    /// copy of pixels); a `width` or `height` of 0 is taken as 1.
    pub fn crop(&self, x0: u32, y0: u32, width: u32, height: u32) -> Camera {
        let (full_w, full_h) = (self.width as f32, self.height as f32);
        let (w, h) = (width.max(1) as f32, height.max(1) as f32);
        let (x0, y0) = (x0 as f32, y0 as f32);
        let crop = Mat4::from_cols(
            Vec4::new(full_w / w, 0.0, 0.0, 0.0),
            Vec4::new(0.0, full_h / h, 0.0, 0.0),
            Vec4::Z,
            Vec4::new(
                (full_w - 2.0 * x0 - w) / w,
                (h - full_h + 2.0 * y0) / h,
                0.0,
                1.0,
            ),
        );
        Camera {
            width: width.max(1),
            height: height.max(1),
            proj: crop * self.proj,
            origin: [self.origin[0] + x0 as u32, self.origin[1] + y0 as u32],
            ..*self
        }
    }

    /// Converts a clip-space position to `(px, py, depth)`: pixel coordinates
    /// (top-left origin, y down) and NDC depth in `[0, 1]` for points between
    /// the near and far planes. Only meaningful for `clip.w > 0`.
    pub fn to_pixel(&self, clip: Vec4) -> Vec3 {
        let ndc = clip.truncate() / clip.w;
        Vec3::new(
            (ndc.x * 0.5 + 0.5) * self.width as f32,
            (0.5 - ndc.y * 0.5) * self.height as f32,
            ndc.z,
        )
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A 200 x 100 camera 10 units in front of the origin, z up (shared
    /// with other modules' tests).
    pub(crate) fn camera() -> Camera {
        Camera::new(
            Vec3::new(0.0, -10.0, 0.0),
            Vec3::ZERO,
            Vec3::Z,
            60f32.to_radians(),
            200,
            100,
            1.0,
            100.0,
        )
    }

    /// Orthographic: a point's pixel depends on its offset across the view
    /// only, by the worked formula `px = W/2 + x * W / width_world`, and
    /// not on its depth; depth still runs from 0 (near) to 1 (far).
    #[test]
    fn an_orthographic_camera_projects_parallel_to_the_view() {
        // Looking down -y from y = -10 at the origin, z up; 200 x 100
        // pixels over a view 4 units high (8 wide).
        let ortho = camera().orthographic(4.0);
        for depth in [-5.0, 0.0, 20.0] {
            let p = Vec3::new(1.0, depth, 0.5);
            let px = ortho.to_pixel(ortho.to_clip(p));
            // x right is +x (the eye looks along +y with z up).
            assert!((px.x - (100.0 + 1.0 * 200.0 / 8.0)).abs() < 1e-3, "{px}");
            assert!((px.y - (50.0 - 0.5 * 100.0 / 4.0)).abs() < 1e-3, "{px}");
        }
        let near = ortho.to_pixel(ortho.to_clip(Vec3::new(0.0, -9.0, 0.0)));
        let far = ortho.to_pixel(ortho.to_clip(Vec3::new(0.0, 90.0, 0.0)));
        assert!(
            near.z.abs() < 1e-5 && (far.z - 1.0).abs() < 1e-5,
            "{near} {far}"
        );
        // The viewer is a direction: towards -y from everywhere.
        assert_eq!(ortho.homogeneous_eye(), Vec4::new(0.0, -1.0, 0.0, 0.0));
        assert_eq!(
            ortho.towards_eye(Vec3::new(3.0, 7.0, -2.0)),
            Vec3::new(0.0, -1.0, 0.0)
        );
        // Perspective: exactly eye - p.
        let p = Vec3::new(0.3, 1.7, -2.9);
        assert_eq!(camera().towards_eye(p), camera().eye - p);
        // A moved orthographic camera stays orthographic.
        let moved = ortho.looking(Vec3::new(0.0, -20.0, 0.0), Vec3::ZERO, Vec3::Z);
        assert_eq!(moved.projection, Projection::Orthographic);
        assert_eq!(moved.proj, ortho.proj);
    }

    #[test]
    fn target_projects_to_image_centre() {
        let cam = camera();
        let p = cam.to_pixel(cam.to_clip(Vec3::ZERO));
        assert!(
            (p.x - 100.0).abs() < 1e-4 && (p.y - 50.0).abs() < 1e-4,
            "{p}"
        );
        assert!(p.z > 0.0 && p.z < 1.0);
    }

    #[test]
    fn clip_pad_bounds_the_clip_motion_of_a_ball() {
        let cam = camera();
        let pad = cam.clip_pad();
        let centre = Vec3::new(0.3, 1.0, -0.2);
        let c = cam.to_clip(centre);
        for k in 0..200 {
            let a = k as f32 * 0.731;
            let b = k as f32 * 0.377;
            let offset = Vec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos()) * 0.5;
            let moved = cam.to_clip(centre + offset);
            let delta = (moved - c).abs();
            assert!(
                delta.cmple(pad * 0.5 * 1.0001 + 1e-6).all(),
                "{delta} {pad}"
            );
        }
    }

    /// A small deterministic generator for the crop tests (xorshift64*).
    struct Random(u64);

    impl Random {
        /// Uniform in `[lo, hi)`.
        fn range(&mut self, lo: f32, hi: f32) -> f32 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40;
            lo + (hi - lo) * (bits as f32 / (1u64 << 24) as f32)
        }
    }

    /// The crops exercised: the whole image, aligned bands and tiles, a
    /// partial edge tile, an odd-sized tile, and one reaching past the image.
    const CROPS: [(u32, u32, u32, u32); 6] = [
        (0, 0, 200, 100),
        (0, 64, 200, 36),
        (64, 0, 64, 64),
        (128, 64, 72, 36),
        (13, 7, 101, 53),
        (192, 64, 64, 64),
    ];

    #[test]
    fn crop_shifts_pixels_by_the_origin() {
        let cam = camera();
        let mut random = Random(0x9e37_79b9_7f4a_7c15);
        for &(x0, y0, w, h) in &CROPS {
            let crop = cam.crop(x0, y0, w, h);
            assert_eq!((crop.width, crop.height), (w, h));
            assert_eq!(
                (crop.eye, crop.target, crop.up, crop.view),
                (cam.eye, cam.target, cam.up, cam.view)
            );
            for _ in 0..500 {
                // Points in front of the camera, inside and well outside its frustum.
                let p = Vec3::new(
                    random.range(-12.0, 12.0),
                    random.range(-8.0, 60.0),
                    random.range(-8.0, 8.0),
                );
                let (full, tile) = (cam.to_clip(p), crop.to_clip(p));
                assert!(full.w > 0.5, "{p} is not in front of the camera");
                assert_eq!(tile.w, full.w, "crop changed w at {p}");
                let (a, b) = (cam.to_pixel(full), crop.to_pixel(tile));
                let expected = Vec3::new(a.x - x0 as f32, a.y - y0 as f32, a.z);
                // Float rounding, relative to the pixel magnitudes involved.
                let tolerance = 1e-5 * (1.0 + a.x.abs().max(a.y.abs()) + 200.0);
                assert!(
                    (b - expected).abs().cmple(Vec3::splat(tolerance)).all(),
                    "crop {:?}: {p} at {b}, expected {expected}",
                    (x0, y0, w, h)
                );
                assert_eq!(b.z, a.z, "crop changed the depth of {p}");
            }
        }
    }

    #[test]
    fn clip_pad_bounds_the_clip_motion_of_a_ball_in_a_crop() {
        let cam = camera();
        let mut random = Random(0x2545_f491_4f6c_dd1d);
        for &(x0, y0, w, h) in &CROPS {
            let crop = cam.crop(x0, y0, w, h);
            let pad = crop.clip_pad();
            for _ in 0..50 {
                let centre = Vec3::new(
                    random.range(-3.0, 3.0),
                    random.range(-3.0, 10.0),
                    random.range(-3.0, 3.0),
                );
                let radius = random.range(0.01, 2.0);
                let c = crop.to_clip(centre);
                for k in 0..100 {
                    let a = k as f32 * 0.731;
                    let b = k as f32 * 0.377;
                    let offset = Vec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos()) * radius;
                    let delta = (crop.to_clip(centre + offset) - c).abs();
                    let bound =
                        pad * radius * 1.0001 + Vec4::splat(1e-4 * (1.0 + c.abs().max_element()));
                    assert!(
                        delta.cmple(bound).all(),
                        "crop {:?}: {delta} {pad}",
                        (x0, y0, w, h)
                    );
                }
            }
        }
    }

    #[test]
    fn axes_and_depth_conventions() {
        let cam = camera();
        // +x is to the right when looking along +y with z up; +z is up (smaller py).
        let right = cam.to_pixel(cam.to_clip(Vec3::new(1.0, 0.0, 0.0)));
        let up = cam.to_pixel(cam.to_clip(Vec3::new(0.0, 0.0, 1.0)));
        assert!(right.x > 100.0);
        assert!(up.y < 50.0);
        let near = cam.to_pixel(cam.to_clip(Vec3::new(0.0, -9.0, 0.0)));
        let far = cam.to_pixel(cam.to_clip(Vec3::new(0.0, 90.0, 0.0)));
        assert!(near.z.abs() < 1e-6, "{}", near.z);
        assert!((far.z - 1.0).abs() < 1e-5, "{}", far.z);
    }
}
