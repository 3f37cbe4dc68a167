//! The `bilinear` scheme: every face flat.
//!
//! A quad `v0 v1 v2 v3` is the bilinear patch with corners `(u, v) = (0,0)
//! v0, (1,0) v1, (1,1) v2, (0,1) v3`, so `dP/du x dP/dv` follows the face's
//! winding, as for RIB polygons. Any other face is first cut into one quad
//! per vertex, `(v_i, mid(v_i, v_i+1), centroid, mid(v_i-1, v_i))`: the first
//! step of bilinear subdivision, after which every face is a quad.

use glam::{Vec2, Vec3};

use super::mesh::Mesh;
use super::{Subdivided, SubdivisionReport};
use crate::model::{Model, Patch};

/// The patches of a validated mesh, one per quad and `n` per `n`-gon; holes
/// make none.
pub(super) fn patches(mesh: &Mesh) -> Subdivided {
    let mut patches = Vec::new();
    let mut st = mesh.st.as_ref().map(|_| Vec::new());
    for (face, corners) in mesh.faces().enumerate() {
        if mesh.is_hole(face) {
            continue;
        }
        let points: Vec<Vec3> = mesh.face_vertices[corners.clone()]
            .iter()
            .map(|&v| mesh.positions[v as usize])
            .collect();
        let face_st: Option<&[Vec2]> = mesh.st.as_ref().map(|st| &st[corners.clone()]);
        for (quad, quad_st) in quads(&points, face_st) {
            patches.push(bilinear_patch(quad));
            if let (Some(st), Some(quad_st)) = (st.as_mut(), quad_st) {
                // Model corner order: (0,0), (1,0), (0,1), (1,1).
                st.push([quad_st[0], quad_st[1], quad_st[3], quad_st[2]]);
            }
        }
    }
    let count = patches.len();
    Subdivided {
        model: Model { patches, st },
        report: SubdivisionReport {
            faces: mesh.face_count(),
            exact_patches: count,
            ..SubdivisionReport::default()
        },
    }
}

/// The quads `(v0, v1, v2, v3)` in winding order of a face with `points`
/// (and their texture coordinates): the face itself when it is a quad, else
/// one per vertex around the centroid.
fn quads(points: &[Vec3], st: Option<&[Vec2]>) -> Vec<([Vec3; 4], Option<[Vec2; 4]>)> {
    if let [a, b, c, d] = points {
        let st = st.map(|s| [s[0], s[1], s[2], s[3]]);
        return vec![([*a, *b, *c, *d], st)];
    }
    let n = points.len();
    let centroid_of = |p: &[Vec3]| p.iter().copied().sum::<Vec3>() / n as f32;
    let st_centroid = st.map(|s| s.iter().copied().sum::<Vec2>() / n as f32);
    let centroid = centroid_of(points);
    (0..n)
        .map(|i| {
            let (prev, next) = ((i + n - 1) % n, (i + 1) % n);
            let quad = [
                points[i],
                (points[i] + points[next]) * 0.5,
                centroid,
                (points[prev] + points[i]) * 0.5,
            ];
            let quad_st = st
                .zip(st_centroid)
                .map(|(s, c)| [s[i], (s[i] + s[next]) * 0.5, c, (s[prev] + s[i]) * 0.5]);
            (quad, quad_st)
        })
        .collect()
}

/// The bicubic Bezier form of the bilinear patch over the quad `q` (in
/// winding order): control point `(i, j)` is the bilinear blend at
/// `(i/3, j/3)`.
fn bilinear_patch(q: [Vec3; 4]) -> Patch {
    let mut points = [Vec3::ZERO; 16];
    for j in 0..4 {
        let v = j as f32 / 3.0;
        for i in 0..4 {
            let u = i as f32 / 3.0;
            points[j * 4 + i] = q[0] * ((1.0 - u) * (1.0 - v))
                + q[1] * (u * (1.0 - v))
                + q[2] * (u * v)
                + q[3] * ((1.0 - u) * v);
        }
    }
    Patch { points }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::subdiv::Scheme;

    fn mesh(positions: Vec<Vec3>, faces: &[&[u32]]) -> Mesh {
        Mesh {
            scheme: Scheme::Bilinear,
            positions,
            face_sizes: faces.iter().map(|f| f.len() as u32).collect(),
            face_vertices: faces.iter().flat_map(|f| f.iter().copied()).collect(),
            ..Mesh::default()
        }
    }

    #[test]
    fn a_quad_is_one_patch_through_its_corners_facing_its_winding() {
        let m = mesh(
            vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            &[&[0, 1, 2, 3]],
        );
        let out = m.to_patches().unwrap();
        let p = out.model.patches[0];
        assert_eq!(p.point(0, 0), Vec3::ZERO);
        assert_eq!(p.point(3, 0), Vec3::X);
        assert_eq!(p.point(3, 3), Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(p.point(0, 3), Vec3::Y);
        let du = p.point(1, 0) - p.point(0, 0);
        let dv = p.point(0, 1) - p.point(0, 0);
        assert!(du.cross(dv).z > 0.0, "counter-clockwise faces +z");
        assert_eq!(out.report.exact_patches, 1);
    }

    #[test]
    fn a_triangle_is_three_quads_that_cover_its_area() {
        let m = mesh(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[&[0, 1, 2]]);
        let out = m.to_patches().unwrap();
        assert_eq!(out.model.patches.len(), 3);
        // Each quad's area from its two triangles; together the triangle's 1/2.
        let area: f32 = out
            .model
            .patches
            .iter()
            .map(|p| {
                let (a, b, c, d) = (p.point(0, 0), p.point(3, 0), p.point(3, 3), p.point(0, 3));
                0.5 * ((b - a).cross(c - a).z + (c - a).cross(d - a).z)
            })
            .sum();
        assert!((area - 0.5).abs() < 1e-6, "area {area}");
    }

    #[test]
    fn holes_make_no_patches_and_texture_coordinates_follow_the_corners() {
        let mut m = mesh(
            vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::Y,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 1.0, 0.0),
            ],
            &[&[0, 1, 2, 3], &[1, 4, 5, 2]],
        );
        m.holes = vec![1];
        m.st = Some((0..8).map(|i| Vec2::splat(i as f32)).collect());
        let out = m.to_patches().unwrap();
        assert_eq!(out.model.patches.len(), 1);
        let st = out.model.st.unwrap();
        assert_eq!(
            st,
            vec![[
                Vec2::splat(0.0),
                Vec2::splat(1.0),
                Vec2::splat(3.0),
                Vec2::splat(2.0)
            ]]
        );
    }
}
