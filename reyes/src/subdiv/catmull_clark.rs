//! The Catmull-Clark scheme: the limit surface as Bezier patches, by
//! feature-adaptive subdivision (Niessner et al. 2012).
//!
//! 1. A mesh with any face that is not a quad is refined once everywhere;
//!    after that every face is a quad.
//! 2. Level by level, each face still to be made is classified: a regular
//!    one (`regular.rs`) becomes its B-spline patch in Bezier form, exactly;
//!    the others are refined together with their 1-ring (`refine.rs`) and
//!    their children are classified at the next level.
//! 3. At the deepest level, what is still irregular is approximated
//!    (`approximate.rs`) and its distance to the limit surface measured.
//! 4. The patches are stitched so that neighbours share their edge curves
//!    bit for bit, or halves of them (`stitch.rs`).

use glam::Vec2;

use super::approximate::{self, MEASURE_DEPTH};
use super::level::{Level, is_infinite};
use super::mesh::{Mesh, MeshError};
use super::refine::refine;
use super::regular;
use super::stitch::{self, Emitted};
use super::transition;
use super::{Subdivided, SubdivisionReport};
use crate::model::{Model, Patch};

/// The deepest level for isolating extraordinary vertices (deeper only
/// where a semi-sharp crease needs its levels to become smooth).
pub const ISOLATION_LEVEL: usize = 8;

/// The most patches (and faces in one level) a mesh may make.
pub const MAX_PATCHES: usize = 1 << 22;

/// The patches of a validated Catmull-Clark mesh, at most `limit` of them
/// (and faces in one level):
/// refinement stops at the first level that would pass it, so the memory
/// it takes stays in proportion to `limit`.
pub(super) fn patches_within(mesh: &Mesh, limit: usize) -> Result<Subdivided, MeshError> {
    let check_size = |count: usize| {
        if count > limit {
            return Err(MeshError::TooManyPatches { limit });
        }
        Ok(())
    };
    let mut levels = vec![Level::from_mesh(mesh)];
    let mut active: Vec<u32>;
    let all_quads = mesh.face_sizes.iter().all(|&s| s == 4);
    if all_quads {
        active = visible(&levels[0], 0..levels[0].face_count() as u32);
    } else {
        let everything: Vec<u32> = (0..levels[0].face_count() as u32).collect();
        let refined = refine(&levels[0], &everything, 1);
        active = visible(&refined.level, refined.children.iter().copied());
        levels.push(refined.level);
    }
    check_size(levels[levels.len() - 1].face_count())?;
    let deepest = deepest_level(mesh, levels.len() - 1);

    let mut emitted: Vec<Emitted> = Vec::new();
    loop {
        let l = levels.len() - 1;
        let mut to_refine = Vec::new();
        let mut to_approximate = Vec::new();
        for &f in &active {
            if let Some(grid) = regular::bspline_points(&levels[l], f) {
                emitted.push(Emitted {
                    level: l,
                    face: f,
                    exact: true,
                    points: regular::bspline_to_bezier(&grid),
                });
            } else if l >= deepest {
                to_approximate.push(f);
            } else {
                to_refine.push(f);
            }
        }
        check_size(emitted.len() + to_approximate.len() + 4 * to_refine.len())?;
        if !to_approximate.is_empty() {
            // Three more levels under the approximated faces: their limit
            // points at u, v = k / 2 (the patches) to k / 8 (the error).
            let mut faces = to_approximate.clone();
            for d in 0..MEASURE_DEPTH {
                let refined = refine(&levels[l + d], &faces, l + d + 1);
                faces = refined.children;
                check_size(refined.level.face_count())?;
                levels.push(refined.level);
            }
            for &f in &to_approximate {
                emitted.push(Emitted {
                    level: l,
                    face: f,
                    exact: false,
                    points: approximate::approximate_patch(&levels, l, f),
                });
            }
            break;
        }
        if to_refine.is_empty() {
            break;
        }
        let refined = refine(&levels[l], &to_refine, l + 1);
        check_size(refined.level.face_count())?;
        active = visible(&refined.level, refined.children.iter().copied());
        levels.push(refined.level);
    }

    let stitched = stitch::stitch(&levels, &mut emitted);
    let mut report = SubdivisionReport {
        faces: mesh.face_count(),
        ..SubdivisionReport::default()
    };
    let mut patches = Vec::with_capacity(emitted.len());
    let mut st = mesh.st.as_ref().map(|_| Vec::with_capacity(emitted.len()));
    for e in &emitted {
        report.max_level = report.max_level.max(e.level as u32);
        let face_st = levels[e.level].face_st(e.face).map(model_st);
        if !e.exact {
            report.approximate_patches += 1;
            let error = approximate::patch_error(&levels, e.level, e.face, &e.points);
            report.max_error = report.max_error.max(error);
        } else if let Some(fan) = transition::fan(&levels, &stitched, e.level, e.face, &e.points) {
            for piece in &fan {
                report.transition_patches += 1;
                report.max_error = report
                    .max_error
                    .max(transition::fan_error(&e.points, piece));
                patches.push(Patch {
                    points: piece.points,
                });
                if let (Some(st), Some(s)) = (st.as_mut(), face_st) {
                    let at = |d: Vec2| s[0].lerp(s[1], d.x).lerp(s[2].lerp(s[3], d.x), d.y);
                    let c = at(Vec2::splat(0.5));
                    st.push([at(piece.domain[0]), at(piece.domain[1]), c, c]);
                }
            }
            continue;
        } else {
            report.exact_patches += 1;
        }
        patches.push(Patch { points: e.points });
        if let (Some(st), Some(s)) = (st.as_mut(), face_st) {
            st.push(s);
        }
    }
    Ok(Subdivided {
        model: Model { patches, st },
        report,
    })
}

