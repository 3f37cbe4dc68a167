//! Nothing wrong in a RIB passes as success (issue 42, items 3 and 5): an
//! unbalanced or truncated block structure is an error naming the file, the
//! line of the unclosed request and what is missing (a warning under
//! `RibOptions::lenient`, which uses what was read); out-of-range values
//! are errors naming the request and the valid range; a scene without
//! geometry warns; overflows name the transform that overflows and the
//! request from which on it does.

use reyes::rib::{RibError, RibOptions, RibScene};

/// A sphere in front of the camera, inside the world block.
const SPHERE: &str = "Translate 0 0 5\nSphere 1 -1 1 360\n";

fn strict(text: &str) -> Result<RibScene, RibError> {
    RibScene::from_text(text, "t.rib")
}

fn lenient(text: &str) -> RibScene {
    RibScene::from_text_with(text, "t.rib", RibOptions { lenient: true })
        .unwrap_or_else(|e| panic!("--lenient still refuses {text:?}: {e}"))
}

/// The error of `text`, with its (line, column).
fn error(text: &str) -> (String, (usize, usize)) {
    let e = strict(text)
        .err()
        .unwrap_or_else(|| panic!("{text:?} was accepted"));
    let position = e.position().unwrap_or((0, 0));
    (e.to_string(), position)
}

