//! The lens: Shirley and Chiu's concentric map from the lens square to the
//! unit disk, and the boxes on the disk that bound its strata (INTERVAL's
//! lens box per time interval).

use glam::Vec2;

#[cfg(doc)]
use super::UvtTables;

/// How far, in lens units (the unit disk), the lens box of an INTERVAL
/// interval ([`UvtTables::interval_lens`]) reaches past the region's image
/// as sampled: more than the bulge of the region's curved sides between
/// the samples taken along each side, and more than f32 rounding of a jittered
/// lens position.
pub const LENS_BOX_MARGIN: f32 = 1.0 / 512.0;
/// Samples per side of a lens stratum when its image on the disk is bounded.
const LENS_BOX_STEPS: u32 = 64;

/// Shirley and Chiu's concentric map from `[0, 1]^2` to the unit disk.
pub fn concentric_disk(a: f32, b: f32) -> Vec2 {
    let (x, y) = (2.0 * a - 1.0, 2.0 * b - 1.0);
    if x == 0.0 && y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, phi) = if x.abs() > y.abs() {
        (x, std::f32::consts::FRAC_PI_4 * (y / x))
    } else {
        (
            y,
            std::f32::consts::FRAC_PI_2 - std::f32::consts::FRAC_PI_4 * (x / y),
        )
    };
    Vec2::new(r * phi.cos(), r * phi.sin())
}

/// The bounding box, on the unit disk, of lens stratum `(col, row)` of a
/// `k x k` grid on the lens square, grown by [`LENS_BOX_MARGIN`] and
/// clamped to the disk's box: `[lo, hi]`.
///
/// The concentric map is continuous and maps the stratum's inside to the
/// inside of its image, so the image's extremes lie on the image of the
/// stratum's boundary, which is sampled here.
pub fn lens_stratum_box(col: u32, row: u32, k: u32) -> [Vec2; 2] {
    let (a0, b0) = (col as f32 / k as f32, row as f32 / k as f32);
    let (a1, b1) = ((col + 1) as f32 / k as f32, (row + 1) as f32 / k as f32);
    let mut lo = Vec2::INFINITY;
    let mut hi = Vec2::NEG_INFINITY;
    for step in 0..=LENS_BOX_STEPS {
        let f = step as f32 / LENS_BOX_STEPS as f32;
        let (a, b) = (a0 + (a1 - a0) * f, b0 + (b1 - b0) * f);
        for p in [
            concentric_disk(a, b0),
            concentric_disk(a, b1),
            concentric_disk(a0, b),
            concentric_disk(a1, b),
        ] {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    [
        (lo - Vec2::splat(LENS_BOX_MARGIN)).max(Vec2::splat(-1.0)),
        (hi + Vec2::splat(LENS_BOX_MARGIN)).min(Vec2::splat(1.0)),
    ]
}
