//! Latitude-longitude environment lookups (`super::environment`): the
//! directions of known texel centres, worked from the RenderMan Interface
//! 3.2's formula for the direction of a point of the picture, read back
//! those texels; the seam wraps and the poles clamp whatever the texture's
//! own wrap modes; the footprint is the derivative of the mapping.

use std::f64::consts::PI;

use glam::{Vec2, Vec3, Vec4};

use super::*;
use crate::texture::environment as latlong;

const WIDTH: u32 = 16;
const HEIGHT: u32 = 8;

/// A texture whose texel `(i, j)` holds `(i, j, 0, 1)` (exact in f16), with
/// the wrap modes an environment lookup must not follow.
fn coordinates() -> (TextureSet, TextureId) {
    let texels = (0..HEIGHT)
        .flat_map(|j| (0..WIDTH).map(move |i| Vec4::new(i as f32, j as f32, 0.0, 1.0)))
        .collect();
    let mut set = TextureSet::new(TextureBudget::DEFAULT);
    let id = set
        .add_linear(
            Path::new("coordinates"),
            WIDTH,
            HEIGHT,
            texels,
            Wrap::Black,
            Wrap::Black,
        )
        .unwrap();
    (set, id)
}

/// The direction of picture point `(s, t)` (t = 0 at the top), from the
/// specification: longitude 0 at the left to 360 degrees at the right,
/// latitude +90 at the top to -90 at the bottom, and
/// `(cos lon cos lat, sin lon cos lat, sin lat)`.
fn direction(s: f64, t: f64) -> Vec3 {
    let longitude = 2.0 * PI * s;
    let latitude = PI / 2.0 - PI * t;
    Vec3::new(
        (longitude.cos() * latitude.cos()) as f32,
        (longitude.sin() * latitude.cos()) as f32,
        latitude.sin() as f32,
    )
}

fn look(set: &TextureSet, id: TextureId, r: Vec3) -> Vec4 {
    set.environment(id, r, Vec3::ZERO, Vec3::ZERO)
}

#[test]
fn the_direction_of_each_texel_centre_reads_that_texel() {
    let (set, id) = coordinates();
    for j in 0..HEIGHT {
        for i in 0..WIDTH {
            let s = (f64::from(i) + 0.5) / f64::from(WIDTH);
            let t = (f64::from(j) + 0.5) / f64::from(HEIGHT);
            // Any length: only the direction counts.
            for scale in [1.0, 7.5] {
                let got = look(&set, id, direction(s, t) * scale);
                let want = Vec4::new(i as f32, j as f32, 0.0, 1.0);
                assert!(
                    (got - want).abs().max_element() < 1e-3,
                    "texel ({i}, {j}) at scale {scale}: {got}"
                );
            }
        }
    }
}

#[test]
fn longitude_wraps_across_the_seam_and_latitude_clamps_at_the_poles() {
    let (set, id) = coordinates();
    // Longitude 0 is the left edge of texel 0: halfway between the last
    // column and the first, as periodic wrapping blends them (a Black
    // texture would fade there).
    let seam = look(&set, id, direction(0.0, 0.5 - 0.5 / f64::from(HEIGHT)));
    assert!((seam.x - 7.5).abs() < 1e-3, "{seam}");
    assert!(
        (seam.y - 3.0).abs() < 1e-3 && (seam.w - 1.0).abs() < 1e-3,
        "{seam}"
    );
    // Just before the seam, from the other side: mostly the last column.
    let before = look(&set, id, direction(1.0 - 0.25 / f64::from(WIDTH), 0.5));
    assert!(
        (before.x - (0.25 * 0.0 + 0.75 * 15.0)).abs() < 1e-2,
        "{before}"
    );
    // The poles read the top and bottom rows, whole (clamped, not black).
    let north = look(&set, id, Vec3::Z);
    assert!(
        north.y.abs() < 1e-6 && (north.w - 1.0).abs() < 1e-6,
        "{north}"
    );
    let south = look(&set, id, -Vec3::Z * 3.0);
    assert!(
        (south.y - (HEIGHT - 1) as f32).abs() < 1e-6 && (south.w - 1.0).abs() < 1e-6,
        "{south}"
    );
}

