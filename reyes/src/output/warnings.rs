//! Warnings about a frame that rendered but may not show what was asked:
//! the counters say so, and a command line should say it too.

use crate::params::MAX_SPLIT_DEPTH_LIMIT;
use crate::stats::RenderStats;

/// Where a frame's input control points lie along the camera's view
/// direction (their depths from the eye, at shutter open), and the
/// camera's clipping planes: what the advice for a frame whose every patch
/// was culled names.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthExtent {
    /// The least depth of any control point (negative: behind the eye).
    pub nearest: f32,
    /// The greatest.
    pub farthest: f32,
    /// The camera's near plane.
    pub near: f32,
    /// Its far plane.
    pub far: f32,
}

/// The warnings a frame's statistics call for, one sentence each (without
/// a `warning:` prefix): patches dropped by the depth guard, a frame that
/// covered no sample although the scene has objects, displaced points
/// beyond their bound, and grid points that turned non-finite, by source. `objects` is the scene's object count and
/// `max_split_depth` the depth guard it rendered with; `extent`, where the
/// control points lie against the clipping planes, lets an empty frame's
/// advice name the plane that culled everything.
pub fn frame_warnings(
    stats: &RenderStats,
    objects: usize,
    max_split_depth: u32,
    extent: Option<DepthExtent>,
) -> Vec<String> {
    let mut warnings = Vec::new();
    let drops = stats.depth_guard_drops;
    // Raising the key helps only below its limit.
    let remedy = if max_split_depth < MAX_SPLIT_DEPTH_LIMIT {
        format!(
            "raise the scene key `max_split_depth` (now {max_split_depth}, at most {MAX_SPLIT_DEPTH_LIMIT})"
        )
    } else {
        format!("`max_split_depth` is already at its limit {MAX_SPLIT_DEPTH_LIMIT}")
    };
    if drops > 0 && stats.grids_diced == 0 {
        warnings.push(format!(
            "the depth guard dropped all {drops} patch piece(s) left after culling: each still needed a split at max_split_depth = {max_split_depth}, so nothing was diced; {remedy}"
        ));
    } else if drops > 0 {
        warnings.push(format!(
            "the depth guard dropped {drops} patch piece(s) that still needed a split at max_split_depth = {max_split_depth} ({} were diced): parts of the surface may be missing; {remedy}",
            stats.grids_diced
        ));
    }
    if objects > 0 && stats.samples_hit == 0 {
        warnings.push(format!(
            "the frame covered no sample although the scene has {objects} object(s) with {} patch(es): {}",
            stats.input_patches,
            empty_frame_cause(stats, extent)
        ));
    }
    if stats.displacement_bound_exceeded > 0 {
        warnings.push(format!(
            "{} displaced grid point(s) moved further than the displacement bound; surfaces near the screen edges may be culled wrongly (raise the bound)",
            stats.displacement_bound_exceeded
        ));
    }
    warnings.extend(non_finite_warnings(stats));
    warnings
}

/// One warning per source that turned grid points non-finite
/// ([`crate::nonfinite`]), naming what to check.
fn non_finite_warnings(stats: &RenderStats) -> impl Iterator<Item = String> {
    [
        (
            stats.non_finite_displacement,
            "the displacement",
            "check the displacement function (a user function may return NaN or infinity) and its scale",
        ),
        (
            stats.non_finite_transform,
            "the object's transform",
            "check the objects' transform and transform_close: their scales times the model's size (and its displacement) must stay well within f32",
        ),
        (
            stats.non_finite_camera,
            "the camera's projection",
            "check the camera (eye, target, fov) and how far from it the surfaces lie: a position, displaced or placed, far beyond the scene overflows f32 when projected",
        ),
    ]
    .into_iter()
    .filter(|&(count, _, _)| count > 0)
    .map(|(count, source, check)| {
        format!(
            "{count} grid point(s) got an infinite or NaN position from {source} and may be missing or drawn wrongly; {check}"
        )
    })
}

