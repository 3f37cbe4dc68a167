//! Catmull-Clark meshes as Bezier patches against an independent uniform
//! refinement (`subdiv_reference`): every reference limit point lies on the
//! patches and every patch point on the reference surface, within a small
//! fraction of the mesh's size; normals agree away from extraordinary
//! vertices; neighbouring patches share their edge curves bit for bit (or
//! De Casteljau halves of them); the CPU reference's coverage at 800 x 600
//! matches the reference mesh's; a million faces stay about a million
//! patches.

mod subdiv_geometry;
mod subdiv_reference;

use std::collections::{HashMap, HashSet};

use glam::{DVec3, Vec3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use reyes::bezier;
use reyes::model::Model;
use reyes::subdiv::{BoundaryInterpolation, Corner, Crease, INFINITE_SHARPNESS, Mesh};
use subdiv_geometry::{Buckets, Triangle, patch_triangles, reference_triangles};
use subdiv_reference::RefMesh;

/// A random generator drawn afresh, its seed printed; `TEST_SEED=<seed>`
/// replays a run.
fn fresh_rng(test: &str) -> StdRng {
    let seed: u64 = std::env::var("TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(rand::random);
    eprintln!("{test} seed = {seed} (replay with TEST_SEED={seed})");
    StdRng::seed_from_u64(seed)
}

fn mesh(positions: Vec<Vec3>, faces: &[&[u32]]) -> Mesh {
    Mesh {
        positions,
        face_sizes: faces.iter().map(|f| f.len() as u32).collect(),
        face_vertices: faces.iter().flat_map(|f| f.iter().copied()).collect(),
        ..Mesh::default()
    }
}

/// Moves every vertex by up to `amount` in each coordinate.
fn jitter(mut m: Mesh, rng: &mut StdRng, amount: f32) -> Mesh {
    for p in &mut m.positions {
        *p += Vec3::new(
            rng.random_range(-amount..amount),
            rng.random_range(-amount..amount),
            rng.random_range(-amount..amount),
        );
    }
    m
}

/// The cube [-1, 1]^3, faces wound outwards.
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
    mesh(
        positions,
        &[
            &[0, 2, 3, 1],
            &[4, 5, 7, 6],
            &[0, 1, 5, 4],
            &[2, 6, 7, 3],
            &[0, 4, 6, 2],
            &[1, 3, 7, 5],
        ],
    )
}

fn creased_cube() -> Mesh {
    let mut m = cube();
    m.creases = vec![
        Crease {
            vertices: vec![0, 1, 3],
            sharpness: 1.0,
        },
        Crease {
            vertices: vec![4, 5],
            sharpness: 2.0,
        },
        Crease {
            vertices: vec![6, 7, 3],
            sharpness: INFINITE_SHARPNESS,
        },
        Crease {
            vertices: vec![2, 6],
            sharpness: 0.5,
        },
    ];
    m
}

fn cornered_cube() -> Mesh {
    let mut m = cube();
    m.corners = vec![Corner {
        vertex: 7,
        sharpness: INFINITE_SHARPNESS,
    }];
    m
}

fn tetrahedron() -> Mesh {
    mesh(
        vec![
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
        ],
        &[&[0, 1, 2], &[0, 3, 1], &[0, 2, 3], &[1, 3, 2]],
    )
}

/// An octagonal pyramid (valence 8 at the apex and, after the first step,
/// at the base's face point; valence 3 at the base) next to a pentagonal
/// bipyramid (valence 5 at its apexes).
fn valences() -> Mesh {
    let mut positions = vec![Vec3::new(0.0, 0.0, 1.5)];
    for i in 0..8 {
        let a = i as f32 * std::f32::consts::TAU / 8.0;
        positions.push(Vec3::new(a.cos(), a.sin(), 0.0));
    }
    let mut faces: Vec<Vec<u32>> = (0..8).map(|i| vec![0, 1 + i, 1 + (i + 1) % 8]).collect();
    faces.push((1..9).rev().collect());
    let base = positions.len() as u32;
    positions.push(Vec3::new(3.5, 0.0, 1.0));
    positions.push(Vec3::new(3.5, 0.0, -1.0));
    for i in 0..5 {
        let a = i as f32 * std::f32::consts::TAU / 5.0;
        positions.push(Vec3::new(3.5 + a.cos(), a.sin(), 0.0));
    }
    for i in 0..5 {
        let (a, b) = (base + 2 + i, base + 2 + (i + 1) % 5);
        faces.push(vec![base, a, b]);
        faces.push(vec![base + 1, b, a]);
    }
    let refs: Vec<&[u32]> = faces.iter().map(|f| f.as_slice()).collect();
    mesh(positions, &refs)
}

/// A `n x n` grid of quads over `[0, n]^2`, with a bump.
fn grid(n: u32) -> Mesh {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32, j as f32);
            let c = n as f32 / 2.0;
            let z = 0.8 * (-((x - c).powi(2) + (y - c).powi(2)) / 3.0).exp();
            positions.push(Vec3::new(x, y, z));
        }
    }
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i;
            faces.push(vec![v, v + 1, v + n + 2, v + n + 1]);
        }
    }
    let refs: Vec<&[u32]> = faces.iter().map(|f| f.as_slice()).collect();
    mesh(positions, &refs)
}

