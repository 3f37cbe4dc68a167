//! RIB attributes the renderer cannot apply: checked, and warned about with
//! their lines; the rest of the scene renders.

use reyes::rib::RibScene;

fn parse(world: &str) -> Result<RibScene, String> {
    let text = format!(
        "Projection \"perspective\" \"fov\" 60\nWorldBegin\nLightSource \"distantlight\" 1\n{world}Polygon \"P\" [0 0 5 1 0 5 0 1 5]\nWorldEnd\n"
    );
    RibScene::from_text(&text, "a.rib").map_err(|e| e.to_string())
}

fn warnings(rib: &RibScene) -> String {
    let all: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    all.join("\n")
}

#[test]
fn displacement_bounds_are_checked_and_shaders_warn() {
    let rib = parse(
        "Attribute \"displacementbound\" \"sphere\" [0.5] \"coordinatesystem\" [\"object\"]\n",
    )
    .unwrap();
    assert_eq!(warnings(&rib), "");
    assert_eq!(rib.scene.objects.len(), 1);
    let rib = parse("Attribute \"displacementbound\" \"float sphere\" [0.5]\n").unwrap();
    assert_eq!(warnings(&rib), "");

    for bad in ["[-1]", "[1 2]", "[\"x\"]"] {
        let error = parse(&format!(
            "Attribute \"displacementbound\" \"sphere\" {bad}\n"
        ))
        .unwrap_err();
        assert!(
            error.contains("a.rib:4") && error.contains("sphere"),
            "{bad}: {error}"
        );
    }

    let rib = parse("Displacement \"bumpy\" \"Km\" [1]\nDisplacement \"bumpy\"\n").unwrap();
    let all = warnings(&rib);
    assert!(
        all.contains("a.rib:4: Displacement \"bumpy\" without a \"texturename\" displaces nothing"),
        "{all}"
    );
    assert_eq!(all.matches("Displacement \"bumpy\"").count(), 1, "{all}");
    assert_eq!(rib.scene.objects.len(), 1);
}

#[test]
fn opacity_and_other_attributes_warn_once() {
    let rib = parse("Opacity [1 1 1]\n").unwrap();
    assert_eq!(warnings(&rib), "");
    let rib = parse(
        "Opacity [0.5 0.5 0.5]\nOpacity [0.2 0.2 0.2]\nAttribute \"identifier\" \"name\" [\"a\"]\n",
    )
    .unwrap();
    let all = warnings(&rib);
    assert!(
        all.contains("a.rib:4: Opacity [0.5 0.5 0.5]: transparency is not supported"),
        "{all}"
    );
    assert_eq!(all.matches("Opacity").count(), 1, "{all}");
    assert!(
        all.contains("a.rib:6: Attribute \"identifier\" is not supported"),
        "{all}"
    );
    assert!(parse("Opacity [1 1]\n").unwrap_err().contains("a.rib:4"));
    assert_eq!(rib.scene.objects.len(), 1);
}

/// Primitive variables the renderer does not read (per-vertex colours and
/// opacities, normals, user variables) are warned about once per name,
/// with the first line; positions and texture coordinates are read
/// without a word.
#[test]
fn unread_primitive_variables_warn_once() {
    let rib = parse(
        "Polygon \"P\" [0 0 5 1 0 5 0 1 5] \"st\" [0 0 1 0 0 1]\n\
         Sphere 1 -1 1 360 \"s\" [0 1 0 1] \"t\" [0 0 1 1]\n",
    )
    .unwrap();
    assert_eq!(warnings(&rib), "");
    let rib = parse(
        "Polygon \"P\" [0 0 5 1 0 5 0 1 5] \"Os\" [0.5 0.5 0.5 0.5 0.5 0.5 0.5 0.5 0.5]\n\
         Polygon \"P\" [0 0 5 1 0 5 0 1 5] \"Os\" [1 1 1 1 1 1 1 1 1] \"Cs\" [1 0 0 1 0 0 1 0 0]\n\
         Sphere 1 -1 1 360 \"N\" [0 0 1 0 0 1 0 0 1 0 0 1]\n",
    )
    .unwrap();
    let all = warnings(&rib);
    for (line, variable) in [(4, "Os"), (5, "Cs")] {
        assert!(
            all.contains(&format!(
                "a.rib:{line}: Polygon: primitive variable \"{variable}\" is not supported"
            )),
            "{all}"
        );
        assert_eq!(all.matches(&format!("\"{variable}\"")).count(), 1, "{all}");
    }
    assert!(
        all.contains("a.rib:6: Sphere: primitive variable \"N\" is not supported"),
        "{all}"
    );
}
