//! Texture coordinates `s`, `t` from RIB to `prepare`: the
//! `TextureCoordinates` attribute, per-vertex `"st"` (and `"s"`, `"t"`) on
//! patches, patch meshes and polygons, the quadrics' own `(u, v)`, the
//! `.bpt` texture coordinate section and the `convert` round trip.

use std::path::PathBuf;

use glam::{Vec2, Vec3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use reyes::model::{DEFAULT_ST, Model, Patch};
use reyes::prepare::{PreparedScene, WorldPatch};
use reyes::rib::RibScene;
use reyes::scene::{Scene, SceneError};

/// A fresh, empty directory under the system's temporary directory.
fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "reyes-texcoords-test-{}-{test}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The prepared patches of `body`, inside a world block whose object space
/// is camera space moved 5 units ahead.
fn prepared(body: &str) -> Vec<WorldPatch> {
    let text = format!(
        "Projection \"perspective\" \"fov\" 60\nWorldBegin\nTranslate 0 0 5\n{body}\nWorldEnd\n"
    );
    let rib = RibScene::from_text(&text, "st.rib").unwrap_or_else(|e| panic!("{e}"));
    rib.prepare().unwrap().patches
}

fn st_of(body: &str) -> Vec<[Vec2; 4]> {
    prepared(body).iter().map(|p| p.st).collect()
}

fn v2(s: f32, t: f32) -> Vec2 {
    Vec2::new(s, t)
}

/// The bilinear blend of `c` (corner order (0,0), (1,0), (0,1), (1,1)).
fn bilerp(c: [Vec2; 4], u: f32, v: f32) -> Vec2 {
    c[0] * (1.0 - u) * (1.0 - v) + c[1] * u * (1.0 - v) + c[2] * (1.0 - u) * v + c[3] * u * v
}

fn close(a: &[[Vec2; 4]], b: &[[Vec2; 4]]) -> bool {
    a.len() == b.len()
        && a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| x.abs_diff_eq(*y, 1e-5))
}

const SQUARE: &str = "\"P\" [-1 -1 0  1 -1 0  -1 1 0  1 1 0]";

#[test]
fn without_texture_coordinates_s_t_are_u_v() {
    assert_eq!(
        st_of(&format!("Patch \"bilinear\" {SQUARE}")),
        vec![DEFAULT_ST]
    );
}

#[test]
fn texture_coordinates_set_the_corners_of_patches_and_meshes() {
    let coords = [v2(0.1, 0.2), v2(0.9, 0.3), v2(0.2, 0.8), v2(0.7, 0.95)];
    let attribute = "TextureCoordinates 0.1 0.2 0.9 0.3 0.2 0.8 0.7 0.95";
    // A patch: the corners themselves.
    assert_eq!(
        st_of(&format!("{attribute}\nPatch \"bilinear\" {SQUARE}")),
        vec![coords]
    );
    // A bilinear mesh of 3 x 2 points, 2 x 1 patches: the mesh's (u, v)
    // spans it all, so each patch takes its half of the corners' blend.
    let mesh = st_of(&format!(
        "{attribute}\nPatchMesh \"bilinear\" 3 \"nonperiodic\" 2 \"nonperiodic\" \"P\" [-1 -1 0  0 -1 0  1 -1 0  -1 1 0  0 1 0  1 1 0]"
    ));
    let expected = [
        [
            bilerp(coords, 0.0, 0.0),
            bilerp(coords, 0.5, 0.0),
            bilerp(coords, 0.0, 1.0),
            bilerp(coords, 0.5, 1.0),
        ],
        [
            bilerp(coords, 0.5, 0.0),
            bilerp(coords, 1.0, 0.0),
            bilerp(coords, 0.5, 1.0),
            bilerp(coords, 1.0, 1.0),
        ],
    ];
    assert!(close(&mesh, &expected), "{mesh:?}");
    // An attribute: AttributeEnd restores the default.
    let scoped = st_of(&format!(
        "AttributeBegin\n{attribute}\nPatch \"bilinear\" {SQUARE}\nAttributeEnd\nPatch \"bilinear\" {SQUARE}"
    ));
    assert_eq!(scoped, vec![coords, DEFAULT_ST]);
}

