//! The scene's camera as written: the lens, the camera at shutter open and
//! its pose at close, and the [`Camera`] they describe.

use glam::{Quat, Vec3};
use serde::{Deserialize, Serialize};

use crate::camera::{Camera, Projection};

use super::defaults::{default_far, default_fov, default_near, default_up};

/// The thin lens of the camera (`[lens]`): depth of field.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Lens {
    /// Lens radius in world units, >= 0 (default 0: a pinhole, everything sharp).
    pub aperture: f32,
    /// Distance from the eye, along the view direction, of the plane in
    /// focus, > 0 (default: the distance from the eye to the camera target).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub focus_distance: Option<f32>,
}

/// The camera of a scene (`[camera]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up direction (default +z).
    #[serde(default = "default_up")]
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180) (default 40).
    #[serde(default = "default_fov")]
    pub fov_y_degrees: f32,
    /// Near plane distance, > 0 (default 0.1).
    #[serde(default = "default_near")]
    pub near: f32,
    /// Far plane distance, > near (default 1000).
    #[serde(default = "default_far")]
    pub far: f32,
    /// `"perspective"` (default, with `fov_y_degrees`) or `"orthographic"`
    /// (with `ortho_height`).
    #[serde(default, skip_serializing_if = "Projection::is_perspective")]
    pub projection: Projection,
    /// An orthographic view's height in world units, > 0. Default: the
    /// height the perspective field of view shows at the target,
    /// `2 |target - eye| tan(fov_y / 2)`, so that switching the projection
    /// keeps the target's plane framed the same.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ortho_height: Option<f32>,
}

/// The camera's pose at shutter close (`[camera_close]`): camera motion.
/// The field of view and the clipping planes stay those of `[camera]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraPose {
    /// Eye position at shutter close.
    pub eye: Vec3,
    /// Point looked at at shutter close.
    pub target: Vec3,
    /// Up direction at shutter close (default: the `[camera]`'s up).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<Vec3>,
}

impl CameraDesc {
    /// The camera this description makes for an image of `width x height`.
    pub fn camera(&self, width: u32, height: u32) -> Camera {
        let camera = Camera::new(
            self.eye,
            self.target,
            self.up,
            self.fov_y_degrees.to_radians(),
            width,
            height,
            self.near,
            self.far,
        );
        match self.projection {
            Projection::Perspective => camera,
            Projection::Orthographic => camera.orthographic(self.view_height()),
        }
    }

    /// The orthographic view height: `ortho_height`, or its default (the
    /// field of view's height at the target).
    pub fn view_height(&self) -> f32 {
        self.ortho_height.unwrap_or_else(|| {
            2.0 * self.eye.distance(self.target) * (0.5 * self.fov_y_degrees.to_radians()).tan()
        })
    }

    /// This camera's pose at shutter close after it moves by `by` and pans
    /// by `pan_degrees` about its up axis through the (moved) eye; a
    /// positive pan turns the view counterclockwise seen from above, so
    /// the scene sweeps to the right across the image. The up direction
    /// stays the same.
    pub fn moved(&self, by: Vec3, pan_degrees: f32) -> CameraPose {
        let pan = Quat::from_axis_angle(self.up.normalize_or_zero(), pan_degrees.to_radians());
        let eye = self.eye + by;
        CameraPose {
            eye,
            target: eye + pan * (self.target - self.eye),
            up: None,
        }
    }

    /// The travel direction of a light coming from over the camera's left
    /// shoulder (above and to the left of the eye, as seen from the eye).
    pub fn shoulder_light_direction(&self) -> Vec3 {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        (forward + right * 0.6 - up * 0.8).normalize()
    }
}