/// Why no sample was covered, as far as the counters tell.
fn empty_frame_cause(stats: &RenderStats, extent: Option<DepthExtent>) -> String {
    let culled = stats.culled_patches;
    if stats.input_patches == 0 {
        "the models have no patches".to_owned()
    } else if stats.grids_diced == 0 && stats.depth_guard_drops == 0 {
        match extent {
            Some(e) if e.nearest > e.far => {
                return format!(
                    "all {culled} patch piece(s) were culled: every control point lies beyond the far plane (far = {}; the nearest is {} from the eye); raise the far plane (`far` in [camera], `Clipping` in RIB, or --far)",
                    e.far, e.nearest
                );
            }
            Some(e) if e.farthest < e.near => {
                return format!(
                    "all {culled} patch piece(s) were culled: every control point lies before the near plane or behind the eye (near = {}; the farthest is {} from the eye); move the eye back, or lower the near plane (`near` in [camera], `Clipping` in RIB, or --near)",
                    e.near, e.farthest
                );
            }
            _ => {}
        }
        format!(
            "all {} patch piece(s) were culled outside the view; check the camera (eye, target, fov) and the objects' transforms",
            stats.culled_patches
        )
    } else if stats.grids_diced == 0 {
        "nothing was diced (see the depth-guard warning)".to_owned()
    } else {
        format!(
            "{} grid(s) were diced but none of their {} sample test(s) hit; the surfaces may face away (sides = 1) or fall between the samples",
            stats.grids_diced, stats.samples_tested
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The statistics of a frame that diced and hit.
    fn healthy() -> RenderStats {
        RenderStats {
            input_patches: 32,
            splits: 10,
            grids_diced: 42,
            samples_tested: 1000,
            samples_hit: 400,
            ..RenderStats::default()
        }
    }

    #[test]
    fn a_healthy_frame_has_no_warning() {
        assert!(frame_warnings(&healthy(), 1, 24, None).is_empty());
    }

    #[test]
    fn a_guard_that_drops_everything_names_the_key() {
        let stats = RenderStats {
            input_patches: 32,
            depth_guard_drops: 32,
            ..RenderStats::default()
        };
        let warnings = frame_warnings(&stats, 1, 0, None);
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert!(warnings[0].starts_with("the depth guard dropped all 32 patch piece(s)"));
        assert!(warnings[0].contains("max_split_depth = 0"));
        assert!(warnings[0].contains("raise the scene key `max_split_depth`"));
        assert!(warnings[1].contains("covered no sample"));
    }

    #[test]
    fn some_drops_are_counted() {
        let stats = RenderStats {
            depth_guard_drops: 3,
            ..healthy()
        };
        let warnings = frame_warnings(&stats, 1, MAX_SPLIT_DEPTH_LIMIT, None);
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].starts_with("the depth guard dropped 3 patch piece(s)"));
        assert!(warnings[0].contains("already at its limit"));
    }

    #[test]
    fn each_non_finite_source_is_named() {
        let stats = RenderStats {
            non_finite_displacement: 7,
            non_finite_camera: 2,
            ..healthy()
        };
        let warnings = frame_warnings(&stats, 1, 24, None);
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert!(
            warnings[0].starts_with(
                "7 grid point(s) got an infinite or NaN position from the displacement"
            )
        );
        assert!(warnings[0].contains("and its scale"));
        assert!(warnings[1].starts_with("2 grid point(s)") && warnings[1].contains("the camera"));
        let moved = RenderStats {
            non_finite_transform: 1,
            ..healthy()
        };
        assert!(frame_warnings(&moved, 1, 24, None)[0].contains("transform_close"));
    }

    #[test]
    fn an_empty_frame_says_why() {
        let culled = RenderStats {
            input_patches: 32,
            culled_patches: 32,
            ..RenderStats::default()
        };
        let warnings = frame_warnings(&culled, 1, 24, None);
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].contains("culled outside the view"));
        // No objects, nothing to cover: not a warning.
        assert!(frame_warnings(&RenderStats::default(), 0, 24, None).is_empty());
        let missed = RenderStats {
            samples_hit: 0,
            ..healthy()
        };
        assert!(
            frame_warnings(&missed, 2, 24, None)[0]
                .contains("none of their 1000 sample test(s) hit")
        );
    }
}
