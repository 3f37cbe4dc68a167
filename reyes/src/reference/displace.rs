//! Displacement: a diced point moves along the exact normal of the
//! undisplaced surface, and a displaced grid takes its shading normals from
//! its own displaced points. The GPU does the same in
//! `shaders/reyes/dice_shade_sample.wgsl`.

use glam::Vec3;

use super::dice::{degenerate, displacement_normal};
use crate::dicing::{GridSize, patch_position};
use crate::displacement::PreparedDisplacement;

/// The parameter `a + (b - a) * s`, written once for both implementations.
pub fn lerp_param(a: f32, b: f32, s: f32) -> f32 {
    a + (b - a) * s
}

/// The point of the input patch at `(u, v)` ([`patch_position`]), displaced
/// when the object is: `P + n * h(u, v) * scale` with `n` the
/// [`displacement_normal`]; and whether it moved beyond the bound. `None`
/// when the height cannot be evaluated on the CPU (a user WGSL function
/// without a Rust twin).
pub fn displaced_point(
    patch: &[Vec3; 16],
    u: f32,
    v: f32,
    displacement: Option<&PreparedDisplacement>,
) -> Option<(Vec3, bool)> {
    let position = patch_position(patch, u, v);
    let Some(displacement) = displacement else {
        return Some((position, false));
    };
    let offset = displacement.height(u, v)? * displacement.scale;
    let normal = displacement_normal(patch, u, v);
    Some((
        position + normal * offset,
        displacement.exceeds_bound(offset),
    ))
}

/// The unit normal of a displaced grid at `(i, j)`, not yet facing the
/// eye: `normalize(dS x dT)` with `dS = Q(i+1, j) - Q(i-1, j)` (central
/// differences), one-sided at the grid's edges, `dT` likewise along j;
/// `None` when degenerate (e.g. on a collapsed patch edge).
pub fn grid_normal(positions: &[Vec3], size: GridSize, i: u32, j: u32) -> Option<Vec3> {
    let at = |i: u32, j: u32| positions[(j * (size.nu + 1) + i) as usize];
    let d_s = at((i + 1).min(size.nu), j) - at(i.saturating_sub(1), j);
    let d_t = at(i, (j + 1).min(size.nv)) - at(i, j.saturating_sub(1));
    let n = d_s.cross(d_t);
    if degenerate(n, d_s, d_t) {
        return None;
    }
    let n = n.normalize_or_zero();
    (n != Vec3::ZERO).then_some(n)
}

#[cfg(test)]
mod tests {
    use glam::Vec4;

    use super::*;
    use crate::dicing::GridSize;
    use crate::displacement::HeightSource;
    use crate::reference::dice::dice;

    /// A flat unit square in the z = 0 plane, normal +z.
    fn square() -> [Vec3; 16] {
        std::array::from_fn(|k| Vec3::new((k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0, 0.0))
    }

    fn sines(scale: f32) -> PreparedDisplacement {
        PreparedDisplacement {
            source: HeightSource::Sines,
            scale,
            bound: scale.abs(),
            tiling: 1.0,
        }
    }

    const WHOLE: Vec4 = Vec4::new(0.0, 0.0, 1.0, 1.0);

    #[test]
    fn points_move_along_the_normal_by_height_times_scale() {
        let d = sines(0.5);
        let eye = Vec3::new(0.5, 0.5, 5.0).extend(1.0);
        let size = GridSize::FIXED;
        let out = dice(&square(), WHOLE, size, None, eye, Some(&d)).unwrap();
        for j in 0..=size.nv {
            for i in 0..=size.nu {
                let (s, t) = (i as f32 / 15.0, j as f32 / 15.0);
                let p = out.positions[out.index(i, j)];
                assert!((p.x - s).abs() < 1e-6 && (p.y - t).abs() < 1e-6);
                let expected = crate::displacement::sines::sines(s, t) * 0.5;
                assert!((p.z - expected).abs() < 1e-6, "{p} {expected}");
            }
        }
        assert_eq!(out.bound_exceeded, 0);
        // A flat, undisplaced grid keeps the plane's normal.
        let flat = dice(&square(), WHOLE, size, None, eye, Some(&sines(0.0))).unwrap();
        for n in flat.normals {
            assert!((n - Vec3::Z).length() < 1e-6, "{n}");
        }
    }

    #[test]
    fn a_piece_uses_its_rectangle_of_the_patch_parameters() {
        let d = sines(1.0);
        let eye = Vec3::new(0.5, 0.5, 5.0).extend(1.0);
        let uv = Vec4::new(0.5, 0.25, 0.75, 0.5);
        let size = GridSize { nu: 4, nv: 8 };
        let out = dice(&square(), uv, size, None, eye, Some(&d)).unwrap();
        let corner = out.positions[out.index(4, 8)];
        let expected = crate::displacement::sines::sines(0.75, 0.5);
        assert!((corner.z - expected).abs() < 1e-6);
        assert!((corner.x - 0.75).abs() < 1e-6 && (corner.y - 0.5).abs() < 1e-6);
    }

    #[test]
    fn a_small_bound_is_counted() {
        let mut d = sines(1.0);
        d.bound = 0.5;
        let eye = Vec3::new(0.5, 0.5, 5.0).extend(1.0);
        let out = dice(&square(), WHOLE, GridSize::FIXED, None, eye, Some(&d)).unwrap();
        assert!(out.bound_exceeded > 0);
    }
}
