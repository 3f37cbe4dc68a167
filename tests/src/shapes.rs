//! Closed models of bicubic Bezier patches for the crack tests.
//!
//! A crack test is only meaningful on a surface that is closed *as data*:
//! wherever two patches meet, their boundary control points must be the same
//! numbers bit for bit, so that the only way a gap can appear in a render is
//! through how the renderer splits and dices. Both spheres here therefore
//! build every control point that lies on a shared boundary exactly once (in
//! a table keyed by its position in an integer lattice) and copy it into every
//! patch that uses it; [`unmatched_edges`] checks the result.
//!
//! Geometry is done in `f64` arrays (the points are rounded to `f32` once)
//! and converted to the renderer's points with `From<[f32; 3]>`.

use std::collections::HashMap;

use reyes::dicing::edge_indices;
use reyes::model::{Model, Patch};

/// `1 / 3` steps of the cubic Bernstein parameter: control points from
/// samples at `t = 0, 1/3, 2/3, 1`, the inverse of the Bernstein matrix at
/// those parameters (`P1 = (-5 S0 + 18 S1 - 9 S2 + 2 S3) / 6` etc.). The
/// first and last rows are the identity, so a patch boundary's control points
/// depend only on the samples on that boundary, which is what lets
/// neighbouring patches agree on it.
const FROM_THIRDS: [[f64; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [-5.0 / 6.0, 3.0, -1.5, 1.0 / 3.0],
    [1.0 / 3.0, -1.5, 3.0, -5.0 / 6.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// Lattice steps along a cube edge: 2 patches of 3 control-point steps.
const CUBE_LATTICE: i32 = 6;

/// The cube faces of [`bezier_sphere`]: the axis of the outward normal, its
/// sign, and the axes of the patch parameters u and v, chosen so that
/// `u x v` points outwards (a consistent winding, though the renderer does
/// not need one).
const CUBE_FACES: [(usize, bool, usize, usize); 6] = [
    (0, true, 1, 2),
    (0, false, 2, 1),
    (1, true, 2, 0),
    (1, false, 0, 2),
    (2, true, 0, 1),
    (2, false, 1, 0),
];

/// A closed sphere of radius 1 around the origin made of 24 bicubic Bezier
/// patches without poles: a cube whose 6 faces are projected onto the sphere
/// (equiangularly, so every patch spans 45 degrees of arc on its centre
/// lines), each face as 2 x 2 patches.
///
/// Each patch interpolates the sphere at its 4 x 4 lattice points (the
/// surface stays within 0.1% of radius 1). Each of its 4 edges is shared
/// with one other patch; half of the 48 shared edges run along the cube's
/// 12 edges, where the u edge of one face meets the v edge (or a reversed
/// edge) of another, and the cube's 8 corners are shared by only 3 patches.
/// Neighbouring patches share their boundary control points bit for bit.
pub fn bezier_sphere() -> Model {
    let mut shared: HashMap<[i32; 3], [f32; 3]> = HashMap::new();
    let mut patches = Vec::with_capacity(24);
    for &(normal, positive, u_axis, v_axis) in &CUBE_FACES {
        // The integer cube coordinate of the face's lattice point (i, j).
        let lattice = |i: i32, j: i32| {
            let mut key = [0; 3];
            key[normal] = if positive { CUBE_LATTICE } else { 0 };
            key[u_axis] = i;
            key[v_axis] = j;
            key
        };
        for patch_v in 0..2 {
            for patch_u in 0..2 {
                let key =
                    |u: usize, v: usize| lattice(3 * patch_u + small(u), 3 * patch_v + small(v));
                let samples: [[[f64; 3]; 4]; 4] =
                    std::array::from_fn(|v| std::array::from_fn(|u| cube_to_sphere(key(u, v))));
                let controls = interpolating_controls(&samples);
                let points: [[f32; 3]; 16] = std::array::from_fn(|index| {
                    let (u, v) = (index % 4, index / 4);
                    *shared
                        .entry(key(u, v))
                        .or_insert_with(|| controls[v][u].map(|c| c as f32))
                });
                patches.push(Patch {
                    points: points.map(Into::into),
                });
            }
        }
    }
    Model::new(patches)
}

/// The sphere point of an integer cube lattice coordinate: the cube
/// `[-1, 1]^3` mapped equiangularly (`tan`), so that the lattice steps are
/// equal angles along the face centre lines, then normalized.
fn cube_to_sphere(key: [i32; 3]) -> [f64; 3] {
    let half = f64::from(CUBE_LATTICE) / 2.0;
    let cube = key.map(|k| (std::f64::consts::FRAC_PI_4 * (f64::from(k) - half) / half).tan());
    let length = cube.iter().map(|c| c * c).sum::<f64>().sqrt();
    cube.map(|c| c / length)
}

/// Control points of the bicubic patch through `samples[v][u]` at
/// parameters `(u / 3, v / 3)`: `C = F S F^T` with [`FROM_THIRDS`] `F`.
fn interpolating_controls(samples: &[[[f64; 3]; 4]; 4]) -> [[[f64; 3]; 4]; 4] {
    std::array::from_fn(|v| {
        std::array::from_fn(|u| {
            let mut point = [0.0; 3];
            for (k, row) in samples.iter().enumerate() {
                for (l, sample) in row.iter().enumerate() {
                    let weight = FROM_THIRDS[v][k] * FROM_THIRDS[u][l];
                    for (p, s) in point.iter_mut().zip(sample) {
                        *p += weight * s;
                    }
                }
            }
            point
        })
    })
}

/// The classic cubic approximation of a quarter circle: the inner control
/// points lie this far along the end tangents (`4 (sqrt 2 - 1) / 3`).
const QUARTER_CIRCLE_HANDLE: f64 = 0.552_284_749_830_793_4;

/// A closed sphere of radius 1 around the origin made of the classic 8
/// octant patches (4 around each hemisphere), each with its `v = 1` edge
/// collapsed to a pole.
///
/// Each patch is the tensor product of a quarter-circle cubic in longitude
/// (u) and one in latitude (v, from the equator to the pole), so the
/// surface stays within about 0.05% of radius 1. The tangent along u
/// vanishes on the collapsed edges, which exercises the dicer's
/// degenerate-normal and zero-length-edge paths. Neighbouring patches share
/// their boundary control points bit for bit; the pole is one point.
pub fn bezier_sphere_with_poles() -> Model {
    let k = QUARTER_CIRCLE_HANDLE;
    // The 12 control points of the full circle in longitude, 3 per quarter:
    // corner, handle leaving it, handle entering the next corner.
    let corners = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];
    let ring: Vec<[f64; 2]> = (0..4)
        .flat_map(|q| {
            let (c, next) = (corners[q], corners[(q + 1) % 4]);
            // The tangent at corner c (counter-clockwise) is (-c.y, c.x).
            [
                c,
                [c[0] - k * c[1], c[1] + k * c[0]],
                [next[0] + k * next[1], next[1] - k * next[0]],
            ]
        })
        .collect();
    // Latitude rows from the equator (0) to a pole (3): (radius, height).
    let profile = [[1.0, 0.0], [1.0, k], [k, 1.0], [0.0, 1.0]];
    // Every point once, keyed by (ring index, signed latitude row); the
    // poles are one key each and exactly (0, 0, +-1), so the collapsed
    // edges are one point bit for bit (no -0.0 from 0 * negative).
    let mut shared: HashMap<(usize, i32), [f32; 3]> = HashMap::new();
    let mut point = |m: usize, row: i32| {
        let key = if row.abs() == 3 {
            (0, row)
        } else {
            (m % 12, row)
        };
        *shared.entry(key).or_insert_with(|| {
            let [radius, height] = profile[row.unsigned_abs() as usize];
            let z = if row < 0 { -height } else { height };
            let [x, y] = ring[key.0];
            [(radius * x) as f32, (radius * y) as f32, z as f32]
        })
    };
    let mut patches = Vec::with_capacity(8);
    for north in [true, false] {
        for quarter in 0..4 {
            let points: [[f32; 3]; 16] = std::array::from_fn(|index| {
                let (u, v) = (index % 4, index / 4);
                let row = if north { small(v) } else { -small(v) };
                point(3 * quarter + u, row)
            });
            patches.push(Patch {
                points: points.map(Into::into),
            });
        }
    }
    Model::new(patches)
}

/// The control points of edge `edge` (numbered as in
/// [`reyes::dicing::edge_indices`]) as bit patterns, in the patch's
/// parameter order.
fn edge_bits(patch: &Patch, edge: usize) -> [[u32; 3]; 4] {
    edge_indices(edge).map(|i| patch.points[i].to_array().map(f32::to_bits))
}

/// The patch edges of `model` that are neither collapsed to one point nor
/// matched, bit for bit (in either direction), by exactly one edge of
/// another patch, as `(patch, edge)` with edges numbered as in
/// [`reyes::dicing::edge_indices`]. Empty for a model that is closed as data.
pub fn unmatched_edges(model: &Model) -> Vec<(usize, usize)> {
    let mut by_curve: HashMap<[[u32; 3]; 4], Vec<(usize, usize)>> = HashMap::new();
    for (p, patch) in model.patches.iter().enumerate() {
        for edge in 0..4 {
            let bits = edge_bits(patch, edge);
            if bits.iter().all(|b| *b == bits[0]) {
                continue;
            }
            let mut reversed = bits;
            reversed.reverse();
            by_curve
                .entry(bits.min(reversed))
                .or_default()
                .push((p, edge));
        }
    }
    let mut unmatched: Vec<(usize, usize)> = by_curve
        .into_values()
        .filter(|users| users.len() != 2 || users[0].0 == users[1].0)
        .flatten()
        .collect();
    unmatched.sort_unstable();
    unmatched
}

/// How many edges of `model` are collapsed to a single point.
pub fn collapsed_edges(model: &Model) -> usize {
    model
        .patches
        .iter()
        .flat_map(|patch| (0..4).map(move |edge| edge_bits(patch, edge)))
        .filter(|bits| bits.iter().all(|b| *b == bits[0]))
        .count()
}

/// A lattice index as a signed coordinate (the lattices here are small).
fn small(index: usize) -> i32 {
    i32::try_from(index).expect("lattice indices are small")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The smallest and largest distance from the origin over a 33 x 33 grid
    /// of every patch.
    fn radius_range(model: &Model) -> (f32, f32) {
        let mut range = (f32::INFINITY, 0.0f32);
        for patch in &model.patches {
            for j in 0..=32 {
                for i in 0..=32 {
                    let p =
                        reyes::bezier::position(&patch.points, i as f32 / 32.0, j as f32 / 32.0);
                    range = (range.0.min(p.length()), range.1.max(p.length()));
                }
            }
        }
        range
    }

    #[test]
    fn cube_sphere_is_closed_bit_for_bit() {
        let sphere = bezier_sphere();
        assert_eq!(sphere.patches.len(), 24);
        assert_eq!(unmatched_edges(&sphere), Vec::<(usize, usize)>::new());
        assert_eq!(collapsed_edges(&sphere), 0);
    }

    #[test]
    fn octant_sphere_is_closed_bit_for_bit_with_collapsed_poles() {
        let sphere = bezier_sphere_with_poles();
        assert_eq!(sphere.patches.len(), 8);
        assert_eq!(unmatched_edges(&sphere), Vec::<(usize, usize)>::new());
        assert_eq!(
            collapsed_edges(&sphere),
            8,
            "one collapsed edge per octant, at its pole"
        );
    }

    #[test]
    fn spheres_are_round() {
        for (name, sphere, tolerance) in [
            ("cube", bezier_sphere(), 2e-3),
            ("octants", bezier_sphere_with_poles(), 1e-3),
        ] {
            let (lo, hi) = radius_range(&sphere);
            assert!(
                lo > 1.0 - tolerance && hi < 1.0 + tolerance,
                "{name} sphere radius in [{lo}, {hi}]"
            );
        }
    }

    /// The checker sees a one-ulp difference and an edge used three times,
    /// so a passing check means the sharing really is exact.
    #[test]
    fn the_edge_check_detects_inexact_and_extra_sharing() {
        let mut nudged = bezier_sphere();
        let p = nudged.patches[5].points[1];
        nudged.patches[5].points[1] = [f32::from_bits(p.x.to_bits() + 1), p.y, p.z].into();
        let unmatched = unmatched_edges(&nudged);
        assert!(unmatched.contains(&(5, 0)), "{unmatched:?}");
        assert_eq!(
            unmatched.len(),
            2,
            "the nudged edge and its former partner: {unmatched:?}"
        );

        let mut tripled = bezier_sphere_with_poles();
        let extra = tripled.patches[0];
        tripled.patches.push(extra);
        // Each of the copied patch's 3 uncollapsed edges now has 3 users.
        assert_eq!(
            unmatched_edges(&tripled).len(),
            3 * 3,
            "{:?}",
            unmatched_edges(&tripled)
        );
    }
}
