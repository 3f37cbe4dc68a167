//! OBJ meshes: the mesh `load::obj` reads (compared whole), the errors
//! each malformed file gives (naming the face, its line and the file),
//! the patch budget, the scene's `subdivision` key, and an OBJ cube
//! rendered as the same cube given as patches.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use reyes::LoadError;
use reyes::budget::PatchBudget;
use reyes::load::obj;
use reyes::model::{Model, Patch};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Scene, SceneError};
use reyes::subdiv::{BoundaryInterpolation, Mesh, MeshError, Scheme};

/// A fresh, empty directory under the system's temporary directory.
fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "reyes-mesh-input-test-{}-{test}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn mesh_of(text: &str) -> Result<obj::ObjMesh, LoadError> {
    obj::parse_mesh(text, Path::new("m.obj"), Scheme::Bilinear)
}

/// A quad, a triangle and a pentagon in three groups, sharing edges, each
/// face vertex with a `vt`; the faces first use the vertices in file
/// order, so the mesh's vertex numbers are the file's minus one.
const MIXED: &str = "\
# three faces
mtllib none.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 2 1 0
v 3 0.5 0
v 0.5 2 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
o quad
usemtl red
f 1/1 2/2 3/3 4/4
g triangle
f 4/4 3/3 8/1
g pentagon
s 1
f 2/1 5/2 7/3 6/4 3/3
";

#[test]
fn quads_triangles_and_pentagons_in_groups_make_one_mesh_with_their_vt() {
    let read = mesh_of(MIXED).unwrap_or_else(|e| panic!("{e}"));
    let vt = [
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 0.0),
    ];
    let p = |x, y| Vec3::new(x, y, 0.0);
    let expected = Mesh {
        scheme: Scheme::Bilinear,
        positions: vec![
            p(0.0, 0.0),
            p(1.0, 0.0),
            p(1.0, 1.0),
            p(0.0, 1.0),
            p(0.5, 2.0),
            p(2.0, 0.0),
            p(3.0, 0.5),
            p(2.0, 1.0),
        ],
        face_sizes: vec![4, 3, 5],
        face_vertices: vec![0, 1, 2, 3, 3, 2, 4, 1, 5, 6, 7, 2],
        creases: Vec::new(),
        corners: Vec::new(),
        holes: Vec::new(),
        boundary: BoundaryInterpolation::EdgeAndCorner,
        // `t = 1 - v`: OBJ's v goes up the image.
        st: Some(vec![
            vt[0], vt[1], vt[2], vt[3], vt[3], vt[2], vt[0], vt[0], vt[1], vt[2], vt[3], vt[2],
        ]),
    };
    assert_eq!(read.mesh, expected);
    assert_eq!(read.face_lines, vec![17, 19, 22]);
    assert_eq!(read.file_vertices, vec![1, 2, 3, 4, 8, 5, 7, 6]);
    // One quad, a triangle's 3 and a pentagon's 5 bilinear patches.
    let model = obj::parse_within(
        MIXED,
        Path::new("m.obj"),
        Scheme::Bilinear,
        &mut PatchBudget::new(9),
    )
    .unwrap();
    assert_eq!(model.patches.len(), 9);
    assert_eq!(model.st.map(|st| st.len()), Some(9));
}

#[test]
fn texture_coordinates_on_only_some_faces_are_not_used() {
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1 3 4\n";
    let read = mesh_of(text).unwrap();
    assert_eq!(read.mesh.st, None);
    assert_eq!(read.mesh.face_vertices, vec![0, 1, 2, 0, 2, 3]);
}

/// The OBJ syntax error of `text`: its line and message.
fn syntax_error(text: &str) -> (usize, String) {
    match mesh_of(text) {
        Err(LoadError::ObjSyntax {
            path,
            line,
            message,
        }) => {
            assert_eq!(path, Path::new("m.obj"));
            (line, message)
        }
        other => panic!("expected an OBJ syntax error, got {other:?}"),
    }
}

