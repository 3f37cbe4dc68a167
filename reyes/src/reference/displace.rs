//! Dicing a displaced piece: every grid point moves along the exact normal
//! of the undisplaced surface, then shading normals are taken from the
//! displaced grid itself. The GPU does the same in
//! `shaders/reyes/dice_shade_sample.wgsl` (phases 1 and 2).

use glam::{Vec3, Vec4};

use super::dice::{GRID_LEN, Grid, degenerate, displacement_normal, surface_point};
use crate::bezier;
use crate::displacement::PreparedDisplacement;
use crate::params::{GRID_POINTS, GRID_QUADS};

/// A displaced grid and how many of its points left the displacement bound.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplacedGrid {
    /// Displaced positions and their shading normals (facing the eye).
    pub grid: Grid,
    /// Grid points displaced further than the bound (see
    /// [`PreparedDisplacement::exceeds_bound`]).
    pub bound_exceeded: u64,
}

/// The parameter `a + (b - a) * s`, written once for both implementations.
pub fn lerp_param(a: f32, b: f32, s: f32) -> f32 {
    a + (b - a) * s
}

/// Dices a displaced piece whose rectangle in its input patch's parameters
/// is `uv = (u0, v0, u1, v1)`.
///
/// 1. Point `(i, j)` at `s = i / 15`, `t = j / 15` is `P + n * h * scale`,
///    with `P` the patch position, `n` its [`displacement_normal`] and `h`
///    the height at `u = u0 + (u1 - u0) s`, `v = v0 + (v1 - v0) t`.
///    Returns `None` when the height cannot be evaluated on the CPU (a user
///    WGSL function without a Rust twin).
/// 2. The shading normal is `normalize(dS x dT)` of the displaced points
///    `Q`: `dS = Q(i+1, j) - Q(i-1, j)` (central difference), one-sided at
///    the grid's edges (`Q(1, j) - Q(0, j)`, `Q(15, j) - Q(14, j)`), and
///    `dT` likewise along j. It is turned to face the eye. Where it is
///    degenerate (a collapsed patch edge), the exact normal of the
///    undisplaced surface is used, as for undisplaced grids.
pub fn dice_displaced(
    points: &[Vec3; 16],
    uv: Vec4,
    eye: Vec3,
    displacement: &PreparedDisplacement,
) -> Option<DisplacedGrid> {
    let mut positions = [Vec3::ZERO; GRID_LEN];
    let mut fallbacks = [Vec3::ZERO; GRID_LEN];
    let mut bound_exceeded = 0;
    for j in 0..GRID_POINTS {
        for i in 0..GRID_POINTS {
            let s = i as f32 / GRID_QUADS as f32;
            let t = j as f32 / GRID_QUADS as f32;
            let position = bezier::position(points, s, t);
            let normal = displacement_normal(points, s, t);
            let u = lerp_param(uv.x, uv.z, s);
            let v = lerp_param(uv.y, uv.w, t);
            let offset = displacement.height(u, v)? * displacement.scale;
            bound_exceeded += u64::from(displacement.exceeds_bound(offset));
            positions[j * GRID_POINTS + i] = position + normal * offset;
            // The undisplaced surface's exact shading normal.
            fallbacks[j * GRID_POINTS + i] = surface_point(points, s, t, eye).1;
        }
    }
    let mut normals = [Vec3::ZERO; GRID_LEN];
    for j in 0..GRID_POINTS {
        for i in 0..GRID_POINTS {
            let k = j * GRID_POINTS + i;
            normals[k] = match grid_normal(&positions, i, j) {
                Some(n) => {
                    if n.dot(eye - positions[k]) < 0.0 {
                        -n
                    } else {
                        n
                    }
                }
                None => fallbacks[k],
            };
        }
    }
    Some(DisplacedGrid {
        grid: Grid { positions, normals },
        bound_exceeded,
    })
}

/// The unit normal of the displaced grid at `(i, j)` from neighbour
/// differences (see [`dice_displaced`]), not yet facing the eye; `None`
/// when degenerate.
fn grid_normal(positions: &[Vec3; GRID_LEN], i: usize, j: usize) -> Option<Vec3> {
    let at = |i: usize, j: usize| positions[j * GRID_POINTS + i];
    let last = GRID_POINTS - 1;
    let d_s = at((i + 1).min(last), j) - at(i.saturating_sub(1), j);
    let d_t = at(i, (j + 1).min(last)) - at(i, j.saturating_sub(1));
    let n = d_s.cross(d_t);
    if degenerate(n, d_s, d_t) {
        return None;
    }
    let n = n.normalize_or_zero();
    (n != Vec3::ZERO).then_some(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::displacement::HeightSource;

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

    #[test]
    fn points_move_along_the_normal_by_height_times_scale() {
        let d = sines(0.5);
        let eye = Vec3::new(0.5, 0.5, 5.0);
        let out = dice_displaced(&square(), Vec4::new(0.0, 0.0, 1.0, 1.0), eye, &d).unwrap();
        for j in 0..GRID_POINTS {
            for i in 0..GRID_POINTS {
                let (s, t) = (i as f32 / 15.0, j as f32 / 15.0);
                let p = out.grid.positions[j * GRID_POINTS + i];
                assert!((p.x - s).abs() < 1e-6 && (p.y - t).abs() < 1e-6);
                let expected = crate::displacement::sines::sines(s, t) * 0.5;
                assert!((p.z - expected).abs() < 1e-6, "{p} {expected}");
            }
        }
        assert_eq!(out.bound_exceeded, 0);
        // A flat, undisplaced grid keeps the plane's normal.
        let flat = dice_displaced(&square(), Vec4::new(0.0, 0.0, 1.0, 1.0), eye, &sines(0.0));
        for n in flat.unwrap().grid.normals {
            assert!((n - Vec3::Z).length() < 1e-6, "{n}");
        }
    }

    #[test]
    fn a_piece_uses_its_rectangle_of_the_patch_parameters() {
        let d = sines(1.0);
        let eye = Vec3::new(0.5, 0.5, 5.0);
        let uv = Vec4::new(0.5, 0.25, 0.75, 0.5);
        let out = dice_displaced(&square(), uv, eye, &d).unwrap();
        let corner = out.grid.positions[GRID_POINTS * GRID_POINTS - 1];
        let expected = crate::displacement::sines::sines(0.75, 0.5);
        assert!((corner.z - expected).abs() < 1e-6);
    }

    #[test]
    fn a_small_bound_is_counted() {
        let mut d = sines(1.0);
        d.bound = 0.5;
        let eye = Vec3::new(0.5, 0.5, 5.0);
        let out = dice_displaced(&square(), Vec4::new(0.0, 0.0, 1.0, 1.0), eye, &d).unwrap();
        assert!(out.bound_exceeded > 0);
    }
}
