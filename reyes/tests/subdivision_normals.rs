//! The shading normal of every Catmull-Clark patch, edges and collapsed
//! corners included, against the normal a hair inside the patch: the
//! transition fans collapse an edge to their centre away from the origin,
//! where the tangent along that edge must come out exactly zero (so the
//! normal falls back to the clamped parameters) and not as rounding noise
//! of random direction (isolated light specks in the normal image).

use glam::Vec3;
use reyes::reference::dice::displacement_normal;
use reyes::subdiv::Mesh;

/// A cube of side 2, centred at `centre` (every corner of valence 3).
fn cube(centre: Vec3) -> Mesh {
    let positions = (0..8)
        .map(|i| {
            centre
                + Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                )
        })
        .collect();
    let faces: [[u32; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    Mesh {
        positions,
        face_sizes: vec![4; faces.len()],
        face_vertices: faces.iter().flatten().copied().collect(),
        ..Mesh::default()
    }
}

/// Points `(u, v)` of a patch where the normal is more than `limit_deg`
/// away from the normal at the point pulled 1/100 towards the middle, on a
/// 7 x 7 grid (sevenths: Bernstein weights that do not cancel exactly).
fn bad_normals(points: &[Vec3; 16], limit_deg: f32) -> Vec<(f32, f32, f32)> {
    let mut bad = Vec::new();
    for j in 0..=7 {
        for i in 0..=7 {
            let (u, v) = (i as f32 / 7.0, j as f32 / 7.0);
            let inner = |x: f32| 0.01 + 0.98 * x;
            let n = displacement_normal(points, u, v);
            let m = displacement_normal(points, inner(u), inner(v));
            let angle = n.dot(m).clamp(-1.0, 1.0).acos().to_degrees();
            if n == Vec3::ZERO || angle > limit_deg {
                bad.push((u, v, angle));
            }
        }
    }
    bad
}

#[test]
fn every_patch_normal_of_a_cube_agrees_with_its_inside_neighbour() {
    // Off the origin, as in a scene: the collapsed centre's coordinates are
    // not zero, so their rounding does not vanish.
    for centre in [Vec3::ZERO, Vec3::new(0.3, -5.0, 7.0)] {
        let out = cube(centre).to_patches().unwrap();
        assert!(out.report.transition_patches > 0);
        let mut failures = Vec::new();
        for (k, patch) in out.model.patches.iter().enumerate() {
            for bad in bad_normals(&patch.points, 5.0) {
                failures.push((k, bad));
            }
        }
        assert!(
            failures.is_empty(),
            "cube at {centre}: {} points of {} patches have a normal off by over 5 degrees \
             from a point 1/100 inside (patch, (u, v, degrees)): {:?}",
            failures.len(),
            out.model.patches.len(),
            &failures[..failures.len().min(12)]
        );
    }
}
