//! RIB `SubdivisionMesh`: every tag read into the expected mesh, the
//! errors (with their line), skipped tags (warned with their line), a
//! bilinear mesh rendered as the same faces given as `PointsPolygons`,
//! and `reyes convert`'s patches.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::rib::subdivision::{self, SubdivisionMesh};
use reyes::rib::{RibError, RibScene};
use reyes::scene::Scene;
use reyes::subdiv::{BoundaryInterpolation, Corner, Crease, Mesh, Scheme};

/// A fresh, empty directory under the system's temporary directory.
fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "reyes-rib-subdivision-test-{}-{test}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The request `SubdivisionMesh` of `text` (one request), read.
fn read(text: &str) -> Result<SubdivisionMesh, String> {
    let calls = reyes::rib::parser::parse(text, Path::new("m.rib")).unwrap();
    assert_eq!(calls.len(), 1);
    assert_eq!(calls[0].name, "SubdivisionMesh");
    subdivision::parse(&calls[0].values, &HashMap::new())
}

/// Six points on a 3 x 2 grid and the two quads between them.
const GRID: &str = "[4 4] [0 1 4 3  1 2 5 4]";
const GRID_P: &str = "\"P\" [0 0 0  1 0 0  2 0 0  0 1 0  1 1 0  2 1 0]";

fn grid_positions() -> Vec<Vec3> {
    [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1)]
        .map(|(x, y)| Vec3::new(x as f32, y as f32, 0.0))
        .to_vec()
}

#[test]
fn every_tag_is_read_into_the_mesh() {
    let text = format!(
        "SubdivisionMesh \"catmull-clark\" {GRID}\n\
         [\"crease\" \"corner\" \"hole\" \"interpolateboundary\" \"stitch\"]\n\
         [3 1  2 2  1 0  1 0  2 1]\n\
         [3 4 5  0 2  1  2  7 8]\n\
         [2.5  10 3  1.5]\n\
         {GRID_P}\n\
         \"facevarying float[2] st\" [0 0 1 0 1 1 0 1  0 0 2 0 2 2 0 2]\n"
    );
    let read = read(&text).unwrap();
    let expected = Mesh {
        scheme: Scheme::CatmullClark,
        positions: grid_positions(),
        face_sizes: vec![4, 4],
        face_vertices: vec![0, 1, 4, 3, 1, 2, 5, 4],
        creases: vec![Crease {
            vertices: vec![3, 4, 5],
            sharpness: 2.5,
        }],
        corners: vec![
            Corner {
                vertex: 0,
                sharpness: 10.0,
            },
            Corner {
                vertex: 2,
                sharpness: 3.0,
            },
        ],
        holes: vec![1],
        boundary: BoundaryInterpolation::EdgeOnly,
        st: Some(
            [
                0., 0., 1., 0., 1., 1., 0., 1., 0., 0., 2., 0., 2., 2., 0., 2.,
            ]
            .chunks(2)
            .map(|c| Vec2::new(c[0], c[1]))
            .collect(),
        ),
    };
    assert_eq!(read.mesh, expected);
    assert_eq!(read.skipped_tags, vec!["stitch".to_owned()]);
    assert_eq!(read.mesh.validate(), Ok(()));
}

