//! Keyframe interpolation: one animated value (a "track") evaluated at a
//! time, linearly or along a Catmull-Rom spline.
//!
//! A track is a list of keys `(t_i, p_i)` with strictly increasing times.
//! Before the first key it holds the first value, after the last the last.
//! Between keys `i` and `i + 1` it follows the interpolation of key `i`:
//!
//! * **linear**: `p_i + s (p_{i+1} - p_i)`, `s = (t - t_i) / (t_{i+1} - t_i)`;
//! * **smooth**: the cubic Hermite curve through `p_i` and `p_{i+1}` with
//!   the Catmull-Rom tangents of a non-uniform track,
//!   `m_i = (p_{i+1} - p_{i-1}) / (t_{i+1} - t_{i-1})` at an inner key and
//!   the one-sided difference at the first and last keys
//!   (`(p_1 - p_0) / (t_1 - t_0)`), so that a smooth track of two keys is a
//!   straight line and evenly spaced keys give the uniform Catmull-Rom
//!   spline:
//!   `h00(s) p_i + h10(s) dt m_i + h01(s) p_{i+1} + h11(s) dt m_{i+1}` with
//!   `dt = t_{i+1} - t_i`, `h00 = 2s³ - 3s² + 1`, `h10 = s³ - 2s² + s`,
//!   `h01 = -2s³ + 3s²`, `h11 = s³ - s²`.
//!
//! The spline passes through every key and has a continuous first
//! derivative; unlike a Bezier curve it may overshoot between keys.

use std::ops::{Add, Mul, Sub};

use serde::{Deserialize, Serialize};

/// How a value moves from one key to the next.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    /// A straight line between the two keys (`"linear"`, the default).
    #[default]
    Linear,
    /// A Catmull-Rom spline through the keys (`"smooth"`).
    Smooth,
}

/// A value that keys can animate: numbers and vectors.
pub trait Animatable:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f32, Output = Self>
{
}

impl<T> Animatable for T where T: Copy + Add<Output = T> + Sub<Output = T> + Mul<f32, Output = T> {}

/// One key of a track: its time in seconds, its value and the
/// interpolation towards the next key.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key<T> {
    /// Time in seconds.
    pub time: f32,
    /// The value at `time`.
    pub value: T,
    /// How the value moves from here to the next key.
    pub interpolation: Interpolation,
}

/// The value of the track `keys` (times strictly increasing, at least one
/// key) at `time`.
pub fn evaluate<T: Animatable>(keys: &[Key<T>], time: f32) -> T {
    let first = keys.first().expect("a track has at least one key");
    let last = keys.last().expect("a track has at least one key");
    if time <= first.time {
        return first.value;
    }
    if time >= last.time {
        return last.value;
    }
    // The segment [keys[i], keys[i + 1]] holding `time`: the first key
    // later than `time` ends it.
    let next = keys.partition_point(|k| k.time <= time);
    let i = next - 1;
    let (a, b) = (keys[i], keys[next]);
    let dt = b.time - a.time;
    let s = (time - a.time) / dt;
    match a.interpolation {
        Interpolation::Linear => a.value + (b.value - a.value) * s,
        Interpolation::Smooth => {
            let m_a = tangent(keys, i);
            let m_b = tangent(keys, next);
            let (s2, s3) = (s * s, s * s * s);
            let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
            let h10 = s3 - 2.0 * s2 + s;
            let h01 = -2.0 * s3 + 3.0 * s2;
            let h11 = s3 - s2;
            a.value * h00 + m_a * (h10 * dt) + b.value * h01 + m_b * (h11 * dt)
        }
    }
}

