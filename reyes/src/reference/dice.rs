//! Dicing: evaluate a piece of an input patch on its grid of points, with
//! shading normals, displacement, and (rate dicing) border points placed
//! on their edges' vertices.

use glam::{Vec3, Vec4};

use super::displace::{Displacer, displaced_point, grid_normal};
use crate::bezier;
use crate::camera::{HomogeneousEye, towards_eye};
use crate::dicing::{
    BorderPoint, GridSize, PieceEdges, border_point, chord_point, grid_param, patch_position,
};
use crate::nonfinite::{Sources, dice_sources};
use crate::params::{DEGENERATE_NORMAL_REL_EPS, DEGENERATE_PARAM_MAX, DEGENERATE_PARAM_MIN};

/// A diced grid: point `(i, j)` (i along u, j along v) is at index
/// `j * (nu + 1) + i`.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Micropolygons along u and v.
    pub size: GridSize,
    /// World-space positions (displaced, and on their edges' chords).
    pub positions: Vec<Vec3>,
    /// Unit normals facing the eye (two-sided shading).
    pub normals: Vec<Vec3>,
    /// Grid points displaced further than their object's bound (see
    /// [`crate::displacement::PreparedDisplacement::exceeds_bound`]).
    pub bound_exceeded: u64,
    /// Per point, the stages that turned its position non-finite
    /// ([`dice_sources`]; the camera's are added when it is projected).
    pub non_finite: Vec<Sources>,
}

impl Grid {
    /// Index of point `(i, j)`.
    pub fn index(&self, i: u32, j: u32) -> usize {
        (j * (self.size.nu + 1) + i) as usize
    }
}

/// Dices the piece with rectangle `uv` of input patch `patch` into `size`:
/// point `(i, j)` is at `u = u0 + (u1 - u0) (i / nu)`, `v` likewise.
///
/// 1. Its position is [`displaced_point`] (the input patch at `(u, v)`,
///    [`crate::dicing::patch_position`], moved along the exact normal by the
///    height when displaced).
/// 2. Its shading normal is the exact normal [`surface_normal`] or, when
///    displaced, the normal of the displaced grid ([`grid_normal`]), turned
///    to face the eye.
/// 3. With `edges` (rate dicing), a border point that lies between two
///    vertices of its edge moves to the nearer of them, or, at a corner of
///    the piece, onto the chord between them ([`border_point`]); its normal
///    stays its own.
/// 4. Its final position is checked for the stage that may have turned it
///    non-finite ([`dice_sources`]).
///
/// Returns `None` when a height cannot be evaluated on the CPU (a user WGSL
/// function without a Rust twin).
pub fn dice(
    patch: &[Vec3; 16],
    uv: Vec4,
    size: GridSize,
    edges: Option<&PieceEdges>,
    eye: HomogeneousEye,
    displacement: Option<&Displacer<'_>>,
) -> Option<Grid> {
    let (columns, rows) = (size.nu + 1, size.nv + 1);
    let param = |i: u32, j: u32| {
        (
            grid_param(uv.x, uv.z, i, size.nu),
            grid_param(uv.y, uv.w, j, size.nv),
        )
    };
    let mut grid = Grid {
        size,
        positions: Vec::with_capacity((columns * rows) as usize),
        normals: Vec::new(),
        bound_exceeded: 0,
        non_finite: Vec::new(),
    };
    for j in 0..rows {
        for i in 0..columns {
            let (u, v) = param(i, j);
            let (point, exceeded) = displaced_point(patch, u, v, displacement)?;
            grid.bound_exceeded += u64::from(exceeded);
            grid.positions.push(point);
        }
    }
    for j in 0..rows {
        for i in 0..columns {
            let (u, v) = param(i, j);
            let k = grid.index(i, j);
            let position = grid.positions[k];
            let displaced = displacement
                .and_then(|_| grid_normal(&grid.positions, size, i, j))
                .map(|n| {
                    if n.dot(towards_eye(eye, position)) < 0.0 {
                        -n
                    } else {
                        n
                    }
                });
            let normal = displaced
                .unwrap_or_else(|| surface_normal(patch, u, v, bezier::position(patch, u, v), eye));
            grid.normals.push(normal);
        }
    }
    if let Some(edges) = edges {
        for j in 0..rows {
            for i in 0..columns {
                let (u, v) = param(i, j);
                let k = grid.index(i, j);
                match border_point(size, edges, i, j, u, v) {
                    BorderPoint::Vertex => {}
                    BorderPoint::Chord { a, b, f } => {
                        let (qa, _) = displaced_point(patch, a.0, a.1, displacement)?;
                        let (qb, _) = displaced_point(patch, b.0, b.1, displacement)?;
                        grid.positions[k] = chord_point(qa, qb, f);
                    }
                    BorderPoint::Snapped { at } => {
                        grid.positions[k] = displaced_point(patch, at.0, at.1, displacement)?.0;
                    }
                }
            }
        }
    }
    // After the chords, as the GPU checks the point's final position.
    for j in 0..rows {
        for i in 0..columns {
            let (u, v) = param(i, j);
            let moved = grid.positions[grid.index(i, j)];
            let sources = dice_sources(patch_position(patch, u, v), displacement.is_some(), moved);
            grid.non_finite.push(sources);
        }
    }
    Some(grid)
}