#[test]
fn interpolateboundary_and_corner_forms_and_vertex_st() {
    let boundary = |args: &str| {
        read(&format!(
            "SubdivisionMesh \"bilinear\" {GRID} [\"interpolateboundary\"] {args} [] {GRID_P}"
        ))
        .map(|m| m.mesh.boundary)
    };
    // RenderMan: no integer means 1; 1 edges and corners, 2 edges only.
    assert_eq!(
        boundary("[0 0] []"),
        Ok(BoundaryInterpolation::EdgeAndCorner)
    );
    assert_eq!(
        boundary("[1 0] [1]"),
        Ok(BoundaryInterpolation::EdgeAndCorner)
    );
    assert_eq!(boundary("[1 0] [2]"), Ok(BoundaryInterpolation::EdgeOnly));
    assert_eq!(boundary("[1 0] [0]"), Ok(BoundaryInterpolation::None));
    assert!(boundary("[1 0] [3]").unwrap_err().contains("not 0, 1 or 2"));
    // Without the tag: none.
    let plain = read(&format!(
        "SubdivisionMesh \"bilinear\" {GRID} [] [] [] [] {GRID_P}"
    ))
    .unwrap();
    assert_eq!(plain.mesh.boundary, BoundaryInterpolation::None);
    assert_eq!(plain.mesh.scheme, Scheme::Bilinear);
    assert_eq!(plain.mesh.st, None);
    // One sharpness for every corner.
    let corners = read(&format!(
        "SubdivisionMesh \"bilinear\" {GRID} [\"corner\"] [3 1] [0 2 5] [4] {GRID_P}"
    ))
    .unwrap();
    assert_eq!(
        corners.mesh.corners,
        [0, 2, 5].map(|vertex| Corner {
            vertex,
            sharpness: 4.0
        })
    );
    // A vertex "st" is taken at each face corner; "s" and "t" alike.
    let vertex_st = read(&format!(
        "SubdivisionMesh \"bilinear\" {GRID} [] [] [] [] {GRID_P} \
         \"vertex float[2] st\" [0 0  1 0  2 0  0 1  1 1  2 1]"
    ))
    .unwrap();
    let by_id: Vec<Vec2> = [0, 1, 4, 3, 1, 2, 5, 4]
        .map(|i: usize| grid_positions()[i].truncate())
        .to_vec();
    assert_eq!(vertex_st.mesh.st, Some(by_id.clone()));
    let s_and_t = read(&format!(
        "SubdivisionMesh \"bilinear\" {GRID} [] [] [] [] {GRID_P} \
         \"s\" [0 1 2 0 1 2] \"t\" [0 0 0 1 1 1]"
    ))
    .unwrap();
    assert_eq!(s_and_t.mesh.st, Some(by_id));
    let s_only = read(&format!(
        "SubdivisionMesh \"bilinear\" {GRID} [] [] [] [] {GRID_P} \"s\" [0 1 2 0 1 2]"
    ));
    assert!(s_only.unwrap_err().contains("both"), "s without t");
}

/// The error of `body` in a world block, which starts at line 3.
fn error(body: &str) -> (usize, String) {
    let text = format!("Projection \"perspective\"\nWorldBegin\n{body}\nWorldEnd\n");
    match RibScene::from_text(&text, "mesh.rib") {
        Err(RibError::Syntax {
            file,
            line,
            message,
            ..
        }) => {
            assert_eq!(file, Path::new("mesh.rib"));
            (line, message)
        }
        Err(other) => panic!("expected a syntax error, got {other}"),
        Ok(_) => panic!("expected an error for {body}"),
    }
}

#[test]
fn errors_name_the_line_and_what_is_wrong() {
    let cases: [(&str, &str); 11] = [
        // Counts that disagree.
        (
            "SubdivisionMesh \"bilinear\" [4 4] [0 1 4 3 1 2 5] [] [] [] [] {P}",
            "add up to 8, but there are 7 vertids",
        ),
        // A vertex id past the points, a repeated face, a third face on an edge.
        (
            "SubdivisionMesh \"bilinear\" [4 4] [0 1 4 3 1 2 9 4] [] [] [] [] {P}",
            "face 1 uses vertex 9, but the mesh has 6 vertices",
        ),
        (
            "SubdivisionMesh \"bilinear\" [4 4] [0 1 4 3 1 4 3 0] [] [] [] [] {P}",
            "face 1 repeats face 0",
        ),
        (
            "SubdivisionMesh \"bilinear\" [4 4 3] [0 1 4 3 1 2 5 4 1 4 2] [] [] [] [] {P}",
            "non-manifold",
        ),
        // Tags with the wrong argument counts, or values.
        (
            "SubdivisionMesh \"bilinear\" {G} [\"crease\"] [2 2] [0 1] [1 1] {P}",
            "takes [n 1] arguments, found [2 2]",
        ),
        (
            "SubdivisionMesh \"bilinear\" {G} [\"hole\"] [1 1] [0] [1] {P}",
            "takes [n 0] arguments",
        ),
        (
            "SubdivisionMesh \"bilinear\" {G} [\"crease\"] [2 1] [0 1] [] {P}",
            "ask for 2 intargs and 1 floatargs",
        ),
        (
            "SubdivisionMesh \"bilinear\" {G} [\"hole\"] [1 0 0] [7] [] {P}",
            "1 tags need 2 nargs",
        ),
        (
            "SubdivisionMesh \"bilinear\" {G} [\"hole\"] [1 0] [7] [] {P}",
            "hole 7 names a face that does not exist",
        ),
        // A point beyond f32, and a scheme not built.
        (
            "SubdivisionMesh \"bilinear\" {G} [] [] [] [] \"P\" [0 0 0 1 0 0 2 0 0 0 1 0 1e39 1 0 2 1 0]",
            "point 4",
        ),
        (
            "SubdivisionMesh \"loop\" {G} [] [] [] [] {P}",
            "scheme \"loop\" is not supported",
        ),
    ];
    for (body, expected) in cases {
        let body = body.replace("{P}", GRID_P).replace("{G}", GRID);
        // The request on the second line of the world block.
        let (line, message) = error(&format!("Color [1 0 0]\n{body}"));
        assert_eq!(line, 4, "{message}");
        assert!(
            message.starts_with("SubdivisionMesh: ") && message.contains(expected),
            "{body}: {message}"
        );
    }
}