/// The Catmull-Rom tangent (per second) at key `i`: the difference across
/// its neighbours, one-sided at the ends.
fn tangent<T: Animatable>(keys: &[Key<T>], i: usize) -> T {
    let before = keys[i.saturating_sub(1)];
    let after = keys[(i + 1).min(keys.len() - 1)];
    (after.value - before.value) * (1.0 / (after.time - before.time))
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    fn keys(points: &[(f32, f32)], interpolation: Interpolation) -> Vec<Key<f32>> {
        points
            .iter()
            .map(|&(time, value)| Key {
                time,
                value,
                interpolation,
            })
            .collect()
    }

    #[test]
    fn linear_keys_interpolate_by_hand() {
        let track = keys(
            &[(0.0, 1.0), (2.0, 5.0), (3.0, -1.0)],
            Interpolation::Linear,
        );
        // Held before the first and after the last key.
        assert_eq!(evaluate(&track, -1.0), 1.0);
        assert_eq!(evaluate(&track, 7.0), -1.0);
        // At the keys themselves.
        assert_eq!(evaluate(&track, 0.0), 1.0);
        assert_eq!(evaluate(&track, 2.0), 5.0);
        // 1 + (5 - 1) * 0.25 = 2; 5 + (-1 - 5) * 0.5 = 2.
        assert_eq!(evaluate(&track, 0.5), 2.0);
        assert_eq!(evaluate(&track, 2.5), 2.0);
    }

    #[test]
    fn smooth_keys_follow_catmull_rom_by_hand() {
        // Evenly spaced keys 0, 1, 0, 1 at t = 0, 1, 2, 3. Tangents: m0 = 1
        // (one-sided), m1 = (0 - 0) / 2 = 0, m2 = (1 - 1) / 2 = 0, m3 = 1.
        let track = keys(
            &[(0.0, 0.0), (1.0, 1.0), (2.0, 0.0), (3.0, 1.0)],
            Interpolation::Smooth,
        );
        // Segment 0 at s = 0.5: h00 = 0.5, h10 = 0.125, h01 = 0.5,
        // h11 = -0.125: 0 + 0.125 * 1 + 0.5 * 1 + (-0.125) * 0 = 0.625.
        assert!((evaluate(&track, 0.5) - 0.625).abs() < 1e-6);
        // Segment 1 at s = 0.25: h00 = 2/64 - 3/16 + 1 = 0.84375, both
        // tangents 0, so 0.84375 * 1 + h01 * 0 = 0.84375.
        assert!((evaluate(&track, 1.25) - 0.843_75).abs() < 1e-6);
        // Segment 2 at s = 0.5: 0.5 * 0 + 0.125 * 0 + 0.5 * 1 - 0.125 * 1 = 0.375.
        assert!((evaluate(&track, 2.5) - 0.375).abs() < 1e-6);
        // Through the keys.
        for (t, v) in [(1.0, 1.0), (2.0, 0.0)] {
            assert!((evaluate(&track, t) - v).abs() < 1e-6);
        }
    }

    #[test]
    fn smooth_keys_use_non_uniform_tangents() {
        // Keys 0 @ 0, 2 @ 1, 2 @ 3: m1 = (2 - 0) / (3 - 0) = 2/3, m0 = 2.
        // Segment 0 at s = 0.5 (dt = 1): 0.5 * 0 + 0.125 * 2 + 0.5 * 2
        // - 0.125 * 2/3 = 0.25 + 1 - 0.083333 = 1.1666667.
        let track = keys(&[(0.0, 0.0), (1.0, 2.0), (3.0, 2.0)], Interpolation::Smooth);
        assert!((evaluate(&track, 0.5) - 1.166_666_7).abs() < 1e-5);
        // Segment 1 at s = 0.5 (dt = 2), m2 = (2 - 2) / 2 = 0:
        // 0.5 * 2 + 0.125 * 2 * 2/3 + 0.5 * 2 - 0 = 2.1666667 (it overshoots).
        assert!((evaluate(&track, 2.0) - 2.166_666_7).abs() < 1e-5);
    }

    #[test]
    fn two_smooth_keys_make_a_straight_line() {
        let smooth = keys(&[(1.0, 3.0), (3.0, 7.0)], Interpolation::Smooth);
        for t in [1.0, 1.5, 2.0, 2.9] {
            let linear = 3.0 + (t - 1.0) * 2.0;
            assert!((evaluate(&smooth, t) - linear).abs() < 1e-5, "t = {t}");
        }
    }

    #[test]
    fn each_segment_takes_its_first_keys_interpolation() {
        let mut track = keys(
            &[(0.0, 0.0), (1.0, 1.0), (2.0, 0.0), (3.0, 1.0)],
            Interpolation::Smooth,
        );
        track[1].interpolation = Interpolation::Linear;
        assert!((evaluate(&track, 1.25) - 0.75).abs() < 1e-6);
        assert!((evaluate(&track, 0.5) - 0.625).abs() < 1e-6);
    }

    #[test]
    fn vectors_interpolate_per_component() {
        let track = [
            Key {
                time: 0.0,
                value: Vec3::new(0.0, 10.0, 0.0),
                interpolation: Interpolation::Linear,
            },
            Key {
                time: 4.0,
                value: Vec3::new(4.0, 2.0, 0.0),
                interpolation: Interpolation::Linear,
            },
        ];
        assert_eq!(evaluate(&track, 1.0), Vec3::new(1.0, 8.0, 0.0));
    }
}
