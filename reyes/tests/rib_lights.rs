//! RIB lights: `pointlight` and `distantlight` placed by the current
//! transform, and the light list (`LightSource` turns a light on for the
//! attribute block, `Illuminate` switches it) mapped onto the renderer's
//! scene-wide lights.

use glam::Vec3;
use reyes::rib::RibScene;

/// A triangle in front of the camera.
const TRIANGLE: &str = "Polygon \"P\" [0 0 5 1 0 5 0 1 5]\n";

fn scene(world: &str) -> RibScene {
    let text = format!(
        "Format 32 32 1\nProjection \"perspective\" \"fov\" 90\nWorldBegin\n{world}WorldEnd\n"
    );
    RibScene::from_text(&text, "l.rib").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn warnings(rib: &RibScene) -> String {
    let all: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    all.join("\n")
}

#[test]
fn a_point_light_is_placed_by_the_current_transform() {
    let rib = scene(&format!(
        "AttributeBegin\nTranslate 1 2 0\nLightSource \"pointlight\" 1 \"from\" [0 0 3] \"intensity\" [12] \"lightcolor\" [1 0.5 0.25]\nIlluminate 1 1\nAttributeEnd\nIlluminate 1 1\n{TRIANGLE}"
    ));
    let lights = &rib.scene.lights;
    assert_eq!(lights.len(), 1, "{}", warnings(&rib));
    // RenderMan's camera space is left-handed: x is mirrored in the
    // renderer's world (see docs/rib.md).
    assert_eq!(lights[0].position, Some(Vec3::new(-1.0, 2.0, 3.0)));
    assert_eq!(lights[0].intensity, 12.0);
    assert_eq!(lights[0].color, Vec3::new(1.0, 0.5, 0.25));
    assert_eq!(warnings(&rib), "");
    // The TOML written from it keeps the point light.
    let toml = rib.scene.to_toml_string();
    assert!(toml.contains("position = [-1.0, 2.0, 3.0]"), "{toml}");
}

#[test]
fn a_distant_light_keeps_its_direction() {
    let rib = scene(&format!(
        "LightSource \"distantlight\" 1 \"from\" [0 0 0] \"to\" [0 0 1]\n{TRIANGLE}"
    ));
    let light = rib.scene.lights[0].clone();
    assert_eq!(light.position, None);
    assert_eq!(light.direction, Vec3::new(0.0, 0.0, 1.0));
}

#[test]
fn a_light_defined_in_an_attribute_block_is_off_after_it() {
    let rib = scene(&format!(
        "AttributeBegin\nLightSource \"pointlight\" \"key\" \"from\" [0 0 3]\nAttributeEnd\n{TRIANGLE}"
    ));
    assert!(rib.scene.lights.is_empty());
    let all = warnings(&rib);
    assert!(
        all.contains("l.rib:5: light \"key\" is off (AttributeEnd or Illuminate) for every primitive; ignored"),
        "{all}"
    );
}

#[test]
fn illuminate_switches_a_light_for_the_geometry_that_follows() {
    // Off before all geometry: dropped.
    let rib = scene(&format!(
        "LightSource \"distantlight\" 7\nIlluminate 7 0\n{TRIANGLE}"
    ));
    assert!(rib.scene.lights.is_empty());
    assert!(
        warnings(&rib).contains("light \"7\" is off"),
        "{}",
        warnings(&rib)
    );

    // Off, then on again for the geometry: kept, no warning.
    let rib = scene(&format!(
        "LightSource \"distantlight\" 7\nIlluminate 7 0\nIlluminate 7 1\n{TRIANGLE}"
    ));
    assert_eq!(rib.scene.lights.len(), 1);
    assert_eq!(warnings(&rib), "");

    // On for one primitive, off for the next: kept, and the difference from
    // RenderMan is said.
    let rib = scene(&format!(
        "LightSource \"distantlight\" 7\n{TRIANGLE}Illuminate 7 0\n{TRIANGLE}"
    ));
    assert_eq!(rib.scene.lights.len(), 1);
    assert!(
        warnings(&rib).contains("l.rib:4: light \"7\" is off for some primitives, but the renderer's lights are scene-wide"),
        "{}",
        warnings(&rib)
    );

    // An unknown handle warns with its line; a malformed request is an error.
    let rib = scene(&format!(
        "LightSource \"distantlight\" 1\nIlluminate 2 0\n{TRIANGLE}"
    ));
    assert!(
        warnings(&rib).contains("l.rib:5: Illuminate \"2\": no light has this handle"),
        "{}",
        warnings(&rib)
    );
    let text = format!("WorldBegin\nIlluminate 1\n{TRIANGLE}WorldEnd\n");
    let error = RibScene::from_text(&text, "e.rib").unwrap_err().to_string();
    assert!(error.contains("e.rib:2"), "{error}");
}

#[test]
fn a_point_light_lights_the_near_side_more() {
    // A floor from z = 1.2 to z = 20 along the view, lit from above the
    // eye: the RIB's CPU image is brighter where the floor is nearer the
    // light (at the bottom of the image).
    let rib = scene(
        "Surface \"matte\"\nLightSource \"pointlight\" 1 \"from\" [0 2 0] \"intensity\" [3]\n\
         Polygon \"P\" [-2 -1 1.2 2 -1 1.2 2 -1 20 -2 -1 20]\n",
    );
    let prepared = rib.prepare().unwrap();
    let image = reyes::reference::render(&prepared).image;
    let column: Vec<u8> = (0..32).map(|y| image.get_pixel(16, y)[0]).collect();
    let lit: Vec<u8> = column.iter().copied().filter(|&c| c > 0).collect();
    assert!(lit.len() > 6, "{column:?}");
    // The first and last rows are partly covered.
    let lit = &lit[1..lit.len() - 1];
    // From the horizon (far, top) down to the bottom (near) every row is
    // at least as bright as the one above, and the nearest is brighter by far.
    assert!(lit.windows(2).all(|w| w[0] <= w[1]), "{column:?}");
    assert!(
        u32::from(lit[lit.len() - 1]) > 2 * u32::from(lit[0]),
        "{column:?}"
    );
}