#[test]
fn an_unknown_tag_is_warned_with_its_line_and_skipped() {
    let text = format!(
        "Projection \"perspective\"\nWorldBegin\nTranslate 0 0 5\n\
         SubdivisionMesh \"bilinear\" {GRID} [\"stitch\" \"hole\"] [2 1 1 0] [0 1 1] [1] {GRID_P}\nWorldEnd\n"
    );
    let rib = RibScene::from_text(&text, "mesh.rib").unwrap();
    let warning = rib
        .warnings
        .iter()
        .find(|w| w.message.contains("stitch"))
        .expect("a warning about the tag");
    assert_eq!(warning.line, 4);
    // The hole after it is read: one face left, one patch.
    assert_eq!(rib.models.iter().map(|m| m.patches.len()).sum::<usize>(), 1);
}

#[test]
fn a_catmull_clark_mesh_becomes_its_limit_surface_s_patches() {
    let text = format!(
        "Projection \"perspective\"\nWorldBegin\nTranslate 0 0 5\n\
         SubdivisionMesh \"catmull-clark\" {GRID} [\"interpolateboundary\"] [0 0] [] [] {GRID_P}\nWorldEnd\n"
    );
    let rib = RibScene::from_text(&text, "mesh.rib").unwrap();
    let patches: usize = rib.models.iter().map(|m| m.patches.len()).sum();
    assert!(rib.warnings.is_empty(), "{:?}", rib.warnings);
    assert!(patches >= 2, "{patches} patches");
}