#[test]
fn per_vertex_st_on_a_patch() {
    let given = [v2(5.0, 6.0), v2(7.0, 6.5), v2(5.5, 8.0), v2(7.5, 9.0)];
    let st = "[5 6  7 6.5  5.5 8  7.5 9]";
    // Varying (the standard class) on a bilinear patch, over
    // TextureCoordinates.
    assert_eq!(
        st_of(&format!(
            "TextureCoordinates 0 0 2 0 0 2 2 2\nPatch \"bilinear\" {SQUARE} \"st\" {st}"
        )),
        vec![given]
    );
    // "s" alone: t stays the default (v).
    assert_eq!(
        st_of(&format!("Patch \"bilinear\" {SQUARE} \"s\" [5 7 5.5 7.5]")),
        vec![[v2(5.0, 0.0), v2(7.0, 0.0), v2(5.5, 1.0), v2(7.5, 1.0)]]
    );
    // Varying on a bicubic patch: four values, at the corners.
    let bicubic_points: String = (0..16)
        .map(|k| {
            format!(
                "{} {} 0  ",
                (k % 4) as f32 / 1.5 - 1.0,
                (k / 4) as f32 / 1.5 - 1.0
            )
        })
        .collect();
    assert_eq!(
        st_of(&format!(
            "Patch \"bicubic\" \"P\" [{bicubic_points}] \"st\" {st}"
        )),
        vec![given]
    );
    // Vertex class on a bicubic patch: the basis at the corners. With
    // Bezier's, the corner control points' values; with the B-spline's,
    // (a + 4b + c) / 6 along each direction.
    let values: Vec<f32> = (0..32).map(|k| (k * k % 17) as f32).collect();
    let list: String = values.iter().map(|x| format!("{x} ")).collect();
    let at = |i: usize, j: usize| v2(values[2 * (j * 4 + i)], values[2 * (j * 4 + i) + 1]);
    assert_eq!(
        st_of(&format!(
            "Patch \"bicubic\" \"P\" [{bicubic_points}] \"vertex float[2] st\" [{list}]"
        )),
        vec![[at(0, 0), at(3, 0), at(0, 3), at(3, 3)]]
    );
    let spline = st_of(&format!(
        "Basis \"b-spline\" 1 \"b-spline\" 1\nDeclare \"st\" \"vertex float[2]\"\nPatch \"bicubic\" \"P\" [{bicubic_points}] \"st\" [{list}]"
    ));
    let along = |f: &dyn Fn(usize) -> Vec2, first: usize| {
        (f(first) + 4.0 * f(first + 1) + f(first + 2)) / 6.0
    };
    let corner = |i0: usize, j0: usize| along(&|j| along(&|i| at(i, j), i0), j0);
    let expected = [[corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1)]];
    assert!(close(&spline, &expected), "{spline:?} vs {expected:?}");
}

#[test]
fn per_vertex_st_on_a_patch_mesh() {
    // 3 x 3 points, bilinear: 2 x 2 patches, 9 varying values (one per
    // patch corner), row by row.
    let points: String = (0..9)
        .map(|k| format!("{} {} 0  ", (k % 3) as f32 - 1.0, (k / 3) as f32 - 1.0))
        .collect();
    let value = |i: usize, j: usize| v2(10.0 * i as f32 + j as f32, 100.0 + (i * j) as f32);
    let list: String = (0..9)
        .map(|k| {
            let v = value(k % 3, k / 3);
            format!("{} {}  ", v.x, v.y)
        })
        .collect();
    let st = st_of(&format!(
        "PatchMesh \"bilinear\" 3 \"nonperiodic\" 3 \"nonperiodic\" \"P\" [{points}] \"st\" [{list}]"
    ));
    let mut expected = Vec::new();
    for pv in 0..2 {
        for pu in 0..2 {
            expected.push([
                value(pu, pv),
                value(pu + 1, pv),
                value(pu, pv + 1),
                value(pu + 1, pv + 1),
            ]);
        }
    }
    assert_eq!(st, expected);
    // Uniform: one per patch, at all four corners.
    let st = st_of(&format!(
        "PatchMesh \"bilinear\" 3 \"nonperiodic\" 3 \"nonperiodic\" \"P\" [{points}] \"uniform float s\" [1 2 3 4]"
    ));
    let s: Vec<f32> = st.iter().map(|c| c[0].x).collect();
    assert_eq!(s, [1.0, 2.0, 3.0, 4.0]);
    assert!(st.iter().all(|c| c.iter().all(|p| p.x == c[0].x)));
}

