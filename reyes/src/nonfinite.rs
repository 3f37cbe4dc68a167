//! Grid points whose position turned infinite or NaN, and the stage that
//! turned it: the displacement (a height times its scale beyond `f32`, or a
//! user function returning NaN or infinity), the object's transform (the
//! shutter-close motion, or a placement that put control points so near
//! the `f32` limit that evaluating the patch overflows) or the camera (the
//! clip or pixel position of a finite world position). Such a point draws
//! nothing, or garbage, without failing: the counts let the frame say so
//! (`crate::output::warnings`).
//!
//! Both renderers build the same [`Sources`] per grid point with the same
//! checks, operation for operation: the CPU reference in
//! `crate::reference::dice_shade_sample`, the GPU in
//! `shaders/reyes/dice_shade_sample.wgsl` with the library's
//! `dice_non_finite`, `camera_non_finite` and `close_non_finite`. A point
//! counts at most once per source, and only at the first stage that lost it:
//! a NaN displacement makes the point's clip position NaN too, but that is
//! not the camera's doing.

use glam::{Vec3, Vec4};

use crate::stats::RenderStats;

/// A stage that can turn a position non-finite; its value is its bit in
/// [`Sources`] and its word after `STAT_NON_FINITE` on the GPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// The displacement: height times scale, or the displaced point.
    Displacement = 0,
    /// The object's transform.
    Transform = 1,
    /// The camera's projection.
    Camera = 2,
}

/// The sources that lost one grid point (a bit set, see [`Source`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Sources(u32);

impl Sources {
    /// No source: the point stayed finite.
    pub const NONE: Sources = Sources(0);

    /// Just `source`.
    pub fn of(source: Source) -> Sources {
        Sources(1 << source as u32)
    }

    /// Whether `source` is among them.
    pub fn contains(self, source: Source) -> bool {
        self.0 & (1 << source as u32) != 0
    }

    /// Both sets.
    pub fn union(self, other: Sources) -> Sources {
        Sources(self.0 | other.0)
    }

    /// Adds one to each of their counters in `stats`.
    pub fn count_into(self, stats: &mut RenderStats) {
        stats.non_finite_displacement += u64::from(self.contains(Source::Displacement));
        stats.non_finite_transform += u64::from(self.contains(Source::Transform));
        stats.non_finite_camera += u64::from(self.contains(Source::Camera));
    }
}

/// Whether every component is finite.
fn finite3(v: Vec3) -> bool {
    v.is_finite()
}

/// The sources of a diced point: the transform when the input patch's own
/// point `patch_point` is not finite (its finite control points lie near
/// the `f32` limit), else, when the final position `moved` (displaced, and
/// on its edge's chord) is not, the displacement when the object is
/// `displaced`, the transform otherwise.
pub fn dice_sources(patch_point: Vec3, displaced: bool, moved: Vec3) -> Sources {
    if !finite3(patch_point) {
        Sources::of(Source::Transform)
    } else if !finite3(moved) {
        Sources::of(if displaced {
            Source::Displacement
        } else {
            Source::Transform
        })
    } else {
        Sources::NONE
    }
}

/// The camera, when the finite world position `world` projects to a clip
/// position `clip` or pixel position `pixel` that is not finite.
pub fn camera_sources(world: Vec3, clip: Vec4, pixel: Vec3) -> Sources {
    if finite3(world) && !(clip.is_finite() && finite3(pixel)) {
        Sources::of(Source::Camera)
    } else {
        Sources::NONE
    }
}

/// The sources at shutter close: the transform when the motion takes the
/// finite position `moved` to a `close_position` that is not finite, else
/// [`camera_sources`] of the close position.
pub fn close_sources(moved: Vec3, close_position: Vec3, close_clip: Vec4, close: Vec3) -> Sources {
    if finite3(moved) && !finite3(close_position) {
        Sources::of(Source::Transform)
    } else {
        camera_sources(close_position, close_clip, close)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ONE: Vec3 = Vec3::ONE;
    const NAN: Vec3 = Vec3::new(0.0, f32::NAN, 0.0);
    const INF: Vec3 = Vec3::new(f32::INFINITY, 0.0, 0.0);

    #[test]
    fn the_first_stage_that_loses_a_point_is_its_source() {
        assert_eq!(dice_sources(ONE, true, ONE), Sources::NONE);
        assert_eq!(
            dice_sources(ONE, true, NAN),
            Sources::of(Source::Displacement)
        );
        assert_eq!(
            dice_sources(ONE, false, INF),
            Sources::of(Source::Transform)
        );
        assert_eq!(dice_sources(INF, true, INF), Sources::of(Source::Transform));
        let clip = ONE.extend(1.0);
        assert_eq!(camera_sources(ONE, clip, ONE), Sources::NONE);
        assert_eq!(
            camera_sources(ONE, INF.extend(1.0), ONE),
            Sources::of(Source::Camera)
        );
        assert_eq!(camera_sources(ONE, clip, NAN), Sources::of(Source::Camera));
        // A lost world position is not the camera's doing.
        assert_eq!(camera_sources(NAN, NAN.extend(1.0), NAN), Sources::NONE);
        assert_eq!(
            close_sources(ONE, INF, INF.extend(1.0), INF),
            Sources::of(Source::Transform)
        );
        assert_eq!(
            close_sources(ONE, ONE, clip, INF),
            Sources::of(Source::Camera)
        );
        assert_eq!(close_sources(NAN, NAN, clip, NAN), Sources::NONE);
    }

    #[test]
    fn a_point_counts_once_per_source() {
        let mut stats = RenderStats::default();
        let camera = Sources::of(Source::Camera);
        camera
            .union(camera)
            .union(Sources::of(Source::Transform))
            .count_into(&mut stats);
        assert_eq!(
            (
                stats.non_finite_displacement,
                stats.non_finite_transform,
                stats.non_finite_camera
            ),
            (0, 1, 1)
        );
    }
}