fn warnings(scene: &RibScene) -> String {
    scene
        .warnings
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn a_balanced_scene_is_accepted_without_structure_warnings() {
    let text = format!(
        "FrameBegin 1\nWorldBegin\nAttributeBegin\nTransformBegin\n{SPHERE}TransformEnd\nAttributeEnd\nWorldEnd\nFrameEnd\n"
    );
    let scene = strict(&text).unwrap();
    assert_eq!(scene.scene.objects.len(), 1);
    assert!(
        !warnings(&scene).contains("never closed"),
        "{}",
        warnings(&scene)
    );
}

#[test]
fn a_missing_world_end_is_an_error_at_world_begin() {
    let text = format!("Format 32 24 1\nWorldBegin\n{SPHERE}");
    let (message, position) = error(&text);
    assert_eq!(position, (2, 1), "{message}");
    assert!(
        message.starts_with("t.rib:2:1: WorldBegin is never closed")
            && message.contains("before its WorldEnd")
            && message.contains("--lenient"),
        "{message}"
    );
    let scene = lenient(&text);
    assert_eq!(scene.scene.objects.len(), 1, "what was read renders");
    assert!(
        warnings(&scene).contains("t.rib:2: WorldBegin is never closed"),
        "{}",
        warnings(&scene)
    );
}

#[test]
fn every_unclosed_block_names_its_line_and_its_end() {
    for (begin, end) in [
        ("AttributeBegin", "AttributeEnd"),
        ("TransformBegin", "TransformEnd"),
        ("MotionBegin [0 1]", "MotionEnd"),
        ("SolidBegin \"primitive\"", "SolidEnd"),
        ("ObjectBegin 1", "ObjectEnd"),
    ] {
        let request = begin.split(' ').next().unwrap();
        // At the end of the scene, inside the world block.
        let text = format!("WorldBegin\n{SPHERE}{begin}\n");
        let (message, position) = error(&text);
        assert_eq!(position.0, 4, "{begin}: {message}");
        assert!(
            message.contains(&format!("{request} is never closed"))
                && message.contains(&format!("before its {end}"))
                && message.contains("also open: the WorldBegin of line 1"),
            "{begin}: {message}"
        );
        // Before the end of the enclosing world block.
        let text = format!("WorldBegin\n{SPHERE}{begin}\nWorldEnd\n");
        let (message, position) = error(&text);
        assert_eq!(position.0, 5, "{begin}: {message}");
        assert!(
            message.contains(&format!(
                "WorldEnd: the {request} of line 4 is still open inside the WorldBegin of line 1 ({end} missing before this WorldEnd)"
            )),
            "{begin}: {message}"
        );
        let scene = lenient(&text);
        assert_eq!(scene.scene.objects.len(), 1, "{begin}");
    }
}

#[test]
fn an_unclosed_frame_is_an_error() {
    let text = format!("FrameBegin 1\nWorldBegin\n{SPHERE}WorldEnd\n");
    let (message, position) = error(&text);
    assert_eq!(position, (1, 1), "{message}");
    assert!(
        message.contains("FrameBegin is never closed") && message.contains("FrameEnd"),
        "{message}"
    );
    assert_eq!(lenient(&text).scene.objects.len(), 1);
}

#[test]
fn an_end_without_its_begin_is_an_error() {
    for end in [
        "AttributeEnd",
        "TransformEnd",
        "MotionEnd",
        "SolidEnd",
        "ObjectEnd",
        "FrameEnd",
    ] {
        let begin = end.replace("End", "Begin");
        let text = format!("WorldBegin\n{SPHERE}{end}\nWorldEnd\n");
        let (message, position) = error(&text);
        assert_eq!(position, (4, 1), "{end}: {message}");
        assert!(
            message.contains(&format!("{end}: without its {begin}")),
            "{end}: {message}"
        );
        let scene = lenient(&text);
        assert_eq!(scene.scene.objects.len(), 1, "{end}");
        assert!(
            warnings(&scene).contains(&format!("t.rib:4: {end}: without its {begin}; ignored")),
            "{end}: {}",
            warnings(&scene)
        );
    }
    let (message, _) = error(&format!("WorldBegin\n{SPHERE}WorldEnd\nWorldEnd\n"));
    assert!(
        message.contains("WorldEnd: without its WorldBegin"),
        "{message}"
    );
}

#[test]
fn lenient_closes_the_inner_blocks_and_restores_their_state() {
    // The colour set inside the unclosed TransformBegin's AttributeBegin is
    // restored when the outer AttributeEnd closes both.
    let text = format!(
        "WorldBegin\nColor [1 0 0]\nAttributeBegin\nColor [0 1 0]\nTransformBegin\nAttributeEnd\n{SPHERE}WorldEnd\n"
    );
    let (message, position) = error(&text);
    assert_eq!(position.0, 6, "{message}");
    assert!(
        message.contains(
            "the TransformBegin of line 5 is still open inside the AttributeBegin of line 3"
        ),
        "{message}"
    );
    let scene = lenient(&text);
    assert_eq!(scene.scene.objects.len(), 1);
    assert_eq!(scene.scene.objects[0].color, glam::Vec3::new(1.0, 0.0, 0.0));
}

#[test]
fn an_unclosed_block_in_an_archive_names_the_archive() {
    let dir = std::env::temp_dir().join(format!("reyes-rib-structure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("part.rib"), "AttributeBegin\nTranslate 0 0 5\n").unwrap();
    let main = dir.join("main.rib");
    std::fs::write(
        &main,
        "WorldBegin\nReadArchive \"part.rib\"\nSphere 1 -1 1 360\nWorldEnd\n",
    )
    .unwrap();
    let e = RibScene::load(&main).expect_err("refused");
    let message = e.to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        message.contains("main.rib:4:1: WorldEnd: the AttributeBegin of ")
            && message.contains("part.rib:1 is still open"),
        "{message}"
    );
}

#[test]
fn sides_must_be_one_or_two() {
    for bad in ["0", "-1", "1.5", "3"] {
        let (message, position) = error(&format!("WorldBegin\nSides {bad}\n{SPHERE}WorldEnd\n"));
        assert_eq!(position, (2, 1), "{message}");
        assert!(
            message.contains(&format!("Sides: {bad} is out of range: must be 1 or 2")),
            "{message}"
        );
    }
    for good in [1u8, 2] {
        let scene = strict(&format!("WorldBegin\nSides {good}\n{SPHERE}WorldEnd\n")).unwrap();
        assert_eq!(scene.scene.objects[0].sides, good);
    }
}

#[test]
fn pixel_samples_must_be_positive() {
    for bad in ["-2 -2", "0 4", "4 0", "2 -1"] {
        let (message, _) = error(&format!(
            "PixelSamples {bad}\nWorldBegin\n{SPHERE}WorldEnd\n"
        ));
        assert!(
            message.contains(&format!(
                "PixelSamples: {bad} is out of range: both counts must be > 0"
            )),
            "{message}"
        );
    }
    // A product that is no square still renders, with its warning.
    let scene = strict(&format!("PixelSamples 3 2\nWorldBegin\n{SPHERE}WorldEnd\n")).unwrap();
    assert!(
        warnings(&scene).contains("square grid"),
        "{}",
        warnings(&scene)
    );
}

#[test]
fn format_and_clipping_out_of_range_are_errors() {
    let (message, _) = error("Format 32.5 24 1\nWorldBegin\nWorldEnd\n");
    assert!(
        message.contains("Format: resolution 32.5 x 24") && message.contains("whole numbers"),
        "{message}"
    );
    for bad in ["0 100", "-1 100", "10 5", "5 5"] {
        let (message, _) = error(&format!("Clipping {bad}\nWorldBegin\nWorldEnd\n"));
        assert!(message.contains("needs 0 < near < far"), "{bad}: {message}");
    }
    let scene = strict(&format!(
        "Clipping 1e-8 100\nWorldBegin\n{SPHERE}WorldEnd\n"
    ))
    .unwrap();
    assert!(
        warnings(&scene).contains("Clipping near 0.00000001 is below"),
        "{}",
        warnings(&scene)
    );
}

#[test]
fn a_scene_without_geometry_warns() {
    for text in [
        "",
        "WorldBegin\nWorldEnd\n",
        "Format 32 24 1\nWorldBegin\nLightSource \"ambientlight\" 1\nWorldEnd\n",
    ] {
        let scene = strict(text).unwrap();
        assert!(scene.scene.objects.is_empty());
        assert!(
            warnings(&scene).contains(reyes::scene::NO_OBJECTS_WARNING),
            "{text:?}: {}",
            warnings(&scene)
        );
    }
}

#[test]
fn an_overflowing_camera_transform_is_named() {
    // The camera scales by 1e60, beyond f32: the light's direction is
    // still a direction, and the sphere's points are beyond f32.
    let text = "Scale 1e30 1e30 1e30\nScale 1e30 1e30 1e30\nWorldBegin\nLightSource \"distantlight\" 1\nTranslate 0 0 5\nPatch \"bilinear\" \"P\" [0 0 0 1 0 0 0 1 0 1 1 0]\nWorldEnd\n";
    let scene = strict(text).unwrap();
    let all = warnings(&scene);
    assert_eq!(scene.scene.lights.len(), 1, "{all}");
    assert!(scene.scene.lights[0].direction.is_finite());
    // The second Scale (line 2) is where the camera leaves f32.
    assert!(
        all.contains("t.rib:6: 1 of the primitive's 1 patches have control points beyond f32")
            && all.contains(
                "the camera transform (the transforms before WorldBegin) overflows f32 (from the Scale at t.rib:2 on)"
            ),
        "{all}"
    );
    assert!(!all.contains("from = to"), "{all}");
}

#[test]
fn an_overflowing_world_transform_names_its_request() {
    // Inside the world: the Rotate keeps the Scale's overflow, the
    // AttributeEnd restores a transform within f32 (nothing to name).
    let text = "WorldBegin
AttributeBegin
Scale 1e20 1e20 1e20
ConcatTransform [1e20 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]
Rotate 10 0 0 1
Translate 0 0 5
Patch \"bilinear\" \"P\" [0 0 0 1 0 0 0 1 0 1 1 0]
AttributeEnd
Translate 0 0 5
Patch \"bilinear\" \"P\" [0 0 0 1 0 0 0 1 0 1 1 0]
WorldEnd
";
    let scene = strict(text).unwrap();
    let all = warnings(&scene);
    assert!(
        all.contains(
            "t.rib:7: 1 of the primitive's 1 patches have control points beyond f32 in camera space: the current transform overflows f32 (from the ConcatTransform at t.rib:4 on)"
        ),
        "{all}"
    );
    assert!(!all.contains("t.rib:10"), "{all}");
    assert_eq!(
        scene.models.iter().map(|m| m.patches.len()).sum::<usize>(),
        1
    );
}

#[test]
fn a_far_plane_beyond_f32_names_the_primitive() {
    let (message, _) = error("WorldBegin\nTranslate 0 0 5\nSphere 3e38 -3e38 3e38 360\nWorldEnd\n");
    assert!(
        message.contains("the Sphere at t.rib:3 reaches z = ")
            && message.contains("give Clipping")
            && !message.contains("camera.far must be finite"),
        "{message}"
    );
    // With Clipping, the far plane is the file's.
    assert!(
        strict(
            "Clipping 0.1 100\nWorldBegin\nTranslate 0 0 5\nSphere 3e38 -3e38 3e38 360\nWorldEnd\n"
        )
        .is_ok()
    );
}

#[test]
fn a_lens_beyond_f32_names_depth_of_field() {
    let (message, position) = error(&format!(
        "Projection \"perspective\"\nDepthOfField 1e-30 1e30 5\nWorldBegin\n{SPHERE}WorldEnd\n"
    ));
    // At the request, before the world block is read.
    assert_eq!(position, (2, 1), "{message}");
    assert!(
        message.starts_with("t.rib:2:1: DepthOfField: the lens radius")
            && !message.contains("lens.aperture must be finite"),
        "{message}"
    );
}

/// Values no RenderMan scene can mean are errors with their line: a shading
/// rate that is not a positive area, a colour with a negative channel, and
/// spotlight angles or a beam distribution below zero. (A shading rate or
/// cone wider than this renderer draws is clamped with a warning.)
#[test]
fn impossible_values_are_errors_with_their_line() {
    for (request, words) in [
        (
            "ShadingRate -5",
            "ShadingRate: -5 is out of range: a shading rate is an area in pixels, > 0",
        ),
        ("ShadingRate 0", "ShadingRate: 0 is out of range"),
        (
            "Color [-1 0.5 0]",
            "Color: [-1 0.5 0] is out of range: every channel must be a finite number >= 0",
        ),
        (
            "LightSource \"spotlight\" 1 \"coneangle\" [-0.5]",
            "spotlight coneangle -0.5 is out of range: it must be a finite number >= 0",
        ),
        (
            "LightSource \"spotlight\" 1 \"conedeltaangle\" [-0.1]",
            "spotlight conedeltaangle -0.1 is out of range",
        ),
        (
            "LightSource \"spotlight\" 1 \"beamdistribution\" [-2]",
            "spotlight beamdistribution -2 is out of range",
        ),
    ] {
        let (message, position) = error(&format!("WorldBegin\n{request}\n{SPHERE}WorldEnd\n"));
        assert_eq!(position.0, 2, "{request}: {message}");
        assert!(message.contains(words), "{request}: {message}");
    }
    let scene = strict(&format!(
        "WorldBegin\nShadingRate 0.001\n{SPHERE}WorldEnd\n"
    ))
    .unwrap();
    assert!(
        scene.warnings.iter().any(|w| w
            .to_string()
            .contains("ShadingRate 0.001 is out of range; using 0.01")),
        "{:?}",
        scene.warnings
    );
}
