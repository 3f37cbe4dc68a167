//! Latitude-longitude environment maps: RenderMan's `environment(name, R)`
//! on the CPU. `texture_environment` and its helpers in
//! `shaders/reyes/library_texture.wgsl` repeat every function here
//! operation for operation.
//!
//! The convention is the RenderMan Interface Specification 3.2's
//! (`MakeLatLongEnvironment`): longitude runs from 0 at the left edge of
//! the picture (`s = 0`) to 360 degrees at the right (`s = 1`), latitude
//! from +90 degrees at the top (`t = 0`, the north pole) to -90 at the
//! bottom, and the direction of a point of the picture is
//! `(cos lon cos lat, sin lon cos lat, sin lat)`, in world space: +z is
//! north. Inverted, a direction `R` reads
//!
//! * `s = atan2(R.y, R.x) / 2 pi` (wrapped periodically, whatever the
//!   texture's own wrap mode), and
//! * `t = 1/2 - atan2(R.z, |R.xy|) / pi` (clamped).
//!
//! The footprint is the change of `(s, t)` that a change `dR` of the
//! direction makes, to first order (the Jacobian of the map above); a
//! zero `dR` is a zero footprint (level 0, bilinear). At the poles the
//! Jacobian is infinite and the lookup takes the coarsest level, as for
//! any non-finite footprint; at a pole itself the longitude is taken as 0. A zero or non-finite `R`, or an unknown id,
//! gives transparent black.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3, Vec4};

use super::Wrap;
use super::gpu::TextureInfo;
use super::sample::{filter, is_finite};

/// The `(s, t)` that direction `r` reads (not wrapped yet).
pub fn latlong_st(r: Vec3) -> Vec2 {
    let rho = (r.x * r.x + r.y * r.y).sqrt();
    // At a pole every longitude is the same point; atan2 of two zeros
    // depends on their signs (and differs between GPUs): take 0.
    let longitude = if rho == 0.0 { 0.0 } else { r.y.atan2(r.x) };
    let latitude = r.z.atan2(rho);
    Vec2::new(longitude / TAU, 0.5 - latitude / PI)
}

/// The change of `(s, t)` that a change `dr` of the direction `r` makes,
/// to first order: `ds = (x dy - y dx) / (2 pi rho^2)` and
/// `dt = -(rho^2 dz - z (x dx + y dy)) / (pi rho |r|^2)`, `rho = |r.xy|`.
pub fn latlong_axis(r: Vec3, dr: Vec3) -> Vec2 {
    if dr.x == 0.0 && dr.y == 0.0 && dr.z == 0.0 {
        return Vec2::ZERO;
    }
    let rho2 = r.x * r.x + r.y * r.y;
    let rho = rho2.sqrt();
    let r2 = rho2 + r.z * r.z;
    let ds = (r.x * dr.y - r.y * dr.x) / (TAU * rho2);
    let dt = -(rho2 * dr.z - r.z * (r.x * dr.x + r.y * dr.y)) / (PI * rho * r2);
    Vec2::new(ds, dt)
}

/// Texture `id` of `infos` as a latitude-longitude environment map, seen
/// along `r`, filtered over the footprint of the direction's changes
/// `dr_du` and `dr_dv` across the shading point.
pub(super) fn environment(
    infos: &[TextureInfo],
    texels: &[[u32; 2]],
    id: u32,
    r: Vec3,
    dr_du: Vec3,
    dr_dv: Vec3,
) -> Vec4 {
    let Some(info) = infos.get(id as usize) else {
        return Vec4::ZERO;
    };
    if !is_finite(r.x) || !is_finite(r.y) || !is_finite(r.z) {
        return Vec4::ZERO;
    }
    if r.x == 0.0 && r.y == 0.0 && r.z == 0.0 {
        return Vec4::ZERO;
    }
    // Longitude goes round; latitude stops at the poles.
    let info = TextureInfo {
        wrap_s: Wrap::Periodic.code(),
        wrap_t: Wrap::Clamp.code(),
        ..*info
    };
    filter(
        &info,
        texels,
        latlong_st(r),
        latlong_axis(r, dr_du),
        latlong_axis(r, dr_dv),
    )
}