/// A wavy 4 x 3 grid of quads (20 points), as `nverts vertids` and `"P"`.
fn wavy_grid() -> (String, String) {
    let (nx, ny) = (5, 4);
    let mut points = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (i as f64 * 0.5 - 1.0, j as f64 * 0.5 - 0.75);
            points.push(format!("{x} {y} {}", 0.3 * (x * 2.0).sin() * y));
        }
    }
    let mut ids = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let at = |i: usize, j: usize| (j * nx + i).to_string();
            ids.extend([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    let faces = (nx - 1) * (ny - 1);
    (
        format!("[{}] [{}]", vec!["4"; faces].join(" "), ids.join(" ")),
        format!("\"P\" [{}]", points.join("  ")),
    )
}

/// A frame around `geometry`: a moving transform, a one-sided reversed
/// surface with texture coordinates shown by a checker.
fn framed(geometry: &str) -> String {
    format!(
        "Format 64 48 1\nPixelSamples 2 2\nShutter 0 1\nProjection \"perspective\" \"fov\" 45\n\
         WorldBegin\nLightSource \"distantlight\" 1 \"from\" [1 1 -2] \"to\" [0 0 0]\n\
         Translate 0 0 4\nMotionBegin [0 1]\nRotate 20 1 0 0\nRotate 30 1 1 0\nMotionEnd\n\
         AttributeBegin\nSides 1\nReverseOrientation\nColor [0.9 0.5 0.2]\n\
         Surface \"plastic\"\n{geometry}\nAttributeEnd\nWorldEnd\n"
    )
}

#[test]
fn a_bilinear_mesh_renders_as_the_same_faces_given_as_points_polygons() {
    let (faces, points) = wavy_grid();
    let st = "\"vertex float[2] st\" [0 0 1 0 2 0 3 0 4 0  0 1 1 1 2 1 3 1 4 1  0 2 1 2 2 2 3 2 4 2  0 3 1 3 2 3 3 3 4 3]";
    let mesh = framed(&format!(
        "SubdivisionMesh \"bilinear\" {faces} [] [] [] [] {points} {st}"
    ));
    let polygons = framed(&format!("PointsPolygons {faces} {points} {st}"));
    let render = |text: &str| {
        let rib = RibScene::from_text(text, "grid.rib").unwrap_or_else(|e| panic!("{e}"));
        let prepared = rib.prepare().unwrap();
        (prepared.patches.clone(), reference::render(&prepared))
    };
    let (mesh_patches, mesh_image) = render(&mesh);
    let (polygon_patches, polygon_image) = render(&polygons);
    assert_eq!(mesh_patches.len(), 12);
    for (a, b) in mesh_patches.iter().zip(&polygon_patches) {
        assert_eq!(a.st, b.st);
        for (p, q) in a.points.iter().zip(&b.points) {
            assert!(p.abs_diff_eq(*q, 1e-5), "{p} against {q}");
        }
    }
    let covered = mesh_image.coverage.iter().filter(|&&c| c).count();
    assert!(covered > 300, "the grid covers {covered} pixels");
    assert_eq!(mesh_image.coverage, polygon_image.coverage);
    assert!(mesh_image.image == polygon_image.image, "the images differ");
}

#[test]
fn convert_writes_a_mesh_as_its_patches() {
    let dir = temp_dir("convert");
    let (faces, points) = wavy_grid();
    let text = framed(&format!(
        "SubdivisionMesh \"bilinear\" {faces} [] [] [] [] {points}"
    ));
    let rib = RibScene::from_text(&text, dir.join("grid.rib")).unwrap();
    let before = rib.prepare().unwrap().patches;
    let toml = dir.join("grid.toml");
    let written = rib.write(&toml).unwrap();
    assert!(written.iter().any(|p| p.extension().unwrap() == "bpt"));
    let after = PreparedScene::load(&Scene::load(&toml).unwrap())
        .unwrap()
        .patches;
    assert_eq!(after.len(), before.len());
    for (a, b) in after.iter().zip(&before) {
        assert_eq!(a.points, b.points);
    }
}

#[test]
fn a_mesh_takes_its_patches_from_the_budget_before_they_are_made() {
    let dir = temp_dir("budget");
    let (faces, points) = wavy_grid();
    let rib = dir.join("grid.rib");
    // The request on line 17 of the frame (see `framed`).
    std::fs::write(
        &rib,
        framed(&format!(
            "SubdivisionMesh \"bilinear\" {faces} [] [] [] [] {points}"
        )),
    )
    .unwrap();
    let render = |max_patches: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_reyes"))
            .arg("render")
            .arg(&rib)
            .args(["--cpu", "--max-patches", max_patches, "-o"])
            .arg(dir.join("grid.png"))
            .output()
            .expect("reyes starts")
    };
    let refused = render("11");
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success());
    assert!(
        stderr.contains("grid.rib:17:1: SubdivisionMesh: its faces' patches: 12 patches"),
        "{stderr}"
    );
    let accepted = render("12");
    assert!(
        accepted.status.success(),
        "{}",
        String::from_utf8_lossy(&accepted.stderr)
    );
}

#[test]
fn an_obj_file_and_a_subdivision_mesh_of_the_same_faces_are_the_same_mesh() {
    // Faces that first use the vertices in file order, so that the OBJ
    // mesh keeps the file's vertex numbers (minus one).
    let obj_text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nv 1 2 0\n\
                    f 1 2 3 4\nf 2 5 6 3\nf 4 3 7\n";
    for (scheme, name) in [
        (Scheme::Bilinear, "bilinear"),
        (Scheme::CatmullClark, "catmull-clark"),
    ] {
        let from_obj = reyes::load::obj::parse_mesh(obj_text, Path::new("m.obj"), scheme)
            .unwrap()
            .mesh;
        let from_rib = read(&format!(
            "SubdivisionMesh \"{name}\" [4 4 3] [0 1 2 3  1 4 5 2  3 2 6] \
             [\"interpolateboundary\"] [0 0] [] [] \
             \"P\" [0 0 0  1 0 0  1 1 0  0 1 0  2 0 0  2 1 0  1 2 0]"
        ))
        .unwrap()
        .mesh;
        assert_eq!(from_obj, from_rib);
        // The same mesh, so the same patches, bit for bit.
        let patches = from_obj.to_patches().unwrap();
        assert_eq!(patches, from_rib.to_patches().unwrap());
        assert!(!patches.model.patches.is_empty());
        if scheme == Scheme::Bilinear {
            assert_eq!(
                from_obj.to_patches().unwrap().model.patches.len(),
                1 + 1 + 3
            );
        }
    }
}