/// The mesh error of `text`: its line and the error in file terms.
fn mesh_error(text: &str) -> (Option<usize>, MeshError, String) {
    let read = mesh_of(text).unwrap_or_else(|e| panic!("{e}"));
    let error = read.mesh.validate().expect_err("an invalid mesh");
    match read.file_error(Path::new("m.obj"), error) {
        e @ LoadError::Mesh { .. } => {
            let message = e.to_string();
            let LoadError::Mesh { line, source, .. } = e else {
                unreachable!()
            };
            (line, source, message)
        }
        other => panic!("expected a mesh error, got {other:?}"),
    }
}

const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n";

#[test]
fn each_malformed_file_names_the_face_and_its_line() {
    // A vertex index past the file's vertices (checked once all are read).
    let (line, message) = syntax_error(&format!("{SQUARE}f 1 2 3 4\nf 2 5 9 3\n"));
    assert_eq!(line, 8);
    assert!(message.contains("face 2 uses vertex 9"), "{message}");
    // A relative index before the first vertex, and index 0.
    let (line, message) = syntax_error(&format!("{SQUARE}f 1 2 3\nf -7 -1 -2\n"));
    assert_eq!((line, message.contains("face 2")), (8, true), "{message}");
    let (line, message) = syntax_error(&format!("{SQUARE}f 0 1 2\n"));
    assert_eq!((line, message.contains("face 1")), (7, true), "{message}");
    // A texture coordinate index past the file's.
    let (line, message) = syntax_error(&format!("{SQUARE}vt 0 0\nf 1/1 2/2 3/1\n"));
    assert_eq!(line, 8);
    assert!(message.contains("texture coordinate 2"), "{message}");
    // NaN, and a word that is not a number.
    let (line, message) = syntax_error("v 0 0 0\nv nan 0 0\nv 1 1 0\nf 1 2 3\n");
    assert_eq!(line, 2);
    assert!(message.contains("not finite"), "{message}");
    let (line, _) = syntax_error("v 0 0 0\nv 1 0 0\nv 1 x 0\nf 1 2 3\n");
    assert_eq!(line, 3);
    // Polylines and points are not surfaces.
    let (line, message) = syntax_error(&format!("{SQUARE}f 1 2 3\nl 1 2\n"));
    assert_eq!(line, 8);
    assert!(message.contains("polylines"), "{message}");
    // A face listed twice (in another rotation).
    let (line, error, message) = mesh_error(&format!("{SQUARE}f 1 2 3 4\nf 3 4 1 2\n"));
    assert_eq!(line, Some(8));
    assert_eq!(error, MeshError::DuplicateFace { face: 2, first: 1 });
    assert!(
        message.starts_with("m.obj:8: face 2 repeats face 1"),
        "{message}"
    );
    // A third face on an edge; numbers in the file's terms (the edge
    // 2-3, the face's line).
    let (line, error, _) = mesh_error(&format!("{SQUARE}v 1 0 1\nf 1 2 3 4\nf 3 2 5 6\nf 2 3 7\n"));
    assert_eq!(line, Some(10));
    assert!(
        matches!(error, MeshError::NonManifoldEdge { face: 3, from, to } if [from, to] == [2, 3]),
        "{error:?}"
    );
    // Fewer than 3 vertices, and a vertex twice.
    let (line, error, _) = mesh_error(&format!("{SQUARE}f 1 2 3\nf 4 5\n"));
    assert_eq!(line, Some(8));
    assert_eq!(error, MeshError::FaceTooSmall { face: 2, size: 2 });
    let (line, error, _) = mesh_error(&format!("{SQUARE}f 1 2 3\nf 4 6 4\n"));
    assert_eq!(line, Some(8));
    assert_eq!(error, MeshError::RepeatedVertex { face: 2, vertex: 4 });
    // Windings that disagree.
    let (line, error, _) = mesh_error(&format!("{SQUARE}f 1 2 3 4\nf 2 3 6 5\n"));
    assert_eq!(line, Some(8));
    assert!(
        matches!(
            error,
            MeshError::InconsistentWinding {
                face: 2,
                first: 1,
                from: 2,
                to: 3
            }
        ),
        "{error:?}"
    );
}

