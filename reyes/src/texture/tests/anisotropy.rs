//! Anisotropic filtering against the box integral of a cosine, computed
//! from its formula: the mean of `cos(2 pi k . x)` over the parallelogram
//! `x0 + u a + v b`, `u, v` in `[-1/2, 1/2]`, is
//! `cos(2 pi k . x0) sinc(pi k . a) sinc(pi k . b)`.

use std::f64::consts::{PI, TAU};

use glam::{DVec2, Vec2};
use rand::Rng;

use super::*;
use crate::test_random::fresh_rng;

/// Side of the test texture, in texels.
const SIDE: u32 = 128;

/// `sin(x) / x`.
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-9 { 1.0 } else { x.sin() / x }
}

/// A `SIDE`-square periodic texture of `0.5 + 0.5 cos(2 pi k . x)`, `x` the
/// texel centre in level-0 texels; `k` in cycles per texel, a whole number
/// of cycles across the texture so that it tiles.
fn cosine(set: &mut TextureSet, k: DVec2) -> TextureId {
    let texels = (0..SIDE)
        .flat_map(|y| (0..SIDE).map(move |x| (x, y)))
        .map(|(x, y)| {
            let centre = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
            Vec4::splat((0.5 + 0.5 * (TAU * k.dot(centre)).cos()) as f32)
        })
        .collect();
    set.add_linear(
        Path::new("cosine"),
        SIDE,
        SIDE,
        texels,
        Wrap::Periodic,
        Wrap::Periodic,
    )
    .unwrap()
}

/// Errors of the filter against the box integral over random footprints
/// `(a, b)` (in level-0 texels) drawn by `footprint`, on cosines of periods
/// 8 to 24 texels in random directions: (largest, root mean square).
fn errors(
    test: &str,
    mut footprint: impl FnMut(&mut rand::rngs::StdRng, DVec2) -> (DVec2, DVec2),
) -> (f64, f64) {
    let (seed, mut rng) = fresh_rng(test);
    let (mut largest, mut squares, mut count) = (0.0f64, 0.0, 0);
    for _ in 0..40 {
        let k = loop {
            let cycles = DVec2::new(
                f64::from(rng.random_range(-16i32..=16)),
                f64::from(rng.random_range(-16i32..=16)),
            );
            let period = f64::from(SIDE) / cycles.length();
            if (8.0..=24.0).contains(&period) {
                break cycles / f64::from(SIDE);
            }
        };
        let mut set = TextureSet::default();
        let id = cosine(&mut set, k);
        for _ in 0..50 {
            let centre = DVec2::new(
                rng.random_range(0.0..f64::from(SIDE)),
                rng.random_range(0.0..f64::from(SIDE)),
            );
            let (a, b) = footprint(&mut rng, k);
            let st = |x: DVec2| (x / f64::from(SIDE)).as_vec2();
            let got = f64::from(set.sample(id, st(centre), st(a), st(b)).x);
            let want =
                0.5 + 0.5 * (TAU * k.dot(centre)).cos() * sinc(PI * k.dot(a)) * sinc(PI * k.dot(b));
            let error = (got - want).abs();
            // Mip levels blur more than a box of their width (a level-1
            // texel between two others spans up to 4 texels): up to about
            // 0.1 where the footprint is 1 to 2 texels wide on the shortest
            // periods.
            assert!(
                error < 0.15,
                "seed {seed}: k {k}, centre {centre}, axes {a} {b}: {got} against {want}"
            );
            largest = largest.max(error);
            squares += error * error;
            count += 1;
        }
    }
    let rms = (squares / f64::from(count)).sqrt();
    eprintln!("{test}: largest error {largest:.4}, rms {rms:.4} (seed {seed})");
    (largest, rms)
}

#[test]
fn a_footprint_along_the_stripes_keeps_their_contrast() {
    // Long along the stripes (up to 16 times its width), at most 2 texels
    // across them: the integral keeps most of the contrast, which an
    // isotropic filter of the longer axis (up to 32 texels, longer than a
    // period) averages away.
    let (_, rms) = errors(
        "a_footprint_along_the_stripes_keeps_their_contrast",
        |rng, k| {
            let across = k.normalize();
            let width = rng.random_range(0.25..2.0);
            let length = width * rng.random_range(1.0..16.0);
            (across.perp() * length, across * width)
        },
    );
    assert!(rms < 0.03, "rms {rms}");
}

#[test]
fn random_footprints_match_the_box_integral() {
    // Any direction, anisotropy up to 16 (the limit): the probes' mean follows
    // the integral of the whole parallelogram.
    let (_, rms) = errors("random_footprints_match_the_box_integral", |rng, _| {
        let direction = |rng: &mut rand::rngs::StdRng| {
            let angle = rng.random_range(0.0..TAU);
            DVec2::new(angle.cos(), angle.sin())
        };
        let width = rng.random_range(0.25..2.0);
        let length = width * rng.random_range(1.0..16.0);
        (direction(rng) * length, direction(rng) * width)
    });
    assert!(rms < 0.03, "rms {rms}");
}

#[test]
fn past_the_limit_the_filter_blurs_across() {
    // 64 texels along 16-texel stripes, none across, through a stripe's
    // peak: 16 probes of level 2 (4 texels wide), so the stripe loses
    // contrast as a box of 4 to 8 texels would (a level-2 texel is a 4-texel
    // box, and bilinear taps between two of them span 8), but no more. An
    // isotropic filter would read level 6, the mean, 1/2.
    let mut set = TextureSet::default();
    let k = DVec2::new(1.0 / 16.0, 0.0);
    let id = cosine(&mut set, k);
    let st = Vec2::new(16.0 / SIDE as f32, 0.37);
    let along = Vec2::new(0.0, 64.0 / SIDE as f32);
    let got = f64::from(set.sample(id, st, along, Vec2::ZERO).x);
    let boxed = |texels: f64| 0.5 + 0.5 * sinc(PI * texels / 16.0);
    assert!(
        (boxed(8.0) - 0.01..=boxed(4.0) + 0.01).contains(&got),
        "{got}: not between {} and {}",
        boxed(8.0),
        boxed(4.0)
    );
}
