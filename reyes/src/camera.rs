//! The pinhole camera and the coordinate conventions of the renderer.
//!
//! * World space is right-handed; the bundled models are z-up.
//! * View: [`Mat4::look_at_rh`]`(eye, target, up)`: the camera looks down its -z axis.
//! * Projection: [`Mat4::perspective_rh`]`(fov_y, width / height, near, far)`,
//!   which maps depth to NDC z in `[0, 1]` (the wgpu/D3D/Vulkan convention):
//!   z = 0 on the near plane, z = 1 on the far plane.
//! * Pixels: `px = (ndc.x * 0.5 + 0.5) * width`, `py = (0.5 - ndc.y * 0.5) * height`.
//!   Pixel `(0, 0)` is the top-left pixel, x grows right, y grows *down*;
//!   pixel `(x, y)` covers `[x, x + 1) x [y, y + 1)`, so its centre is at
//!   `(x + 0.5, y + 0.5)`.

use glam::{Mat4, Vec3, Vec4};

/// A perspective camera for an image of `width x height` pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
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
        Camera {
            eye,
            target,
            up,
            fov_y_radians,
            near,
            far,
            width,
            height,
            view: Mat4::look_at_rh(eye, target, up),
            proj: Mat4::perspective_rh(fov_y_radians, aspect, near, far),
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
mod tests {
    use super::*;

    fn camera() -> Camera {
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
