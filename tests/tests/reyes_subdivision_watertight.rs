//! Catmull-Clark patches in the renderer: a cube (valence-3 extraordinary
//! vertices), an octagonal pyramid (valence 8 at the apex and at the
//! base's centre, valence 3 around it), the cube with a hole (seen through
//! it) and an open wavy grid with interpolated boundary and valence-5 and
//! valence-3 vertices, in the CPU reference at 16 spp and
//! shading rates 1, 4, 16 and 64, counted against a dense tessellation of
//! the same patches with the 5 x 5 rule of `reyes_watertight.rs`
//! ([`tests::watertight::cracks`]); no pixel is left out around patch
//! edges.
//!
//! Every patch edge is shared bit for bit by exactly one other patch (a
//! coarse patch next to finer ones is a fan of transition patches, so
//! there are no T-junctions), and no crack may appear. Moving one edge of
//! the cube by 1e-4 units must show cracks.

use std::collections::HashSet;

use glam::Vec3;
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::Scene;
use reyes::subdiv::{BoundaryInterpolation, Mesh};
use tests::watertight::{
    coverage_iou, cracks, dense_coverage, smooth_front, view_scene, visible_patches,
};

const SPP: u32 = 16;
const SHADING_RATES: [f32; 4] = [1.0, 4.0, 16.0, 64.0];
const WIDTH: u32 = 256;
const HEIGHT: u32 = 192;
/// Where the cube is seen from: one corner (an extraordinary vertex) in
/// front, three faces around it.
const CUBE_EYE: Vec3 = Vec3::new(2.6, -2.0, 2.3);
/// The coverage IoU each render must reach: the renders' chords cut convex
/// silhouettes (the lowest seen is 0.9958, at shading rate 64).
const MIN_IOU: f64 = 0.99;
/// Points per patch side of the reference tessellation.
const DENSITY: u32 = 48;

fn mesh(positions: Vec<Vec3>, faces: &[Vec<u32>]) -> Mesh {
    Mesh {
        positions,
        face_sizes: faces.iter().map(|f| f.len() as u32).collect(),
        face_vertices: faces.iter().flatten().copied().collect(),
        ..Mesh::default()
    }
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
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    mesh(positions, &faces.map(|f| f.to_vec()))
}

/// The cube with its top face (+z) a hole: open along the hole's border,
/// seen through it.
fn cube_with_a_hole() -> Mesh {
    Mesh {
        holes: vec![1],
        ..cube()
    }
}

/// An open 6 x 6 grid of quads, wavy in z, with a valence-5 vertex (a
/// triangle split off one quad) and a valence-3 one, its boundary
/// interpolated (`interpolateboundary 1`: edges and corners).
fn open_grid() -> Mesh {
    let n = 7;
    let positions: Vec<Vec3> = (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f32 - 3.0, (i / n) as f32 - 3.0);
            Vec3::new(x * 0.5, y * 0.5, 0.15 * (x * 0.9).sin() * (y * 0.7).cos())
        })
        .collect();
    let at = |x: u32, y: u32| y * n as u32 + x;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for y in 0..(n as u32 - 1) {
        for x in 0..(n as u32 - 1) {
            let quad = vec![at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)];
            if (x, y) == (2, 2) {
                // Two triangles: the diagonal's ends get valence 5.
                faces.push(vec![quad[0], quad[1], quad[2]]);
                faces.push(vec![quad[0], quad[2], quad[3]]);
            } else if (x, y) == (3, 3) {
                // Made one hexagon with the next quad (below).
                continue;
            } else if (x, y) == (4, 3) {
                // The quads (3, 3) and (4, 3) as one hexagon: the vertices
                // between them, (4, 3) and (4, 4), lose an edge (valence 3).
                faces.push(vec![
                    at(3, 3),
                    at(4, 3),
                    at(5, 3),
                    at(5, 4),
                    at(4, 4),
                    at(3, 4),
                ]);
            } else {
                faces.push(quad);
            }
        }
    }
    Mesh {
        boundary: BoundaryInterpolation::EdgeAndCorner,
        ..mesh(positions, &faces)
    }
}

fn octagonal_pyramid() -> Mesh {
    let mut positions = vec![Vec3::new(0.0, 0.0, 1.5)];
    for i in 0..8 {
        let a = i as f32 * std::f32::consts::TAU / 8.0;
        positions.push(Vec3::new(a.cos(), a.sin(), 0.0));
    }
    let mut faces: Vec<Vec<u32>> = (0..8).map(|i| vec![0, 1 + i, 1 + (i + 1) % 8]).collect();
    faces.push((1..9).rev().collect());
    mesh(positions, &faces)
}

/// `model` at `WIDTH x HEIGHT`, 16 spp, seen from `eye` looking at
/// `target`.
fn scene_for(model: &Model, eye: Vec3, target: Vec3) -> Scene {
    view_scene(model, (WIDTH, HEIGHT, SPP), eye, target)
}

/// A view: the patches not clearly hidden, and where cracks are counted.
struct Shot {
    scene: Scene,
    model: Model,
    coverage: Vec<bool>,
    counted: Vec<bool>,
}