#[test]
fn per_vertex_st_on_polygons() {
    // A quad: one patch with corners (u, v) = (0,0) a, (1,0) b, (0,1) d,
    // (1,1) c of the fan (a, b, c, d).
    let quad = "\"P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]";
    let st = "\"st\" [0 0  1 0  1 1  0 1]";
    assert_eq!(
        st_of(&format!("Polygon {quad} {st}")),
        vec![[v2(0.0, 0.0), v2(1.0, 0.0), v2(0.0, 1.0), v2(1.0, 1.0)]]
    );
    // A pentagon: a quad and a last triangle (its third corner doubled).
    let pentagon = "\"P\" [0 -1 0  1 -0.3 0  0.6 1 0  -0.6 1 0  -1 -0.3 0]";
    let st5 = "\"st\" [0 0  1 0  2 0  3 0  4 0]";
    let s = |k: f32| v2(k, 0.0);
    assert_eq!(
        st_of(&format!("Polygon {pentagon} {st5}")),
        vec![
            [s(0.0), s(1.0), s(3.0), s(2.0)],
            [s(0.0), s(3.0), s(4.0), s(4.0)]
        ]
    );
    // Without st, each fan patch has the unit square (TextureCoordinates
    // apply to parametric primitives only).
    assert_eq!(
        st_of(&format!(
            "TextureCoordinates 5 5 6 5 5 6 6 6\nPolygon {pentagon}"
        )),
        vec![DEFAULT_ST, DEFAULT_ST]
    );
    // PointsPolygons: varying values follow the points (shared between
    // faces), face-varying ones the vertid positions.
    let points = "\"P\" [-1 -1 0  0 -1 0  1 -1 0  -1 1 0  0 1 0  1 1 0]";
    let faces = "PointsPolygons [4 4] [0 1 4 3  1 2 5 4]";
    let varying = st_of(&format!(
        "{faces} {points} \"st\" [0 0  1 0  2 0  0 1  1 1  2 1]"
    ));
    assert_eq!(
        varying,
        vec![
            [v2(0.0, 0.0), v2(1.0, 0.0), v2(0.0, 1.0), v2(1.0, 1.0)],
            [v2(1.0, 0.0), v2(2.0, 0.0), v2(1.0, 1.0), v2(2.0, 1.0)],
        ]
    );
    let facevarying = st_of(&format!(
        "{faces} {points} \"facevarying float s\" [10 11 12 13  20 21 22 23]"
    ));
    let s: Vec<Vec<f32>> = facevarying
        .iter()
        .map(|c| c.iter().map(|p| p.x).collect())
        .collect();
    // Fan corners (a, b, d, c) of each face's vertices 0..4.
    assert_eq!(
        s,
        vec![vec![10.0, 11.0, 13.0, 12.0], vec![20.0, 21.0, 23.0, 22.0]]
    );
}

