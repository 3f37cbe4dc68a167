//! RIB `ObjectBegin` / `ObjectEnd` / `ObjectInstance`: instances render as
//! the same geometry written out in place, take the attributes in force at
//! the instance, share one stored copy of their patches, convert to one
//! model file, and bad requests are errors with their line.

use std::path::PathBuf;

use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::rib::RibScene;
use reyes::scene::Scene;

/// A fresh, empty directory under the system's temporary directory.
fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "reyes-rib-instances-test-{}-{test}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A bicubic patch (a bump) and a quarter of a sphere, with a transform of
/// their own inside the definition's block.
const GEOMETRY: &str = "AttributeBegin\n\
     Translate 0 0.25 0\n\
     Patch \"bicubic\" \"P\" [-1 -1 0  -0.3 -1 0.2  0.3 -1 -0.2  1 -1 0\n\
       -1 -0.3 0.1  -0.3 -0.3 0.9  0.3 -0.3 0.6  1 -0.3 0\n\
       -1 0.3 0  -0.3 0.3 0.7  0.3 0.3 0.8  1 0.3 0.1\n\
       -1 1 0  -0.3 1 -0.1  0.3 1 0.1  1 1 0]\n\
     AttributeEnd\n\
     Sphere 0.5 -0.5 0.5 270\n";

/// The placements and colours of the three instances.
const PLACEMENTS: [(&str, &str); 3] = [
    (
        "Translate -1.6 0 0\nRotate 30 0 1 0\nScale 0.8 0.8 0.8",
        "Color [0.9 0.3 0.2]",
    ),
    (
        "Translate 0 0.3 0.5\nRotate -40 1 0 0",
        "Color [0.2 0.8 0.3]",
    ),
    (
        "Translate 1.6 -0.2 0\nRotate 70 0 0 1\nScale 1 -1 1",
        "Color [0.3 0.4 0.9]",
    ),
];

/// A frame around `world`.
fn framed(world: &str) -> String {
    format!(
        "Format 160 120 1\nPixelSamples 2 2\nProjection \"perspective\" \"fov\" [45]\n\
         Translate 0 0 6\nWorldBegin\n\
         LightSource \"distantlight\" 1 \"from\" [1 2 -2] \"to\" [0 0 0]\n\
         Surface \"plastic\"\nSides 1\n{world}WorldEnd\n"
    )
}

/// The three instances of one definition.
fn instanced() -> String {
    let mut world = format!("ObjectBegin \"bumpy\"\n{GEOMETRY}ObjectEnd\n");
    for (placement, color) in PLACEMENTS {
        world += &format!(
            "AttributeBegin\n{color}\n{placement}\nObjectInstance \"bumpy\"\nAttributeEnd\n"
        );
    }
    framed(&world)
}

/// The same geometry written out in place three times.
fn in_place() -> String {
    let mut world = String::new();
    for (placement, color) in PLACEMENTS {
        world += &format!("AttributeBegin\n{color}\n{placement}\n{GEOMETRY}AttributeEnd\n");
    }
    framed(&world)
}

fn prepared(text: &str) -> PreparedScene {
    RibScene::from_text(text, "instances.rib")
        .unwrap_or_else(|e| panic!("{e}"))
        .prepare()
        .unwrap()
}

