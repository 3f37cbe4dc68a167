//! The built-in procedural height `"sines"`: two octaves of egg-crate bumps,
//! the Rust twin of `height_sines` in `shaders/reyes/displacement.wgsl`.

use crate::params::{SINES_NORMALIZATION, SINES_OCTAVE_2_FREQUENCY, SINES_OCTAVE_2_WEIGHT};

/// `sin(2 pi (fract(x) - 1/2)) = -sin(2 pi x)`: the argument is reduced to
/// `[-pi, pi)` first, where GPU `sin` is accurate.
pub fn wave(x: f32) -> f32 {
    // fract as WGSL defines it (x - floor(x)), not Rust's f32::fract (x - trunc(x)).
    let fract = x - x.floor();
    (std::f32::consts::TAU * (fract - 0.5)).sin()
}

/// Height in `[-1, 1]` at `(u, v)` (already multiplied by the tiling):
///
/// `h = (2/3) * (w(u) w(v) + 1/2 * w(3u) w(3v))`, `w(x) = -sin(2 pi x)`.
///
/// Every term has a factor `sin(2 pi k u)` and `sin(2 pi k v)` with integer
/// `k`, so `h = 0` wherever `u` or `v` is an integer: with an integer tiling
/// the height vanishes on every patch edge, and neighbouring patches meet
/// without cracks whatever their parameterizations. The maximum `|h| = 1` is
/// reached at `u, v = 1/4 (mod 1)`.
pub fn sines(u: f32, v: f32) -> f32 {
    let k = SINES_OCTAVE_2_FREQUENCY;
    let first = wave(u) * wave(v);
    let second = wave(k * u) * wave(k * v);
    (first + SINES_OCTAVE_2_WEIGHT * second) * SINES_NORMALIZATION
}

/// The largest `|h|` of [`sines`].
pub const SINES_MAX_HEIGHT: f32 = 1.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vanishes_on_integer_lines_and_peaks_at_one() {
        for k in 0..=20 {
            let t = k as f32 / 20.0;
            for edge in [0.0, 1.0, 2.0] {
                assert!(sines(edge, t).abs() < 1e-5, "u = {edge}, v = {t}");
                assert!(sines(t, edge).abs() < 1e-5, "u = {t}, v = {edge}");
            }
        }
        assert!((sines(0.25, 0.25) - 1.0).abs() < 1e-5);
        let mut max = 0.0f32;
        for i in 0..200 {
            for j in 0..200 {
                max = max.max(sines(i as f32 / 200.0, j as f32 / 200.0).abs());
            }
        }
        assert!(max <= SINES_MAX_HEIGHT + 1e-5, "{max}");
    }
}