/// The cube with its top face (+z) a hole.
fn holed_cube() -> Mesh {
    let mut m = cube();
    m.holes = vec![1];
    m
}

/// The uniform reference `levels` deep: the refined mesh and its limit
/// positions.
fn reference(mesh: &Mesh, levels: usize) -> (RefMesh, Vec<DVec3>) {
    let mut r = RefMesh::new(mesh);
    for _ in 0..levels {
        r = r.refine();
    }
    let limit = r.limit();
    (r, limit)
}

/// What [`compare`] measured.
#[derive(Debug)]
struct Comparison {
    /// The largest distance from a reference limit point to the patches.
    reference_to_patches: f64,
    /// The largest distance from a patch point to the reference surface.
    patches_to_reference: f64,
    /// The largest angle (degrees) between a patch normal and the
    /// reference normal, away from extraordinary vertices and creases.
    normal_degrees: f64,
    /// How far the worst normal is from the nearest irregular point.
    worst_normal_at: f64,
    /// The bounding box diagonal of the reference limit points.
    diagonal: f64,
}

/// Compares the patches of `mesh` with its uniform reference `levels` deep.
fn compare(mesh: &Mesh, model: &Model, levels: usize) -> Comparison {
    let (r, limit) = reference(mesh, levels);
    let vertex_faces = r.vertex_faces();
    let neighbours = r.neighbours();
    let visible: Vec<usize> = (0..r.points.len())
        .filter(|&v| vertex_faces[v].iter().any(|&f| !r.hidden[f]))
        .collect();
    let (lo, hi) = visible.iter().fold(
        (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
        |(lo, hi), &v| (lo.min(limit[v]), hi.max(limit[v])),
    );
    let diagonal = (hi - lo).length();
    let reach = 6e-3 * diagonal;
    let cell = diagonal / 64.0;
    let patches = Buckets::new(patch_triangles(model, 12), cell, reach);
    let surface = Buckets::new(reference_triangles(&r, &limit), cell, reach);
    let far = |hit: Option<(f64, Triangle, [f64; 3])>| hit.map_or(f64::INFINITY, |h| h.0);

    let reference_to_patches = visible
        .iter()
        .map(|&v| far(patches.nearest(limit[v])))
        .fold(0.0, f64::max);
    let patches_to_reference = patches
        .triangles
        .iter()
        .flat_map(|t| t.corners)
        .map(|p| far(surface.nearest(p)))
        .fold(0.0, f64::max);

    // Normals at interior valence-4 vertices away from anything irregular.
    let normals = r.normals(&limit);
    let cones: Vec<DVec3> = (0..r.points.len())
        .filter(|&v| r.corner[v] > 0.0)
        .map(|v| limit[v])
        .collect();
    let special: Vec<DVec3> = (0..r.points.len())
        .filter(|&v| {
            let boundary = neighbours[v].len() != vertex_faces[v].len();
            let regular_valence = if boundary { 3 } else { 4 };
            !vertex_faces[v].is_empty()
                && (neighbours[v].len() != regular_valence
                    || r.corner[v] > 0.0
                    || neighbours[v]
                        .iter()
                        .any(|&w| r.tagged.contains(&(v.min(w), v.max(w)))))
        })
        .map(|v| limit[v])
        .collect();
    // Central differences converge slowly near a sharp vertex's cone.
    let (radius, cone_radius) = (0.04 * diagonal, 0.15 * diagonal);
    let mut normal_degrees: f64 = 0.0;
    let mut worst_normal_at = 0.0;
    for &v in &visible {
        let interior = neighbours[v].len() == 4 && vertex_faces[v].len() == 4;
        if !interior
            || vertex_faces[v].iter().any(|&f| r.hidden[f])
            || special.iter().any(|s| (*s - limit[v]).length() < radius)
            || cones.iter().any(|s| (*s - limit[v]).length() < cone_radius)
        {
            continue;
        }
        let Some((_, t, bary)) = patches.nearest(limit[v]) else {
            continue;
        };
        let u = t.uv[0].0 * bary[0] + t.uv[1].0 * bary[1] + t.uv[2].0 * bary[2];
        let w = t.uv[0].1 * bary[0] + t.uv[1].1 * bary[1] + t.uv[2].1 * bary[2];
        let points = &model.patches[t.patch].points;
        let (u, w) = (u.clamp(0.0, 1.0) as f32, w.clamp(0.0, 1.0) as f32);
        // A fan patch's edge v = 1 collapses to a point, where its normal is
        // all rounding: look just off it.
        let collapsed = points[12..].iter().all(|&p| p == points[12]);
        let w = if collapsed { w.min(0.98) } else { w };
        let e = bezier::evaluate(points, u, w);
        let n = e.d_ds.cross(e.d_dt).as_dvec3().normalize();
        let angle = n.dot(normals[v].normalize()).clamp(-1.0, 1.0).acos();
        if angle.to_degrees() > normal_degrees {
            normal_degrees = angle.to_degrees();
            worst_normal_at = special
                .iter()
                .map(|s| (*s - limit[v]).length())
                .fold(f64::MAX, f64::min);
        }
    }
    Comparison {
        reference_to_patches,
        patches_to_reference,
        normal_degrees,
        worst_normal_at,
        diagonal,
    }
}

/// Subdivides `mesh` and checks it against the reference: distances within
/// 2e-3 of the diagonal both ways, the reported error within that too,
/// normals within 2 degrees.
fn check_surface(name: &str, mesh: &Mesh) -> Model {
    let out = mesh.to_patches().unwrap();
    let levels = std::env::var("REF_LEVELS").map_or(5, |s| s.parse().unwrap());
    let c = compare(mesh, &out.model, levels);
    let eps = 2e-3 * c.diagonal;
    println!("{name}: {:?} {c:?} eps {eps:.2e}", out.report);
    assert!(
        c.reference_to_patches <= eps,
        "{name}: a limit point is {} from the patches (eps {eps})",
        c.reference_to_patches
    );
    assert!(
        c.patches_to_reference <= eps,
        "{name}: a patch point is {} from the limit surface (eps {eps})",
        c.patches_to_reference
    );
    assert!(
        f64::from(out.report.max_error) <= eps,
        "{name}: reported error {}",
        out.report.max_error
    );
    assert!(
        c.normal_degrees <= 2.0,
        "{name}: normals {} degrees off, {} from an irregular point",
        c.normal_degrees,
        c.worst_normal_at
    );
    out.model
}

// ---------------------------------------------------------------------------
// Watertightness, structurally.

type CurveBits = [[u32; 3]; 4];

fn bits(c: [Vec3; 4]) -> CurveBits {
    c.map(|p| p.to_array().map(f32::to_bits))
}

fn reversed(c: [Vec3; 4]) -> [Vec3; 4] {
    [c[3], c[2], c[1], c[0]]
}

/// The four boundary curves of every patch, each running around the patch.
fn boundary_curves(model: &Model) -> Vec<[Vec3; 4]> {
    const EDGES: [[usize; 4]; 4] = [
        [0, 1, 2, 3],
        [3, 7, 11, 15],
        [15, 14, 13, 12],
        [12, 8, 4, 0],
    ];
    model
        .patches
        .iter()
        .flat_map(|p| EDGES.map(|e| e.map(|i| p.points[i])))
        .collect()
}

/// Whether `c` is met exactly by reversed curves of the set, either whole
/// or as De Casteljau halves (down to `depth` splits); marks the curves
/// that meet it.
fn cover(
    c: [Vec3; 4],
    depth: u32,
    set: &HashMap<CurveBits, Vec<usize>>,
    marks: &mut Vec<usize>,
) -> bool {
    if let Some(list) = set.get(&bits(reversed(c))) {
        marks.extend(list);
        return true;
    }
    if depth == 0 {
        return false;
    }
    let (l, r) = bezier::split_cubic(c);
    let before = marks.len();
    if cover(l, depth - 1, set, marks) && cover(r, depth - 1, set, marks) {
        return true;
    }
    marks.truncate(before);
    false
}

/// The boundary curves that no other patch meets: neither the same curve
/// reversed, nor De Casteljau halves of it, nor a curve it is a half of.
fn unmatched_curves(model: &Model) -> Vec<usize> {
    let curves = boundary_curves(model);
    let mut set: HashMap<CurveBits, Vec<usize>> = HashMap::new();
    for (i, &c) in curves.iter().enumerate() {
        set.entry(bits(c)).or_default().push(i);
    }
    let mut matched: HashSet<usize> = HashSet::new();
    for (i, &c) in curves.iter().enumerate() {
        let mut marks = Vec::new();
        if cover(c, 8, &set, &mut marks) {
            matched.insert(i);
            matched.extend(marks);
        }
    }
    (0..curves.len()).filter(|i| !matched.contains(i)).collect()
}

/// Closed meshes: every boundary curve met, and the check catches one
/// control point moved by 1e-4.
fn check_watertight(name: &str, model: &Model) {
    let unmatched = unmatched_curves(model);
    assert!(
        unmatched.is_empty(),
        "{name}: {} of {} curves unmatched",
        unmatched.len(),
        model.patches.len() * 4
    );
    for patch in [0, model.patches.len() - 1] {
        let mut moved = model.clone();
        moved.patches[patch].points[1].x += 1e-4;
        assert!(
            !unmatched_curves(&moved).is_empty(),
            "{name}: moving patch {patch}'s edge went unnoticed"
        );
    }
}

#[test]
fn the_cube_matches_the_limit_surface_and_is_watertight() {
    let mut rng = fresh_rng("cube");
    let m = jitter(cube(), &mut rng, 0.1);
    let model = check_surface("cube", &m);
    check_watertight("cube", &model);
}

#[test]
fn a_creased_cube_follows_its_creases() {
    let mut rng = fresh_rng("creased cube");
    let m = jitter(creased_cube(), &mut rng, 0.1);
    let model = check_surface("creased cube", &m);
    check_watertight("creased cube", &model);
}

#[test]
fn a_corner_stays_sharp() {
    let mut rng = fresh_rng("corner");
    let m = jitter(cornered_cube(), &mut rng, 0.1);
    let model = check_surface("corner", &m);
    check_watertight("corner", &model);
}

#[test]
fn a_tetrahedron_is_refined_once_then_matched() {
    let mut rng = fresh_rng("tetrahedron");
    let m = jitter(tetrahedron(), &mut rng, 0.1);
    let model = check_surface("tetrahedron", &m);
    check_watertight("tetrahedron", &model);
}

#[test]
fn valences_three_five_and_eight() {
    let mut rng = fresh_rng("valences");
    let m = jitter(valences(), &mut rng, 0.05);
    let model = check_surface("valences", &m);
    check_watertight("valences", &model);
}

#[test]
fn a_hole_leaves_its_neighbours_in_place() {
    let mut rng = fresh_rng("hole");
    let m = jitter(holed_cube(), &mut rng, 0.1);
    check_surface("hole", &m);
}

#[test]
fn open_grids_under_each_boundary_rule() {
    let mut rng = fresh_rng("grids");
    for boundary in [
        BoundaryInterpolation::EdgeAndCorner,
        BoundaryInterpolation::EdgeOnly,
        BoundaryInterpolation::None,
    ] {
        let mut m = jitter(grid(6), &mut rng, 0.1);
        m.boundary = boundary;
        check_surface(&format!("grid {boundary:?}"), &m);
    }
}

/// A 1000 x 1000 grid (a million faces) with a semi-sharp crease, a sharp
/// corner and a dart: refinement stays local, so the patches are about one
/// per face and the run takes seconds.
#[test]
fn a_million_faces_refine_only_around_their_features() {
    let n = 1000;
    let mut m = grid(n);
    m.boundary = BoundaryInterpolation::EdgeAndCorner;
    let row = 500 * (n + 1);
    m.creases = vec![
        Crease {
            vertices: (row + 100..row + 120).collect(),
            sharpness: 2.5,
        },
        Crease {
            vertices: vec![row + 700, row + 701],
            sharpness: INFINITE_SHARPNESS,
        },
    ];
    m.corners = vec![Corner {
        vertex: row + 300,
        sharpness: INFINITE_SHARPNESS,
    }];
    let start = std::time::Instant::now();
    let out = m.to_patches().unwrap();
    let faces = (n * n) as usize;
    println!("{:?} in {:.1?}", out.report, start.elapsed());
    assert!(out.model.patches.len() >= faces);
    assert!(
        out.model.patches.len() < faces + 20_000,
        "{} patches",
        out.model.patches.len()
    );
}

/// Whether the pixel centre `p` is inside the triangle `a b c` (either
/// winding).
fn inside(p: glam::Vec2, [a, b, c]: [glam::Vec2; 3]) -> bool {
    let edge = |a: glam::Vec2, b: glam::Vec2| (b - a).perp_dot(p - a);
    let (e0, e1, e2) = (edge(a, b), edge(b, c), edge(c, a));
    (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0)
}

/// At 800 x 600, the CPU reference's coverage of the patches against the
/// reference mesh's limit quads rasterized at pixel centres: IoU >= 0.995.
#[test]
fn coverage_matches_the_reference_tessellation() {
    use glam::Vec2;
    use reyes::prepare::PreparedScene;
    use reyes::scene::Scene;
    let (width, height, spp) = (800usize, 600usize, 4u32);
    for (name, m) in [("cube", cube()), ("valences", valences())] {
        let out = m.to_patches().unwrap();
        // The same mesh's flat (bilinear) patches, which must fall short.
        let flat = Mesh {
            scheme: reyes::subdiv::Scheme::Bilinear,
            ..m.clone()
        }
        .to_patches()
        .unwrap();
        let mut scene = Scene::for_model("subdivision test model", &out.model);
        scene.resolution.width = width as u32;
        scene.resolution.height = height as u32;
        scene.spp = spp;
        let prepared = PreparedScene::new(&scene, std::slice::from_ref(&out.model)).unwrap();
        let (r, limit) = reference(&m, 5);
        let camera = &prepared.camera;
        let view_proj = camera.view_proj();
        let pixel = |p: DVec3| {
            camera
                .to_pixel(view_proj * p.as_vec3().extend(1.0))
                .truncate()
        };
        let mut mask = vec![false; width * height];
        for (f, face) in r.faces.iter().enumerate() {
            if r.hidden[f] {
                continue;
            }
            let q: Vec<Vec2> = face.iter().map(|&v| pixel(limit[v])).collect();
            for tri in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
                let lo = tri[0].min(tri[1]).min(tri[2]).floor().max(Vec2::ZERO);
                let hi = tri[0].max(tri[1]).max(tri[2]).ceil();
                for y in lo.y as usize..(hi.y as usize).min(height) {
                    for x in lo.x as usize..(hi.x as usize).min(width) {
                        if inside(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), tri) {
                            mask[y * width + x] = true;
                        }
                    }
                }
            }
        }
        let iou = |model: &Model| {
            let prepared = PreparedScene::new(&scene, std::slice::from_ref(model)).unwrap();
            let rendered = reyes::reference::render(&prepared);
            let (mut both, mut either) = (0usize, 0usize);
            for (&c, &m) in rendered.covered_samples.iter().zip(&mask) {
                let covered = 2 * u32::from(c) >= spp && c > 0;
                both += usize::from(covered && m);
                either += usize::from(covered || m);
            }
            both as f64 / either as f64
        };
        let (smooth, bilinear) = (iou(&out.model), iou(&flat.model));
        println!("{name}: coverage IoU {smooth:.5}; the bilinear patches' {bilinear:.5}");
        assert!(smooth >= 0.995, "{name}: IoU {smooth}");
        assert!(
            bilinear < 0.995,
            "{name}: the bilinear patches pass too ({bilinear})"
        );
    }
}