#[test]
fn wrong_st_counts_and_declarations_are_errors() {
    for (body, message) in [
        (
            format!("Patch \"bilinear\" {SQUARE} \"st\" [0 0 1 0 0 1]"),
            "has 3 values; this primitive needs 4",
        ),
        (
            format!("Patch \"bilinear\" {SQUARE} \"st\" [0 0 1 0 0 1 1]"),
            "not pairs",
        ),
        (
            format!("Patch \"bilinear\" {SQUARE} \"varying color st\" [0 0 0]"),
            "texture coordinates are float",
        ),
        (
            "TextureCoordinates 0 0 1 0 0 1 1".to_owned(),
            "expected 8 numbers",
        ),
    ] {
        let text = format!("WorldBegin\nTranslate 0 0 5\n{body}\nWorldEnd\n");
        let error = RibScene::from_text(&text, "bad.rib").expect_err(&body);
        assert!(error.to_string().contains(message), "{body}: {error}");
    }
}

/// The angle of `(x, y)` as a fraction of a turn, in `[0, 1)`.
fn turn(x: f32, y: f32) -> f32 {
    y.atan2(x).rem_euclid(std::f32::consts::TAU) / std::f32::consts::TAU
}

#[test]
fn a_quadric_s_patches_tile_the_unit_square_of_st() {
    for (request, v_of) in [
        (
            "Cylinder 1 -1 2 360",
            &(|p: Vec3| (p.z + 1.0) / 3.0) as &dyn Fn(Vec3) -> f32,
        ),
        (
            "Sphere 1 -1 1 360",
            &(|p: Vec3| (p.z.clamp(-1.0, 1.0).asin() / std::f32::consts::PI) + 0.5),
        ),
    ] {
        let patches = prepared(request);
        assert!(patches.len() >= 4, "{request}: {} patches", patches.len());
        let mut area = 0.0;
        for patch in &patches {
            let [a, b, c, d] = patch.st;
            // An axis-aligned rectangle of the unit square.
            assert!(a.x < b.x && a.y < c.y, "{request}: {:?}", patch.st);
            assert_eq!((a.y, c.x, d), (b.y, a.x, Vec2::new(b.x, c.y)));
            assert!(
                patch
                    .st
                    .iter()
                    .all(|p| (0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y))
            );
            area += (b.x - a.x) * (c.y - a.y);
            // Its corners are the quadric's points at (u, v) = st: the
            // patch's corner control points, back in object space (the
            // world mirrors camera space's x; the object is 5 ahead).
            for (corner, index) in [(a, 0), (b, 3), (c, 12), (d, 15)] {
                let w = patch.points[index];
                let p = Vec3::new(-w.x, w.y, w.z - 5.0);
                assert!(
                    (v_of(p) - corner.y).abs() < 1e-3,
                    "{request}: {p} at {corner}"
                );
                if p.truncate().length() > 1e-3 {
                    let u = turn(p.x, p.y);
                    let du = (u - corner.x).abs();
                    assert!(du.min(1.0 - du) < 1e-3, "{request}: {p} at {corner}");
                }
            }
        }
        assert!((area - 1.0).abs() < 1e-5, "{request}: area {area}");
        // Disjoint: no two rectangles overlap inside.
        for (i, p) in patches.iter().enumerate() {
            for q in &patches[i + 1..] {
                let overlap_s = p.st[1].x.min(q.st[1].x) - p.st[0].x.max(q.st[0].x);
                let overlap_t = p.st[2].y.min(q.st[2].y) - p.st[0].y.max(q.st[0].y);
                assert!(
                    overlap_s <= 1e-6 || overlap_t <= 1e-6,
                    "{request}: {:?} and {:?}",
                    p.st,
                    q.st
                );
            }
        }
    }
    // TextureCoordinates map the quadric's (u, v) square.
    let scaled = st_of("TextureCoordinates 0 0 2 0 0 4 2 4\nCylinder 1 -1 2 360");
    let max = scaled.iter().flatten().fold(Vec2::ZERO, |m, p| m.max(*p));
    assert_eq!(max, Vec2::new(2.0, 4.0));
}