#[test]
fn instances_render_as_the_geometry_written_in_place() {
    let instanced = prepared(&instanced());
    let in_place = prepared(&in_place());
    // The quadric inside the definition is tessellated without knowing
    // where its instances go: finer than in place, the same surface.
    assert_eq!(instanced.objects.len(), 3);
    assert!(instanced.objects.iter().all(|o| o.placement.is_some()));
    assert!(in_place.objects.iter().all(|o| o.placement.is_none()));
    // One stored copy for the three instances.
    let per_instance = instanced.patches.len() / 3;
    assert_eq!(instanced.store.shared.len(), per_instance);
    assert_eq!(instanced.store.len as usize, per_instance);
    // The bicubic patch of each instance is the in-place one.
    let bumps = |scene: &PreparedScene| -> Vec<[glam::Vec3; 16]> {
        let mut seen = Vec::new();
        let mut object = u32::MAX;
        for patch in &scene.patches {
            if patch.object != object {
                object = patch.object;
                seen.push(patch.points);
            }
        }
        seen
    };
    let (a, b) = (bumps(&instanced), bumps(&in_place));
    assert_eq!(a.len(), 3);
    for (p, q) in a.iter().flatten().zip(b.iter().flatten()) {
        assert!(p.abs_diff_eq(*q, 1e-5), "{p} against {q}");
    }
    let (a, b) = (reference::render(&instanced), reference::render(&in_place));
    let covered = a.coverage.iter().filter(|&&c| c).count();
    assert!(covered > 2000, "the instances cover {covered} pixels");
    let differing = a
        .coverage
        .iter()
        .zip(&b.coverage)
        .filter(|(x, y)| x != y)
        .count();
    assert!(
        differing <= covered / 100,
        "{differing} of {covered} pixels differ in coverage"
    );
    // Colours: each instance takes its own; the shading agrees where both
    // cover a pixel fully (the sphere's tessellations differ a little).
    let mut far = 0;
    for (i, (p, q)) in a.image.pixels().zip(b.image.pixels()).enumerate() {
        if a.covered_samples[i] == 4 && b.covered_samples[i] == 4 {
            let d =
                p.0.iter()
                    .zip(q.0)
                    .map(|(x, y)| x.abs_diff(y))
                    .max()
                    .unwrap();
            if d > 8 {
                far += 1;
            }
        }
    }
    assert!(
        far <= covered / 100,
        "{far} pixels differ by more than 8/255"
    );
}

#[test]
fn an_instance_takes_the_attributes_in_force_where_it_is_placed() {
    let text = framed(
        "ObjectBegin 7\nColor [0 0 1]\nSphere 1 -1 1 360\nObjectEnd\n\
         AttributeBegin\nColor [1 0 0]\nObjectInstance 7\nAttributeEnd\n",
    );
    let scene = prepared(&text);
    assert_eq!(scene.objects.len(), 1);
    assert_eq!(scene.objects[0].color, glam::Vec3::new(1.0, 0.0, 0.0));
}

#[test]
fn a_moving_instance_is_placed_in_world_space_and_moves() {
    let text = format!(
        "Shutter 0 1\n{}",
        framed(
            "ObjectBegin \"ball\"\nSphere 1 -1 1 360\nObjectEnd\n\
             AttributeBegin\nMotionBegin [0 1]\nTranslate 0 0 0\nTranslate 1 0 0\nMotionEnd\n\
             ObjectInstance \"ball\"\nAttributeEnd\n",
        )
    );
    let scene = prepared(&text);
    assert!(scene.objects[0].placement.is_none());
    assert!(scene.objects[0].motion.is_some());
}

#[test]
fn bad_instancing_requests_are_errors_with_their_line() {
    let cases = [
        (
            "ObjectInstance \"nothing\"\n",
            "no object \"nothing\" (no object is defined)",
        ),
        (
            "ObjectBegin 1\nObjectBegin 2\nObjectEnd\nObjectEnd\n",
            "definitions do not nest",
        ),
        (
            "ObjectBegin 1\nSphere 1 -1 1 360\nObjectEnd\nObjectInstance 2\n",
            "no object \"2\" (defined: \"1\")",
        ),
        ("ObjectBegin\nObjectEnd\n", "needs the object's name"),
    ];
    for (world, expected) in cases {
        let text = framed(world);
        let error = RibScene::from_text(&text, "bad.rib")
            .unwrap_err()
            .to_string();
        assert!(error.contains(expected), "{world:?}: {error}");
        // The world starts on line 7 of the frame.
        assert!(error.contains("bad.rib:"), "{error}");
    }
}