/// The faces among `faces` that have a surface of their own.
fn visible(level: &Level, faces: impl Iterator<Item = u32>) -> Vec<u32> {
    faces.filter(|&f| !level.hidden[f as usize]).collect()
}

/// The level where irregular faces are approximated: [`ISOLATION_LEVEL`]
/// below `first` (the first level of quads), and no shallower than the
/// level where the sharpest semi-sharp tag has become smooth, so that the
/// limit positions there follow the smooth, crease and corner rules alone.
fn deepest_level(mesh: &Mesh, first: usize) -> usize {
    let semi_sharp = mesh
        .creases
        .iter()
        .map(|c| c.sharpness)
        .chain(mesh.corners.iter().map(|c| c.sharpness))
        .filter(|&s| !is_infinite(s))
        .fold(0.0f32, f32::max);
    (first + ISOLATION_LEVEL).max(semi_sharp.ceil() as usize)
}

/// A face's corner texture coordinates (in winding order `v0 v1 v2 v3`) in
/// the model's order `(0,0), (1,0), (0,1), (1,1)`.
fn model_st(s: &[Vec2]) -> [Vec2; 4] {
    [s[0], s[1], s[3], s[2]]
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    /// The patches of a validated mesh, within the mesh cap.
    fn patches(mesh: &Mesh) -> Result<Subdivided, MeshError> {
        patches_within(mesh, MAX_PATCHES)
    }
    use crate::bezier;

    fn quads(positions: Vec<Vec3>, faces: &[[u32; 4]]) -> Mesh {
        Mesh {
            positions,
            face_sizes: vec![4; faces.len()],
            face_vertices: faces.iter().flatten().copied().collect(),
            ..Mesh::default()
        }
    }

    /// A `n x n` grid of quads with heights from `height`.
    fn grid(n: u32, height: impl Fn(f32, f32) -> f32) -> Mesh {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f32, j as f32);
                positions.push(Vec3::new(x, y, height(x, y)));
            }
        }
        let mut faces = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                faces.push([v, v + 1, v + n + 2, v + n + 1]);
            }
        }
        quads(positions, &faces)
    }

    fn cube() -> Mesh {
        let positions = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                )
            })
            .collect();
        quads(
            positions,
            &[
                [0, 2, 3, 1],
                [4, 5, 7, 6],
                [0, 1, 5, 4],
                [2, 6, 7, 3],
                [0, 4, 6, 2],
                [1, 3, 7, 5],
            ],
        )
    }

    #[test]
    fn an_interior_grid_face_is_one_exact_patch_through_the_limit_points() {
        let (seed, mut rng) = crate::test_random::fresh_rng("grid face");
        let mut m = grid(4, |_, _| 0.0);
        for p in &mut m.positions {
            *p += crate::test_random::random_vec3(&mut rng, 0.3);
        }
        let out = patches(&m).unwrap();
        // Interior rule 0: 2 x 2 central faces are regular (the others
        // touch the boundary and make nothing).
        assert_eq!(out.model.patches.len(), 4, "seed {seed}");
        assert_eq!(out.report.exact_patches, 4, "seed {seed}");
        // The patch over face (1, 1) -> its corner at vertex (1, 1) is the
        // limit of that valence-4 vertex: (16 v + 4 sum e + sum d) / 36.
        let at = |i: i32, j: i32| m.positions[(j * 5 + i) as usize];
        let limit = (at(1, 1) * 16.0
            + (at(0, 1) + at(2, 1) + at(1, 0) + at(1, 2)) * 4.0
            + at(0, 0)
            + at(2, 0)
            + at(0, 2)
            + at(2, 2))
            / 36.0;
        let patch = out.model.patches[0];
        assert!(
            (patch.points[0] - limit).length() < 1e-5,
            "seed {seed}: {} vs {limit}",
            patch.points[0]
        );
    }

    #[test]
    fn patches_face_outwards_on_a_closed_mesh() {
        let out = patches(&cube()).unwrap();
        for p in &out.model.patches {
            let e = bezier::evaluate(&p.points, 0.5, 0.5);
            assert!(e.d_ds.cross(e.d_dt).dot(e.position) > 0.0);
        }
    }

    #[test]
    fn too_many_patches_is_an_error_not_an_allocation() {
        assert_eq!(
            patches_within(&cube(), 100).unwrap_err(),
            MeshError::TooManyPatches { limit: 100 }
        );
        assert!(patches_within(&cube(), 10_000).is_ok());
    }

    #[test]
    fn texture_coordinates_are_refined_linearly() {
        // A triangle fan closed into a tetrahedron, each face's st its own
        // corners (0,0), (1,0), (0,1): every patch's st stays in that
        // triangle, and one of them starts at each face's centroid.
        let mut m = Mesh {
            positions: vec![
                Vec3::new(1.0, 1.0, 1.0),
                Vec3::new(1.0, -1.0, -1.0),
                Vec3::new(-1.0, 1.0, -1.0),
                Vec3::new(-1.0, -1.0, 1.0),
            ],
            face_sizes: vec![3; 4],
            face_vertices: vec![0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2],
            ..Mesh::default()
        };
        let corners = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 1.0),
        ];
        m.st = Some((0..12).map(|i| corners[i % 3]).collect());
        let out = patches(&m).unwrap();
        let st = out.model.st.unwrap();
        assert_eq!(st.len(), out.model.patches.len());
        let centroid = Vec2::splat(1.0 / 3.0);
        for s in st.iter().flatten() {
            assert!(s.x >= 0.0 && s.y >= 0.0 && s.x + s.y <= 1.0 + 1e-6, "{s}");
        }
        assert!(st.iter().flatten().any(|s| (*s - centroid).length() < 1e-6));
    }

    #[test]
    fn odd_meshes_make_patches_without_panicking() {
        assert!(patches(&Mesh::default()).unwrap().model.patches.is_empty());
        // Two quads sharing only vertex 2 (two fans at one vertex), with an
        // unused vertex 7; each boundary rule.
        let mut positions: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new(i as f32, (i * i % 5) as f32, 0.0))
            .collect();
        positions[2] = Vec3::new(2.0, 2.0, 1.0);
        for boundary in [
            super::super::BoundaryInterpolation::None,
            super::super::BoundaryInterpolation::EdgeOnly,
            super::super::BoundaryInterpolation::EdgeAndCorner,
        ] {
            let mut m = quads(positions.clone(), &[[0, 1, 2, 3], [2, 4, 5, 6]]);
            m.boundary = boundary;
            let out = patches(&m).unwrap();
            // Under rule 0 every face touches the boundary and makes nothing.
            let none = boundary == super::super::BoundaryInterpolation::None;
            assert_eq!(out.model.patches.is_empty(), none, "{boundary:?}");
            assert!(out.report.max_error.is_finite());
        }
    }
}