/// Whether `n = a x b` is degenerate: `|n|^2 <= eps * |a|^2 |b|^2`, `|n|^2 == 0`,
/// or not finite.
pub(crate) fn degenerate(n: Vec3, a: Vec3, b: Vec3) -> bool {
    let n2 = n.length_squared();
    !n2.is_finite()
        || n2 <= DEGENERATE_NORMAL_REL_EPS * (a.length_squared() * b.length_squared())
        || n2 == 0.0
}

/// `dP/du x dP/dv` of the input patch at `(u, v)`, re-evaluated at
/// `(clamp(u, 0.01, 0.99), clamp(v, 0.01, 0.99))` when degenerate (a
/// collapsed patch edge, where a tangent vanishes); `None` when that is
/// degenerate too. Clamped in the input patch's parameters, so that every
/// piece finds the same normal at the same `(u, v)`.
fn tangent_normal(patch: &[Vec3; 16], u: f32, v: f32) -> Option<Vec3> {
    let e = bezier::evaluate(patch, u, v);
    let n = e.d_ds.cross(e.d_dt);
    if !degenerate(n, e.d_ds, e.d_dt) {
        return Some(n);
    }
    let inner = bezier::evaluate(
        patch,
        u.clamp(DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
        v.clamp(DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
    );
    let n = inner.d_ds.cross(inner.d_dt);
    (!degenerate(n, inner.d_ds, inner.d_dt)).then_some(n)
}

/// The unit geometric normal `normalize(dP/du x dP/dv)` at `(u, v)`, not
/// turned towards the eye: the direction displacement moves a point (zero
/// where even the clamped re-evaluation is degenerate: the point is not
/// displaced).
pub fn displacement_normal(patch: &[Vec3; 16], u: f32, v: f32) -> Vec3 {
    tangent_normal(patch, u, v).map_or(Vec3::ZERO, Vec3::normalize_or_zero)
}

/// The unit shading normal at `(u, v)` of the point at `position`, facing
/// `eye`; never NaN: the exact normal `dP/du x dP/dv` (re-evaluated at the
/// clamped parameters where degenerate, as for [`displacement_normal`]),
/// else the direction towards the eye ([`towards_eye`]; +z if even that
/// is zero), flipped if it faces away from the eye.
pub fn surface_normal(
    patch: &[Vec3; 16],
    u: f32,
    v: f32,
    position: Vec3,
    eye: HomogeneousEye,
) -> Vec3 {
    let to_eye = towards_eye(eye, position);
    let n = tangent_normal(patch, u, v).unwrap_or(to_eye);
    let mut n = n.normalize_or_zero();
    if n == Vec3::ZERO {
        // Only reachable when the eye lies on the surface point itself.
        n = Vec3::Z;
    }
    if n.dot(to_eye) < 0.0 { -n } else { n }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dicing::EdgeSpacing;
    use crate::test_random::{fresh_rng, random_vec3};

    /// A T-junction: the left half of a patch diced 1 x 2 against its
    /// right half split in v and each quarter diced 1 x 4, all with the
    /// shared line `u = 1/2` at spacing 1/2. Every point the quarters put
    /// on that line must be, bit for bit, one of the left half's points
    /// there: a point only near its chord lets samples through between
    /// the two sides' micropolygon edges.
    #[test]
    fn a_finer_border_is_made_of_the_coarser_sides_vertices() {
        let (seed, mut rng) = fresh_rng("a_finer_border_is_made_of_the_coarser_sides_vertices");
        let eye = Vec4::new(0.0, 0.0, 10.0, 1.0);
        let half = EdgeSpacing::fixed(1);
        let fine = EdgeSpacing::fixed(4);
        for _ in 0..100 {
            let patch: [Vec3; 16] = std::array::from_fn(|k| {
                Vec3::new((k % 4) as f32, (k / 4) as f32, 0.0) + random_vec3(&mut rng, 0.4)
            });
            let left = dice(
                &patch,
                Vec4::new(0.0, 0.0, 0.5, 1.0),
                GridSize { nu: 1, nv: 2 },
                Some(&[fine, fine, fine, half]),
                eye,
                None,
            )
            .expect("an undisplaced grid evaluates");
            let shared: Vec<Vec3> = (0..=2).map(|j| left.positions[left.index(1, j)]).collect();
            for v0 in [0.0, 0.5] {
                let quarter = dice(
                    &patch,
                    Vec4::new(0.5, v0, 1.0, v0 + 0.5),
                    GridSize { nu: 1, nv: 4 },
                    Some(&[fine, fine, half, fine]),
                    eye,
                    None,
                )
                .expect("an undisplaced grid evaluates");
                for j in 0..=4 {
                    let point = quarter.positions[quarter.index(0, j)];
                    assert!(
                        shared.iter().any(|s| s.to_array().map(f32::to_bits)
                            == point.to_array().map(f32::to_bits)),
                        "seed {seed}: the quarter at v0 = {v0} puts point {j} of its border at {point}, none of the coarser side's {shared:?}"
                    );
                }
            }
        }
    }
}