#[test]
fn an_obj_file_is_loaded_by_extension_within_the_patch_budget() {
    let dir = temp_dir("load");
    let path = dir.join("Quad.OBJ");
    std::fs::write(&path, format!("{SQUARE}f 1 2 3 4\nf 2 5 6 3\n")).unwrap();
    let limit = reyes::InputKind::Model.limit();
    let model =
        Model::load_subdivided_within(&path, limit, &mut PatchBudget::new(2), Scheme::Bilinear)
            .unwrap();
    assert_eq!(model.patches.len(), 2);
    let mut budget = PatchBudget::new(1);
    match Model::load_subdivided_within(&path, limit, &mut budget, Scheme::Bilinear) {
        Err(e @ LoadError::PatchBudgetOf { .. }) => {
            assert!(e.to_string().contains("Quad.OBJ"), "{e}");
        }
        other => panic!("expected the budget error, got {other:?}"),
    }
    assert_eq!(budget.used(), 0, "nothing taken by a refused file");
    // The default scheme is Catmull-Clark: the quad's corners are sharp
    // (an OBJ's boundary is interpolated), so it is refined around them.
    let model = Model::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(model.patches.len() >= 2, "{} patches", model.patches.len());
    // A malformed file read by path names the path.
    std::fs::write(&path, format!("{SQUARE}f 1 2 3 4\nf 1 2 3 4\n")).unwrap();
    let e = Model::load(&path).unwrap_err();
    assert!(
        e.to_string().contains("Quad.OBJ:8: face 2 repeats face 1"),
        "{e}"
    );
}

/// The cube `[-1, 1]^3` as an OBJ text, faces wound outwards.
const CUBE_OBJ: &str = "\
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
";

/// The cube's faces as bilinear Bezier patches, each control point the
/// blend of its face's corners at `(i/3, j/3)`, written out here.
fn cube_patches() -> Model {
    let corners: Vec<Vec3> = CUBE_OBJ
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let c: Vec<f32> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            Vec3::new(c[0], c[1], c[2])
        })
        .collect();
    let faces = CUBE_OBJ.lines().filter_map(|l| l.strip_prefix("f "));
    let patches = faces
        .map(|f| {
            let q: Vec<Vec3> = f
                .split(' ')
                .map(|i| corners[i.parse::<usize>().unwrap() - 1])
                .collect();
            let mut points = [Vec3::ZERO; 16];
            for j in 0..4 {
                for i in 0..4 {
                    let (u, v) = (i as f32 / 3.0, j as f32 / 3.0);
                    points[j * 4 + i] = q[0] * ((1.0 - u) * (1.0 - v))
                        + q[1] * (u * (1.0 - v))
                        + q[2] * (u * v)
                        + q[3] * ((1.0 - u) * v);
                }
            }
            Patch { points }
        })
        .collect();
    Model::new(patches)
}

/// A scene of one object, `model`, with `extra` keys, seen from a corner.
fn cube_scene(model: &str, extra: &str) -> String {
    format!(
        "resolution = {{ width = 48, height = 40 }}\nspp = 4\n\
         [camera]\neye = [3.0, 2.5, 4.0]\ntarget = [0.0, 0.0, 0.0]\n\
         [[objects]]\nmodel = \"{model}\"\n{extra}\n"
    )
}