#[test]
fn convert_keeps_st() {
    let dir = temp_dir("convert");
    // One object (same attributes): a plain patch, a sphere and a polygon
    // with st; then another object without any st.
    let text = format!(
        "Projection \"perspective\" \"fov\" 60\nWorldBegin\nTranslate 0 0 5\n\
         Patch \"bilinear\" {SQUARE}\n\
         Sphere 1 -1 1 360\n\
         Polygon \"P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0] \"st\" [0.25 0.5  1 0  1 1  0 1]\n\
         Color [1 0 0]\nPatch \"bilinear\" {SQUARE}\nWorldEnd\n"
    );
    let rib = RibScene::from_text(&text, dir.join("st.rib")).unwrap();
    let st = |prepared: &PreparedScene| prepared.patches.iter().map(|p| p.st).collect::<Vec<_>>();
    let before = st(&rib.prepare().unwrap());
    assert!(before.iter().any(|c| *c != DEFAULT_ST));
    let toml = dir.join("st.toml");
    let written = rib.write(&toml).unwrap();
    let scene = Scene::load(&toml).unwrap();
    assert_eq!(st(&PreparedScene::load(&scene).unwrap()), before);
    // The object without st is written without the section.
    let bpt: Vec<String> = written[..2]
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    assert!(bpt[0].contains("\nst "), "{}", bpt[0]);
    assert!(!bpt[1].contains("st"), "{}", bpt[1]);
}

/// A random model with texture coordinates.
fn random_model(rng: &mut StdRng) -> Model {
    let n = rng.random_range(1..5);
    let mut point = || Vec3::new(rng.random(), rng.random(), rng.random());
    let patches: Vec<Patch> = (0..n)
        .map(|_| Patch {
            points: std::array::from_fn(|_| point()),
        })
        .collect();
    let st = (0..n)
        .map(|_| std::array::from_fn(|_| Vec2::new(rng.random_range(-1e3..1e3), rng.random())))
        .collect();
    Model {
        patches,
        st: Some(st),
    }
}

#[test]
fn bpt_st_round_trips_and_bad_sections_are_refused() {
    let seed: u64 = std::env::var("TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(rand::random);
    eprintln!("bpt_st seed = {seed} (replay with TEST_SEED={seed})");
    let mut rng = StdRng::seed_from_u64(seed);
    for _ in 0..20 {
        let model = random_model(&mut rng);
        let text = reyes::load::bpt::write(&model);
        assert_eq!(reyes::load::bpt::parse(&text).unwrap(), model);
    }
    let plain = reyes::load::bpt::write(&Model::new(random_model(&mut rng).patches));
    assert!(!plain.contains("st"));
    let one = reyes::load::bpt::write(&Model::new(vec![Patch::default()]));
    for (section, message) in [
        ("st 2\n0 0 1 0 0 1 1 1\n", "expected \"st 1\""),
        ("st\n0 0 1 0 0 1 1 1\n", "expected \"st 1\""),
        ("st 1\n0 0 1 0 0 1 1\n", "expected 8 texture coordinates"),
        ("st 1\n0 0 1 0 0 1 1 x\n", "expected a number"),
        ("st 1\n0 0 1 0 0 1 1 inf\n", "not finite"),
        ("st 1\n", "texture coordinates (8 numbers) of patch 1"),
        ("st 1\n0 0 1 0 0 1 1 1\nmore\n", "more"),
    ] {
        let error = reyes::load::bpt::parse(&format!("{one}{section}")).unwrap_err();
        assert!(error.to_string().contains(message), "{section:?}: {error}");
    }
}

#[test]
fn prepare_refuses_st_that_do_not_fit_the_patches() {
    let model = Model {
        patches: vec![Model::teapot().patches[0]],
        st: Some(vec![DEFAULT_ST; 2]),
    };
    let scene = Scene::for_model("one.bpt", &model);
    let error = PreparedScene::new(&scene, std::slice::from_ref(&model)).unwrap_err();
    assert!(
        matches!(&error, SceneError::InvalidSt { index: 0, .. }),
        "{error}"
    );
    assert!(
        error
            .to_string()
            .contains("2 texture coordinate entries for 1 patches")
    );
}
