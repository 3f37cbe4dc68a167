//! Automatic camera framing: the camera that shows a set of points, or why
//! `f32` view math cannot frame them.

use glam::Vec3;

use crate::camera::{PoseProblem, Projection, pose_problem};
use crate::params::NEAR_EPS;

use super::CameraDesc;
use super::defaults::default_fov;

/// The 8 corners of the box `[lo, hi]`.
pub(super) fn box_corners(lo: Vec3, hi: Vec3) -> impl Iterator<Item = Vec3> + Clone {
    (0..8).map(move |i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The smallest view depth at which automatic framing places a point
/// (twice `NEAR_EPS`, the clip `w` below which the renderers cannot project
/// a point): a model framed closer is too small for `f32` view math.
pub const MIN_FRAMED_DEPTH: f32 = 2.0 * NEAR_EPS;

/// Why points cannot be framed automatically
/// ([`CameraDesc::try_framing_points`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FramingError {
    /// The bounds are too large (or not finite) for `f32` view math.
    #[error(
        "are too large to frame automatically ({detail}); give the scene a [camera] (or --eye and --target), or scale the model down (objects[].transform.scale)"
    )]
    TooLarge {
        /// Smallest corner of the bounds.
        lo: Vec3,
        /// Largest corner of the bounds.
        hi: Vec3,
        /// What overflows.
        detail: String,
    },
    /// The bounds are too small: the framing camera would be too close.
    #[error(
        "are too small to frame automatically: the camera would be {nearest:e} from the nearest point, below the {MIN_FRAMED_DEPTH:e} that f32 view math resolves; scale the model up (objects[].transform.scale)"
    )]
    TooSmall {
        /// Smallest corner of the bounds.
        lo: Vec3,
        /// Largest corner of the bounds.
        hi: Vec3,
        /// The nearest point's view depth.
        nearest: f32,
    },
}

impl FramingError {
    /// The bounds that could not be framed.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match self {
            FramingError::TooLarge { lo, hi, .. } | FramingError::TooSmall { lo, hi, .. } => {
                (*lo, *hi)
            }
        }
    }
}

impl CameraDesc {
    /// A camera (z up, fov 40 degrees) looking at the centre of the box
    /// `[lo, hi]` from in front and above, at the smallest distance at which
    /// all 8 box corners fall within 90% of the half-width and half-height of
    /// an image of the given aspect ratio (width / height).
    ///
    /// "In front" is -y when the box is at least as wide in x as in y
    /// (the teapot), and +x otherwise (the Killeroo, which is long in y), so
    /// the longer horizontal side faces the camera; the view is turned about
    /// 17 degrees off axis for a three-quarter view.
    pub fn framing(lo: Vec3, hi: Vec3, aspect: f32) -> CameraDesc {
        CameraDesc::framing_points(box_corners(lo, hi), aspect)
    }

    /// Like [`CameraDesc::framing`], but the distance is fitted to the given
    /// points (e.g. all control points, which contain the surface) rather than
    /// to their bounding box's corners: a tighter fit for rounded models. The
    /// view direction and target still come from the points' bounding box.
    /// With no points, frames the unit box around the origin.
    ///
    /// Points too far apart or too far out for `f32` view math give a
    /// camera that does not validate; [`CameraDesc::try_framing_points`]
    /// says so instead.
    pub fn framing_points(
        points: impl IntoIterator<Item = Vec3> + Clone,
        aspect: f32,
    ) -> CameraDesc {
        Self::framing_fit(points, aspect).0
    }