#[test]
fn an_obj_cube_subdivided_bilinearly_renders_as_the_cube_of_patches() {
    let dir = temp_dir("cube");
    std::fs::write(dir.join("cube.obj"), CUBE_OBJ).unwrap();
    std::fs::write(
        dir.join("cube.bpt"),
        reyes::load::bpt::write(&cube_patches()),
    )
    .unwrap();
    let render = |scene: &str| {
        let path = dir.join("scene.toml");
        std::fs::write(&path, scene).unwrap();
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        reference::render(&PreparedScene::load(&scene).unwrap_or_else(|e| panic!("{e}")))
    };
    let from_obj = render(&cube_scene("cube.obj", "subdivision = \"bilinear\""));
    let from_patches = render(&cube_scene("cube.bpt", ""));
    let covered = from_obj.coverage.iter().filter(|&&c| c).count();
    assert!(covered > 200, "the cube covers {covered} pixels");
    assert_eq!(from_obj.coverage, from_patches.coverage);
    assert!(from_obj.image == from_patches.image, "the images differ");
}

#[test]
fn subdivision_is_a_key_of_obj_objects_only() {
    let scene = Scene::from_toml_str(&cube_scene("a.obj", "subdivision = \"bilinear\"")).unwrap();
    assert_eq!(
        scene.objects[0].subdivision.map(|s| s.scheme()),
        Some(Scheme::Bilinear)
    );
    let scene =
        Scene::from_toml_str(&cube_scene("a.OBJ", "subdivision = \"catmull-clark\"")).unwrap();
    assert_eq!(
        scene.objects[0].subdivision.map(|s| s.scheme()),
        Some(Scheme::CatmullClark)
    );
    let round_trip = Scene::from_toml_str(&scene.to_toml_string()).unwrap();
    assert_eq!(
        round_trip.objects[0].subdivision,
        scene.objects[0].subdivision
    );
    match Scene::from_toml_str(&cube_scene("a.bpt", "subdivision = \"bilinear\"")) {
        Err(SceneError::InvalidValue { field, reason }) => {
            assert_eq!(field, "objects[0].subdivision");
            assert!(reason.contains(".obj"), "{reason}");
        }
        other => panic!("expected the key refused, got {other:?}"),
    }
    match Scene::from_toml_str(&cube_scene("a.obj", "subdivision = \"loop\"")) {
        Err(SceneError::Parse { line, .. }) => assert_eq!(line, Some(8)),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn a_scene_loads_its_obj_models_with_their_scheme() {
    let dir = temp_dir("scheme");
    std::fs::write(dir.join("cube.obj"), CUBE_OBJ).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, cube_scene("cube.obj", "subdivision = \"bilinear\"")).unwrap();
    let models = Scene::load(&path).unwrap().load_models().unwrap();
    assert_eq!(models[0].patches.len(), 6);
    std::fs::write(&path, cube_scene("cube.obj", "")).unwrap();
    // Catmull-Clark by default: the cube's limit surface, refined around
    // its eight valence-3 corners.
    let models = Scene::load(&path).unwrap().load_models().unwrap();
    assert!(models[0].patches.len() > 6, "{}", models[0].patches.len());
}

#[test]
fn reyes_render_reads_obj_scenes_and_models() {
    let dir = temp_dir("cli");
    std::fs::write(dir.join("cube.obj"), CUBE_OBJ).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, cube_scene("cube.obj", "subdivision = \"bilinear\"")).unwrap();
    let render = |input: &Path, out: &Path| {
        std::process::Command::new(env!("CARGO_BIN_EXE_reyes"))
            .arg("render")
            .arg(input)
            .args(["--cpu", "--width", "32", "--height", "24", "-o"])
            .arg(out)
            .output()
            .expect("reyes starts")
    };
    let out = dir.join("scene.png");
    let output = render(&scene, &out);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(out.is_file());
    // A bare .obj model takes the default scheme, Catmull-Clark.
    let out = dir.join("model.png");
    let output = render(&dir.join("cube.obj"), &out);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(out.is_file());
}