#[test]
fn a_zero_or_non_finite_direction_or_an_unknown_id_is_transparent_black() {
    let (set, id) = coordinates();
    for r in [
        Vec3::ZERO,
        Vec3::new(f32::NAN, 0.0, 1.0),
        Vec3::new(f32::INFINITY, 0.0, 0.0),
    ] {
        assert_eq!(look(&set, id, r), Vec4::ZERO, "{r}");
    }
    assert_eq!(look(&set, TextureId(7), Vec3::X), Vec4::ZERO);
}

#[test]
fn the_footprint_axis_is_the_derivative_of_the_mapping() {
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        // xorshift: deterministic, no seed to print.
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..200 {
        let r = glam::DVec3::new(next(), next(), 0.8 * next());
        let dr = glam::DVec3::new(next(), next(), next());
        // The mapping in f64, differentiated numerically.
        let st = |r: glam::DVec3| {
            glam::DVec2::new(
                r.y.atan2(r.x) / (2.0 * PI),
                0.5 - r.z.atan2(r.x.hypot(r.y)) / PI,
            )
        };
        let h = 1e-6;
        let mut step = st(r + dr * h) - st(r - dr * h);
        // Across the seam, s jumps by a whole turn.
        step.x -= step.x.round();
        let want = step / (2.0 * h);
        let got = latlong::latlong_axis(r.as_vec3(), dr.as_vec3());
        let scale = 1.0 + want.abs().max_element();
        assert!(
            (got.as_dvec2() - want).abs().max_element() < 1e-3 * scale,
            "r {r}, dr {dr}: {got} against {want}"
        );
    }
    assert_eq!(latlong::latlong_axis(Vec3::Z, Vec3::ZERO), Vec2::ZERO);
}

#[test]
fn a_longer_footprint_averages_along_its_length() {
    // Columns alternating 0 and 1: a texel centre reads 0 or 1, and probes
    // a texel apart along s, or any coarser level, read 1/2.
    let texels = (0..HEIGHT)
        .flat_map(|_| (0..WIDTH).map(|i| Vec4::new((i % 2) as f32, 0.0, 0.0, 1.0)))
        .collect();
    let mut set = TextureSet::new(TextureBudget::DEFAULT);
    let id = set
        .add_linear(
            Path::new("stripes"),
            WIDTH,
            HEIGHT,
            texels,
            Wrap::Clamp,
            Wrap::Clamp,
        )
        .unwrap();
    let r = direction(5.5 / f64::from(WIDTH), 0.5 / f64::from(HEIGHT) + 0.25);
    assert!((look(&set, id, r).x - 1.0).abs() < 1e-3);
    // A change of direction across 4 texels in s (a quarter turn in
    // longitude spans 4 of the 16 columns) and none across: 4 probes at
    // level 0, one per texel.
    let dr = Vec3::new(-r.y, r.x, 0.0) * (4.0 * std::f32::consts::TAU / WIDTH as f32);
    let probes = sample::probes(
        set.info(id).unwrap(),
        latlong::latlong_axis(r, dr),
        Vec2::ZERO,
    );
    assert_eq!((probes.count, probes.lod), (4, 0.0), "{probes:?}");
    let blurred = set.environment(id, r, dr, Vec3::ZERO);
    assert!((blurred.x - 0.5).abs() < 1e-3, "{blurred}");
    // The same change along v instead.
    assert_eq!(set.environment(id, r, Vec3::ZERO, dr), blurred);
}

/// The value of `const NAME: f32 = X;` in the WGSL library.
fn wgsl_f32(name: &str) -> f32 {
    let line = TEXTURE_WGSL
        .lines()
        .find(|l| l.starts_with(&format!("const {name}: f32 = ")))
        .unwrap_or_else(|| panic!("no constant {name}"));
    line.rsplit(' ')
        .next()
        .unwrap()
        .trim_end_matches(';')
        .parse()
        .unwrap()
}

#[test]
fn the_wgsl_constants_are_the_rust_ones() {
    assert_eq!(wgsl_f32("TEXTURE_PI"), std::f32::consts::PI);
    assert_eq!(wgsl_f32("TEXTURE_TAU"), std::f32::consts::TAU);
}
