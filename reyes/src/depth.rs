//! The depth output ([`crate::Aov::Z`], RIB `Display "x.z" "zfile" "z"`):
//! per pixel the camera-space depth of the nearest surface, the distance
//! along the camera's view axis, as 32-bit floats, [`NO_SURFACE`] (+inf)
//! where no sample of the pixel is covered. Shadow maps are made from it.
//!
//! The sample framebuffer keeps, per sample, the NDC depth of the nearest
//! surface (the key's high word, `crate::color::key_depth`); the depth
//! resolve turns it back into camera-space depth ([`DepthProjection`]) and
//! takes the [`DepthFilter`] over the pixel's own samples (no pixel filter:
//! a shadow map must not blend the depths of surfaces at different
//! distances). For [`DepthFilter::Midpoint`] only, the framebuffer keeps a
//! second layer of keys, each sample's second-nearest
//! ([`crate::prepare::PreparedScene::keeps_second_depth`]).

use image::{Rgba, Rgba32FImage};
use serde::{Deserialize, Serialize};

use crate::camera::Camera;

/// The depth of a pixel no surface covers.
pub const NO_SURFACE: f32 = f32::INFINITY;

/// How a pixel's depth is made from its samples' (RenderMan's `Hider
/// "hidden" "depthfilter"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum DepthFilter {
    /// The minimum over the pixel's samples of the nearest surface's depth
    /// (default).
    #[default]
    Min,
    /// Per sample the mean of the nearest and the second-nearest surface's
    /// depths (+inf where a single surface covers it: nothing behind it to
    /// shadow), then the minimum over the pixel's samples. A shadow map of
    /// midpoints keeps the lit surfaces in front of it, so they do not
    /// shadow themselves.
    Midpoint,
    /// The maximum over the pixel's samples of the nearest surface's depth.
    Max,
    /// The mean over the pixel's covered samples of the nearest surface's
    /// depth (a pixel on a silhouette mixes the two surfaces' depths).
    Average,
}

impl DepthFilter {
    /// Every filter, in a fixed order.
    pub const ALL: [DepthFilter; 4] = [
        DepthFilter::Min,
        DepthFilter::Midpoint,
        DepthFilter::Max,
        DepthFilter::Average,
    ];

    /// Its name in scene files and in RIB.
    pub fn name(self) -> &'static str {
        match self {
            DepthFilter::Min => "min",
            DepthFilter::Midpoint => "midpoint",
            DepthFilter::Max => "max",
            DepthFilter::Average => "average",
        }
    }

    /// The filter named `name` (as RIB spells it), if any.
    pub fn from_name(name: &str) -> Option<DepthFilter> {
        DepthFilter::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// What turns an NDC depth `d` in [0, 1] (near plane 0, far plane 1) back
/// into camera-space depth: `near * far / (far - d * (far - near))` for a
/// perspective camera (the inverse of `Mat4::perspective_rh`'s depth),
/// `near + d * (far - near)` for an orthographic one. The resolve shader's
/// `view_depth` computes the same in f32, operation for operation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthProjection {
    /// The near plane's distance.
    pub near: f32,
    /// The far plane's distance.
    pub far: f32,
    /// Whether the camera is perspective (else orthographic).
    pub perspective: bool,
}

impl DepthProjection {
    /// The projection of `camera` (a crop of it has the same).
    pub fn of(camera: &Camera) -> DepthProjection {
        DepthProjection {
            near: camera.near,
            far: camera.far,
            perspective: camera.projection.is_perspective(),
        }
    }

    /// The code of `filter` in the resolve's parameters (`DEPTH_FILTER_*`).
    pub fn code(filter: DepthFilter) -> u32 {
        filter as u32
    }

    /// The camera-space depth of NDC depth `d`.
    pub fn view_depth(self, d: f32) -> f32 {
        let range = self.far - self.near;
        if self.perspective {
            self.near * self.far / (self.far - d * range)
        } else {
            self.near + d * range
        }
    }
}

/// Turns the raw pixels of a depth resolve, `(depth, finite, 0, covered)`
/// (`finite` and `covered` 1 or 0: WGSL has no infinite constant), into
/// the depth in every channel, [`NO_SURFACE`] where it is not finite, and
/// alpha `covered`.
pub fn finish_depths(image: &mut Rgba32FImage) {
    for Rgba([r, g, b, _]) in image.pixels_mut() {
        let depth = if *g != 0.0 { *r } else { NO_SURFACE };
        (*r, *g, *b) = (depth, depth, depth);
    }
}

/// The depth channel of a depth resolve's image, row-major.
pub fn depths(image: &Rgba32FImage) -> Vec<f32> {
    image.pixels().map(|p| p.0[0]).collect()
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    #[test]
    fn view_depth_inverts_the_projection() {
        let camera = crate::camera::tests::camera();
        for camera in [camera, camera.orthographic(4.0)] {
            let projection = DepthProjection::of(&camera);
            let forward = (camera.target - camera.eye).normalize();
            for distance in [camera.near * 1.5, 1.0, 7.25, camera.far * 0.9] {
                let p = camera.eye + forward * distance + Vec3::new(0.3, 0.0, 0.2);
                let d = camera.to_pixel(camera.to_clip(p)).z;
                let expected = (p - camera.eye).dot(forward);
                let z = projection.view_depth(d);
                assert!(
                    (z - expected).abs() <= 1e-4 * expected,
                    "{:?}: {z} for {expected}",
                    camera.projection
                );
            }
        }
    }

    #[test]
    fn filters_are_named_as_rib_names_them() {
        for filter in DepthFilter::ALL {
            assert_eq!(DepthFilter::from_name(filter.name()), Some(filter));
        }
        assert_eq!(DepthFilter::from_name("median"), None);
    }
}
