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

//!
//! Whether a pose (eye, target, up) makes a view in `f32` at all is
//! answered in `pose` ([`pose_problem`]), re-exported here.

use glam::{Mat4, Vec3, Vec4};
use serde::{Deserialize, Serialize};

mod pose;

#[cfg(test)]
pub(crate) mod tests;

pub use pose::{PoseProblem, pose_problem, unit};

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
    /// Width in pixels of the full image: `width` unless the camera is a
    /// [`Camera::crop`] of a larger one. Interleave UVT numbers its tiles
    /// along the rows of the full image.
    pub full_width: u32,
    /// Height in pixels of the full image: `height` unless the camera is a
    /// [`Camera::crop`] of a larger one.
    pub full_height: u32,
}

impl Camera {
    /// Builds a camera. The caller is responsible for sensible values (the
    /// scene validation checks them: `near > 0`, `far > near`, fov in (0, pi),
    /// `eye != target`, `up` not parallel to the view direction).
    #[expect(
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
            full_width: width,
            full_height: height,
        }
    }

    /// The same camera (lens, image, crop) placed at another pose: looking
    /// from `eye` at `target` with `up`.
    pub fn looking(&self, eye: Vec3, target: Vec3, up: Vec3) -> Camera {
        let placed = Camera {
            width: self.width,
            height: self.height,
            origin: self.origin,
            ..Camera::new(
                eye,
                target,
                up,
                self.fov_y_radians,
                self.full_width,
                self.full_height,
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
        let half_w = half_h * self.full_width as f32 / self.full_height as f32;
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
    /// y0 + height)` of this camera's image (a screen tile): a point at
    /// pixel `(px, py)` here is at `(px - x0, py - y0)` in the cropped
    /// camera, with the same depth.
    ///
    /// The projection stays the full image's: every pixel position is
    /// computed in the full image and then shifted by the tile's origin (an
    /// exact subtraction of integers), so that a tile decides splits,
    /// dicing and sample positions bit for bit as the whole frame does.
    /// Only culling looks at the tile's own frustum, through
    /// [`Camera::window`].
    ///
    /// The rectangle may reach beyond the image (it is a frustum, not a
    /// copy of pixels); a `width` or `height` of 0 is taken as 1.
    pub fn crop(&self, x0: u32, y0: u32, width: u32, height: u32) -> Camera {
        Camera {
            width: width.max(1),
            height: height.max(1),
            origin: [self.origin[0] + x0, self.origin[1] + y0],
            ..*self
        }
    }

    /// The clip-space scale and translate `(sx, sy, tx, ty)` that takes the
    /// full image's clip coordinates to this camera's window (a
    /// [`Camera::crop`]'s tile): `x' = sx x + tx w`, `y' = sy y + ty w`, `z`
    /// and `w` unchanged, so the window's frustum is `-w' <= x', y' <= w'`.
    /// From the pixel convention, `ndc'.x = ndc.x W / w + (W - 2 x0 - w) / w`
    /// and `ndc'.y = ndc.y H / h + (h - H + 2 y0) / h` (`W x H` the full
    /// image, `w x h` the window at `(x0, y0)`). `(1, 1, 0, 0)` for an
    /// uncropped camera.
    pub fn window(&self) -> Vec4 {
        let (full_w, full_h) = (self.full_width as f32, self.full_height as f32);
        let (w, h) = (self.width as f32, self.height as f32);
        let (x0, y0) = (self.origin[0] as f32, self.origin[1] as f32);
        Vec4::new(
            full_w / w,
            full_h / h,
            (full_w - 2.0 * x0 - w) / w,
            (h - full_h + 2.0 * y0) / h,
        )
    }

    /// Clip position `c` of the full image in this camera's window
    /// ([`Camera::window`]), for culling.
    pub fn window_clip(&self, c: Vec4) -> Vec4 {
        let s = self.window();
        Vec4::new(s.x * c.x + s.z * c.w, s.y * c.y + s.w * c.w, c.z, c.w)
    }

    /// Converts a clip-space position to `(px, py, depth)`: pixel coordinates
    /// (top-left origin, y down) and NDC depth in `[0, 1]` for points between
    /// the near and far planes. Only meaningful for `clip.w > 0`.
    pub fn to_pixel(&self, clip: Vec4) -> Vec3 {
        let ndc = clip.truncate() / clip.w;
        // In the full image, then shifted to this camera's window (an
        // integer subtracted: exact for the pixels of the window).
        Vec3::new(
            (ndc.x * 0.5 + 0.5) * self.full_width as f32 - self.origin[0] as f32,
            (0.5 - ndc.y * 0.5) * self.full_height as f32 - self.origin[1] as f32,
            ndc.z,
        )
    }
}