    /// [`CameraDesc::framing_points`], or why the points cannot be framed
    /// in `f32`: the bounds are non-finite or too large for the view math
    /// (the squared distances overflow), or so small that the nearest point
    /// would lie closer to the eye than [`MIN_FRAMED_DEPTH`] (the renderers
    /// cannot project points at clip `w <= NEAR_EPS`).
    pub fn try_framing_points(
        points: impl IntoIterator<Item = Vec3> + Clone,
        aspect: f32,
    ) -> Result<CameraDesc, FramingError> {
        let (desc, lo, hi, nearest) = Self::framing_fit(points, aspect);
        let too_large = |detail: String| FramingError::TooLarge { lo, hi, detail };
        if !(lo.is_finite() && hi.is_finite()) {
            return Err(too_large("they are not finite".into()));
        }
        let fields = [desc.eye, desc.target, Vec3::new(desc.near, desc.far, 0.0)];
        let usable =
            fields.iter().all(|v| v.is_finite()) && desc.near > 0.0 && desc.far > desc.near;
        if !usable {
            return Err(too_large(
                "the camera that would frame them is not finite in f32".into(),
            ));
        }
        if let Some(problem) = pose_problem(desc.eye, desc.target, desc.up) {
            return Err(match problem {
                PoseProblem::TooClose => FramingError::TooSmall { lo, hi, nearest },
                _ => too_large(
                    "the camera that would frame them lies too far out for f32 view math: its squared distances overflow"
                        .into(),
                ),
            });
        }
        // Also refuses a NaN depth.
        if nearest.is_nan() || nearest < MIN_FRAMED_DEPTH {
            return Err(FramingError::TooSmall { lo, hi, nearest });
        }
        Ok(desc)
    }

    /// The framing camera, the points' bounds and the view depth of the
    /// nearest point.
    fn framing_fit(
        points: impl IntoIterator<Item = Vec3> + Clone,
        aspect: f32,
    ) -> (CameraDesc, Vec3, Vec3, f32) {
        const MARGIN: f32 = 0.9;
        let fov_y_degrees = default_fov();
        let (lo, hi) = framed_bounds(points.clone());
        let mut center = (lo + hi) * 0.5;
        if !center.is_finite() {
            // lo + hi overflowed.
            center = lo * 0.5 + hi * 0.5;
        }
        let extent = hi - lo;
        let length = extent.length();
        let radius = if length > 0.0 && length.is_finite() && length >= 1e-18 {
            length * 0.5
        } else if extent.max_element() > 0.0 {
            // The squared length underflows or overflows: scale first.
            let m = extent.max_element();
            (extent / m).length() * m * 0.5
        } else {
            // One point: frame a small ball around it.
            1e-3f32.max(center.abs().max_element() * 1e-3)
        };
        // Direction from the target to the eye.
        let to_eye = if extent.x >= extent.y {
            Vec3::new(0.3, -1.0, 0.55)
        } else {
            Vec3::new(1.0, 0.3, 0.55)
        }
        .normalize();
        let forward = -to_eye;
        let right = forward.cross(Vec3::Z).normalize();
        let up = right.cross(forward);
        let tan_y = (fov_y_degrees.to_radians() * 0.5).tan() * MARGIN;
        let tan_x = tan_y * aspect;
        // A point at offset q from the centre has depth (dist - q.to_eye) and
        // must satisfy |q.right| <= depth * tan_x and |q.up| <= depth * tan_y.
        let mut distance = radius * 0.1;
        for point in points.clone() {
            let q = point - center;
            let along = q.dot(to_eye);
            distance = distance
                .max(along + q.dot(right).abs() / tan_x)
                .max(along + q.dot(up).abs() / tan_y);
        }
        let near = ((distance - radius) * 0.5).max(distance * 1e-3);
        let far = distance + radius * 4.0;
        let farthest_along = points
            .clone()
            .into_iter()
            .map(|p| (p - center).dot(to_eye))
            .fold(f32::NEG_INFINITY, f32::max);
        let nearest = distance - farthest_along.max(-distance);
        (
            CameraDesc {
                eye: center + to_eye * distance,
                target: center,
                up: Vec3::Z,
                fov_y_degrees,
                near,
                far,
                projection: Projection::Perspective,
                ortho_height: None,
            },
            lo,
            hi,
            nearest,
        )
    }
}

/// The box the framing fits around `points`: their bounds, or a unit box
/// around the origin when there are none.
pub(crate) fn framed_bounds(points: impl IntoIterator<Item = Vec3>) -> (Vec3, Vec3) {
    points
        .into_iter()
        .fold(None, |acc: Option<(Vec3, Vec3)>, p| match acc {
            None => Some((p, p)),
            Some((lo, hi)) => Some((lo.min(p), hi.max(p))),
        })
        .unwrap_or((Vec3::splat(-0.5), Vec3::splat(0.5)))
}
