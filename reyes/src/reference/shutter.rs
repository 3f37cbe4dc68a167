//! When in the shutter a moving grid point can be seen: the part of the
//! shutter its clip position spends between the near and far planes, and
//! its clip position at a time in it.

use glam::Vec4;

use crate::params::NEAR_EPS;

/// The interval `[lo, hi]` of shutter times `t` in `[0, 1]` at which the
/// clip position `clip_open + (clip_close - clip_open) * t` lies in front
/// of the near plane and not past the far plane; `lo > hi` when there is
/// none (or an end is not finite). Shared with the WGSL `visible_span`.
pub fn visible_span(clip_open: Vec4, clip_close: Vec4) -> (f32, f32) {
    const NEVER: (f32, f32) = (1.0, 0.0);
    if !(clip_open.is_finite() && clip_close.is_finite()) {
        return NEVER;
    }
    // Each plane is a function of the clip position that is linear in t and
    // >= 0 on the visible side.
    let planes = [
        (clip_open.z, clip_close.z),
        (clip_open.w - clip_open.z, clip_close.w - clip_close.z),
        (clip_open.w - NEAR_EPS, clip_close.w - NEAR_EPS),
    ];
    let mut span = (0.0f32, 1.0f32);
    for (f0, f1) in planes {
        if f0 >= 0.0 && f1 >= 0.0 {
            continue;
        }
        if f0 < 0.0 && f1 < 0.0 {
            return NEVER;
        }
        let t = f0 / (f0 - f1);
        if f0 < 0.0 {
            span.0 = span.0.max(t);
        } else {
            span.1 = span.1.min(t);
        }
    }
    span
}

/// The clip position at shutter time `t`, exactly an end at 0 and 1.
pub(super) fn clip_at(clip_open: Vec4, clip_close: Vec4, t: f32) -> Vec4 {
    if t == 0.0 {
        clip_open
    } else if t == 1.0 {
        clip_close
    } else {
        clip_open + (clip_close - clip_open) * t
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec4;

    use super::visible_span;
    use crate::params::NEAR_EPS;

    /// A clip position with depth `z` and `w` (x and y do not matter).
    fn clip(z: f32, w: f32) -> Vec4 {
        Vec4::new(0.0, 0.0, z, w)
    }

    fn assert_span(open: Vec4, close: Vec4, expected: (f32, f32)) {
        let (lo, hi) = visible_span(open, close);
        assert!(
            (lo - expected.0).abs() < 1e-6 && (hi - expected.1).abs() < 1e-6,
            "{open} -> {close}: span ({lo}, {hi}), expected {expected:?}"
        );
    }

    #[test]
    fn a_point_in_view_at_both_ends_is_seen_during_the_whole_shutter() {
        assert_eq!(visible_span(clip(0.5, 2.0), clip(1.0, 3.0)), (0.0, 1.0));
    }

    #[test]
    fn a_point_crossing_the_near_plane_is_seen_until_it_does() {
        // z goes from 1 to -3: it reaches 0 a quarter into the shutter.
        assert_span(clip(1.0, 2.0), clip(-3.0, 0.5), (0.0, 0.25));
        // And the other way round: seen from three quarters on.
        assert_span(clip(-3.0, 0.5), clip(1.0, 2.0), (0.75, 1.0));
    }

    #[test]
    fn a_point_receding_past_the_far_plane_is_seen_until_it_does() {
        // w - z goes from 1 to -1: past the far plane from half-way.
        assert_span(clip(1.0, 2.0), clip(5.0, 4.0), (0.0, 0.5));
    }

    #[test]
    fn a_point_passing_behind_the_eye_is_seen_while_in_front_of_it() {
        // Depth 0 (on the near plane) throughout, w from 1 to -1: seen
        // while w > NEAR_EPS, up to just before half-way.
        let (lo, hi) = visible_span(clip(0.0, 1.0), clip(0.0, -1.0));
        assert_eq!(lo, 0.0);
        let expected = (1.0 - NEAR_EPS) / 2.0;
        assert!((hi - expected).abs() < 1e-7 && hi < 0.5, "{hi}");
    }

    #[test]
    fn a_point_out_of_view_throughout_or_not_finite_is_never_seen() {
        let never = |open, close| {
            let (lo, hi) = visible_span(open, close);
            assert!(lo > hi, "{open} -> {close}: ({lo}, {hi})");
        };
        never(clip(-1.0, 2.0), clip(-0.5, 3.0));
        never(clip(3.0, 2.0), clip(4.0, 3.0));
        never(clip(0.5, f32::NAN), clip(0.5, 1.0));
        never(clip(0.5, 1.0), clip(f32::INFINITY, 1.0));
    }
}
