//! Bicubic Bezier patch models.
//!
//! This module holds only the patch types; reading them from files (and the
//! embedded teapot) lives in [`crate::load`], which builds on these types, so
//! that the arrow between the two modules points one way.

use glam::Vec3;

/// One bicubic Bezier patch: 16 control points, row by row.
///
/// `points[v * 4 + u]` is the control point in column `u` (along the patch
/// parameter `u`, or `s` inside a diced grid) and row `v` (parameter `v`/`t`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Patch {
    /// The control points, `points[v * 4 + u]`.
    pub points: [Vec3; 16],
}

impl Patch {
    /// The control point in column `u` and row `v` (both in `0..4`).
    pub fn point(&self, u: usize, v: usize) -> Vec3 {
        self.points[v * 4 + u]
    }
}

/// A model: a list of bicubic Bezier patches in the model's own space.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Model {
    /// The patches.
    pub patches: Vec<Patch>,
}

impl Model {
    /// The axis-aligned bounding box `(min, max)` of all control points (which
    /// contains the surface, by the convex-hull property of Bezier patches).
    /// An empty model gives `(Vec3::ZERO, Vec3::ZERO)`.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut points = self.patches.iter().flat_map(|p| p.points.iter().copied());
        let Some(first) = points.next() else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)))
    }
}