fn shot(whole: &Model, eye: Vec3, target: Vec3) -> Shot {
    let scene = scene_for(whole, eye, target);
    let prepared =
        PreparedScene::new(&scene, std::slice::from_ref(whole)).expect("the scene prepares");
    let visible = visible_patches(&prepared, DENSITY, SPP.isqrt(), 0.02);
    let model = Model::new(
        whole
            .patches
            .iter()
            .zip(&visible)
            .filter(|(_, v)| **v)
            .map(|(p, _)| *p)
            .collect(),
    );
    let prepared =
        PreparedScene::new(&scene, std::slice::from_ref(&model)).expect("the scene prepares");
    let coverage = dense_coverage(&prepared, DENSITY);
    let smooth = smooth_front(&prepared, DENSITY, SPP.isqrt(), 0.01);
    let counted = coverage
        .iter()
        .zip(&smooth)
        .map(|(&c, &s)| c && s)
        .collect();
    Shot {
        scene,
        model,
        coverage,
        counted,
    }
}

/// The boundary curves of `model` that no other patch shares bit for bit
/// (reversed), such as either side of a T-junction.
fn unshared_curves(model: &Model) -> Vec<[Vec3; 4]> {
    const EDGES: [[usize; 4]; 4] = [
        [0, 1, 2, 3],
        [3, 7, 11, 15],
        [15, 14, 13, 12],
        [12, 8, 4, 0],
    ];
    let bits = |c: [Vec3; 4]| c.map(|p| p.to_array().map(f32::to_bits));
    let curves: Vec<[Vec3; 4]> = model
        .patches
        .iter()
        .flat_map(|p| EDGES.map(|e| e.map(|i| p.points[i])))
        .collect();
    let all: HashSet<_> = curves.iter().map(|&c| bits(c)).collect();
    curves
        .into_iter()
        .filter(|&c| !all.contains(&bits([c[3], c[2], c[1], c[0]])))
        .collect()
}

/// The crack pixels and coverage IoU of `model` rendered in `shot`'s view
/// at `rate`.
fn render(shot: &Shot, model: &Model, rate: f32) -> (Vec<(u32, u32)>, f64) {
    let mut scene = shot.scene.clone();
    scene.shading_rate = rate;
    let prepared =
        PreparedScene::new(&scene, std::slice::from_ref(model)).expect("the scene prepares");
    let rendered = reference::render(&prepared);
    (
        cracks(&rendered.covered_samples, SPP, &shot.counted, WIDTH, HEIGHT),
        coverage_iou(&rendered.covered_samples, SPP, &shot.coverage),
    )
}

#[test]
fn catmull_clark_patches_render_without_cracks() {
    let views = [
        ("cube", cube(), CUBE_EYE, Vec3::ZERO),
        (
            "octagonal pyramid",
            octagonal_pyramid(),
            Vec3::new(1.6, -2.4, 2.8),
            Vec3::new(0.0, 0.0, 0.4),
        ),
        (
            "cube with a hole",
            cube_with_a_hole(),
            Vec3::new(1.8, -1.6, 3.2),
            Vec3::ZERO,
        ),
        (
            "open grid",
            open_grid(),
            Vec3::new(1.0, -3.0, 3.5),
            Vec3::ZERO,
        ),
    ];
    let mut failures = Vec::new();
    for (name, mesh, eye, target) in views {
        let subdivided = mesh.to_patches().expect("the mesh subdivides");
        let shot = shot(&subdivided.model, eye, target);
        let counted = shot.counted.iter().filter(|&&c| c).count();
        eprintln!(
            "{name}: {} patches ({} visible), {counted} pixels counted, report {:?}",
            subdivided.model.patches.len(),
            shot.model.patches.len(),
            subdivided.report
        );
        if counted < 2_000 {
            failures.push(format!("{name}: only {counted} pixels counted"));
        }
        // A closed mesh's every curve is shared; an open one's border is not.
        let unshared = unshared_curves(&subdivided.model);
        let closed = mesh.holes.is_empty() && mesh.boundary == BoundaryInterpolation::None;
        if closed && !unshared.is_empty() {
            failures.push(format!("{name}: {} curves not shared", unshared.len()));
        }
        for rate in SHADING_RATES {
            let (found, iou) = render(&shot, &shot.model, rate);
            eprintln!(
                "{name}, rate {rate}: {} cracks {found:?}, IoU {iou:.4}",
                found.len()
            );
            if !found.is_empty() || iou < MIN_IOU {
                failures.push(format!("{name}, rate {rate}: {found:?}, IoU {iou}"));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The count can fail: the largest patch on screen with its first edge's
/// inner control points moved 1e-4 units towards the patch's inside.
#[test]
fn a_gap_of_1e_4_is_seen() {
    let subdivided = cube().to_patches().expect("the cube subdivides");
    let shot = shot(&subdivided.model, CUBE_EYE, Vec3::ZERO);
    let area = |p: &reyes::model::Patch| {
        (p.points[3] - p.points[0])
            .cross(p.points[12] - p.points[0])
            .length()
    };
    let largest = (0..shot.model.patches.len())
        .max_by(|&a, &b| area(&shot.model.patches[a]).total_cmp(&area(&shot.model.patches[b])))
        .unwrap();
    let mut moved = shot.model.clone();
    let patch = &mut moved.patches[largest];
    for i in [1, 2] {
        let inwards = (patch.points[i + 4] - patch.points[i]).normalize();
        patch.points[i] += inwards * 1e-4;
    }
    let mut found = 0;
    for rate in SHADING_RATES {
        let (cracks, _) = render(&shot, &moved, rate);
        eprintln!("moved edge, rate {rate}: {} cracks", cracks.len());
        found += cracks.len();
    }
    assert!(found > 0, "a 1e-4 gap went unseen");
}