#[test]
fn convert_writes_one_model_for_the_instances_and_renders_the_same() {
    let dir = temp_dir("convert");
    let rib = RibScene::from_text(&instanced(), dir.join("instances.rib")).unwrap();
    let before = rib.prepare().unwrap();
    let toml = dir.join("instances.toml");
    let written = rib.write(&toml).unwrap();
    let models: Vec<_> = written
        .iter()
        .filter(|p| p.extension().unwrap() == "bpt")
        .collect();
    assert_eq!(models.len(), 1, "{written:?}");
    let text = std::fs::read_to_string(&toml).unwrap();
    assert!(text.contains("matrix"), "{text}");
    let after = PreparedScene::load(&Scene::load(&toml).unwrap()).unwrap();
    assert_eq!(after.store, before.store);
    assert_eq!(after.patches, before.patches);
    assert_eq!(
        reference::render(&after).image,
        reference::render(&before).image
    );
}

/// `reyes render --stats` shows the patches the GPU stores: the 32 of the
/// teapot for three objects that name it.
#[test]
fn the_statistics_show_the_stored_patches() {
    let dir = temp_dir("stats");
    let scene = dir.join("teapots.toml");
    std::fs::write(
        &scene,
        "[[objects]]\nmodel = \"teapot\"\n\
         [[objects]]\nmodel = \"teapot\"\ntransform = { translate = [4, 0, 0] }\n\
         [[objects]]\nmodel = \"teapot\"\ntransform = { translate = [8, 0, 0] }\n",
    )
    .unwrap();
    let out = dir.join("teapots.png");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_reyes"))
        .args(["render", scene.to_str().unwrap(), "--cpu", "--stats"])
        .args(["--width", "64", "--height", "48", "--spp", "1"])
        .args(["-o", out.to_str().unwrap()])
        .output()
        .expect("reyes starts");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let table = String::from_utf8_lossy(&output.stdout);
    let row = table
        .lines()
        .find(|l| l.starts_with("patches stored"))
        .unwrap_or_else(|| panic!("no `patches stored` in {table}"));
    assert!(row.ends_with("32 (7 KiB)"), "{row}");
    let input = table
        .lines()
        .find(|l| l.starts_with("input patches"))
        .and_then(|l| l.split_whitespace().last());
    assert_eq!(input, Some("96"), "{table}");
}

/// A definition may come before `WorldBegin` (its geometry keeps its own
/// space); the transform in force at `ObjectBegin` does not apply to it.
#[test]
fn a_definition_may_come_before_the_world() {
    let text = "Format 64 48 1\nTranslate 5 5 5\nObjectBegin \"ball\"\nSphere 1 -1 1 360\nObjectEnd\n\
                Identity\nProjection \"perspective\" \"fov\" [45]\nTranslate 0 0 6\nWorldBegin\n\
                ObjectInstance \"ball\"\nTranslate 2 0 0\nObjectInstance \"ball\"\nWorldEnd\n";
    let scene = prepared(text);
    assert_eq!(scene.objects.len(), 2);
    assert_eq!(scene.store.len as usize * 2, scene.patches.len());
    // The first ball is centred on the view axis, 6 in front of the eye.
    let first: Vec<_> = scene.patches.iter().filter(|p| p.object == 0).collect();
    let centre =
        first.iter().flat_map(|p| p.points).sum::<glam::Vec3>() / (16 * first.len()) as f32;
    assert!(centre.x.abs() < 1e-3 && centre.y.abs() < 1e-3, "{centre}");
    // A definition's geometry before it, outside any definition, is still
    // an error.
    let error = RibScene::from_text("Sphere 1 -1 1 360\nWorldBegin\nWorldEnd\n", "early.rib")
        .unwrap_err()
        .to_string();
    assert!(error.contains("geometry before WorldBegin"), "{error}");
}
