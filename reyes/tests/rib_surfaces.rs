//! `Surface` with the standard shaders (`constant`, `matte`, `metal`,
//! `plastic`) and their `Ka`, `Kd`, `Ks`, `roughness` and `specularcolor`:
//! the scene each maps to, the warnings for what the renderer cannot
//! follow, and rendered pixels against the RenderMan Interface 3.2
//! (appendix A) formulas worked by hand.

use reyes::color::linear_to_srgb8;
use reyes::rib::RibScene;

/// A square facing the camera at depth 5 filling the middle of a 33 x 33
/// image, with `lights` and `surface` (and `Color [cs]`) before it.
fn scene(lights: &str, cs: [f64; 3], surface: &str) -> String {
    format!(
        "Format 33 33 1\nPixelSamples 1 1\nProjection \"perspective\" \"fov\" [40]\n\
         WorldBegin\n{lights}\nColor [{} {} {}]\n{surface}\n\
         Polygon \"P\" [-1 -1 5  -1 1 5  1 1 5  1 -1 5]\nWorldEnd\n",
        cs[0], cs[1], cs[2]
    )
}

fn read(text: &str) -> RibScene {
    RibScene::from_text(text, "surface.rib").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn warnings(rib: &RibScene) -> Vec<String> {
    rib.warnings.iter().map(ToString::to_string).collect()
}

fn close(a: f32, b: f64) -> bool {
    (f64::from(a) - b).abs() < 1e-6
}

fn assert_color(rib: &RibScene, expected: [f64; 3]) {
    let c = rib.scene.objects[0].color;
    assert!(
        close(c.x, expected[0]) && close(c.y, expected[1]) && close(c.z, expected[2]),
        "colour {c}, expected {expected:?}"
    );
}

const AMBIENT: &str = "LightSource \"ambientlight\" 1 \"intensity\" [0.2]";
/// A distant light travelling along +z (from behind the camera): on the
/// square, `N.L = 1`, and in the middle of the image `N.H = 1`.
const HEAD_LIGHT: &str =
    "LightSource \"distantlight\" 2 \"intensity\" [0.5] \"from\" [0 0 0] \"to\" [0 0 1]";

#[test]
fn matte_maps_kd_onto_the_colour_and_ka_onto_the_ambient() {
    let rib = read(&scene(
        AMBIENT,
        [0.8, 0.4, 0.2],
        "Surface \"matte\" \"Ka\" [0.5] \"Kd\" [0.8]",
    ));
    assert!(rib.warnings.is_empty(), "{:?}", warnings(&rib));
    assert_color(&rib, [0.64, 0.32, 0.16]);
    // Cs * Kd * ambient' = Cs * Ka * 0.2: ambient' = 0.2 * Ka / Kd.
    assert!(
        close(rib.scene.ambient, 0.2 * 0.5 / 0.8),
        "{}",
        rib.scene.ambient
    );
    assert_eq!(rib.scene.specular.strength, 0.0);
    // The defaults: Ka = Kd = 1.
    let rib = read(&scene(AMBIENT, [0.8, 0.4, 0.2], "Surface \"matte\""));
    assert_color(&rib, [0.8, 0.4, 0.2]);
    assert!(close(rib.scene.ambient, 0.2));
}

#[test]
fn plastic_maps_every_parameter() {
    let rib = read(&scene(
        AMBIENT,
        [0.8, 0.4, 0.2],
        "Surface \"plastic\" \"Ka\" [0.6] \"Kd\" [0.4] \"Ks\" [0.3] \"roughness\" [0.05] \
         \"specularcolor\" [0.5 0.5 0.5]",
    ));
    assert!(rib.warnings.is_empty(), "{:?}", warnings(&rib));
    assert_color(&rib, [0.32, 0.16, 0.08]);
    assert!(close(rib.scene.ambient, 0.2 * 0.6 / 0.4));
    assert!(close(rib.scene.specular.strength, 0.3 * 0.5));
    assert!(close(rib.scene.specular.shininess, 20.0));
    // The defaults: Ka 1, Kd 0.5, Ks 0.5, roughness 0.1, specularcolor white.
    let rib = read(&scene(AMBIENT, [0.8, 0.4, 0.2], "Surface \"plastic\""));
    assert!(rib.warnings.is_empty(), "{:?}", warnings(&rib));
    assert_color(&rib, [0.4, 0.2, 0.1]);
    assert!(close(rib.scene.ambient, 0.4));
    assert!(close(rib.scene.specular.strength, 0.5));
    assert!(close(rib.scene.specular.shininess, 10.0));
}

#[test]
fn a_coloured_specularcolor_is_taken_as_its_mean_with_a_warning() {
    let rib = read(&scene(
        AMBIENT,
        [1.0, 1.0, 1.0],
        "Surface \"plastic\" \"Ks\" [0.8] \"specularcolor\" [1 0.5 0]",
    ));
    assert!(close(rib.scene.specular.strength, 0.8 * 0.5));
    let shown = warnings(&rib);
    assert!(
        shown.len() == 1 && shown[0].contains("specularcolor [1 0.5 0] is taken as its mean, 0.5"),
        "{shown:?}"
    );
}

#[test]
fn metal_has_no_diffuse_and_a_highlight_of_ks_times_its_colour() {
    let rib = read(&scene(
        AMBIENT,
        [0.9, 0.6, 0.3],
        "Surface \"metal\" \"Ks\" [0.8] \"roughness\" [0.2]",
    ));
    assert_color(&rib, [0.0, 0.0, 0.0]);
    assert!(close(rib.scene.specular.strength, 0.8 * 0.6));
    assert!(close(rib.scene.specular.shininess, 5.0));
    // No surface with a diffuse term: the ambient keeps its scale of 1.
    assert!(close(rib.scene.ambient, 0.2));
    let shown = warnings(&rib);
    assert_eq!(shown.len(), 2, "{shown:?}");
    assert!(shown[0].contains("Surface \"metal\""), "{shown:?}");
    assert!(
        shown[1].contains("metal's colour Cs [0.9 0.6 0.3]"),
        "{shown:?}"
    );
    // The defaults: Ks 1, roughness 0.1.
    let rib = read(&scene(AMBIENT, [0.5, 0.5, 0.5], "Surface \"metal\""));
    assert!(close(rib.scene.specular.strength, 0.5));
    assert!(close(rib.scene.specular.shininess, 10.0));
}

#[test]
fn constant_is_matte_with_ka_and_kd_one_with_a_warning() {
    let rib = read(&scene(AMBIENT, [0.3, 0.6, 0.9], "Surface \"constant\""));
    assert_color(&rib, [0.3, 0.6, 0.9]);
    assert!(close(rib.scene.ambient, 0.2));
    assert_eq!(rib.scene.specular.strength, 0.0);
    let shown = warnings(&rib);
    assert!(
        shown.len() == 1 && shown[0].contains("\"constant\" is unlit in RenderMan"),
        "{shown:?}"
    );
}

#[test]
fn surfaces_that_differ_share_the_scene_wide_terms_with_warnings() {
    // A matte (Ka / Kd = 1) and a plastic (1 / 0.5 = 2): the mean, 1.5.
    let text = scene(AMBIENT, [1.0, 1.0, 1.0], "Surface \"matte\"").replace(
        "WorldEnd",
        "Surface \"plastic\" \"Ks\" [0.7]\nPolygon \"P\" [2 2 5  2 3 5  3 3 5  3 2 5]\nWorldEnd",
    );
    let rib = read(&text);
    assert!(close(rib.scene.ambient, 0.2 * 1.5), "{}", rib.scene.ambient);
    assert!(close(rib.scene.specular.strength, 0.7));
    let shown = warnings(&rib);
    assert_eq!(shown.len(), 2, "{shown:?}");
    assert!(
        shown.iter().any(|w| w.contains("one ambient term")
            && w.contains("Ka / Kd goes from 1 to 2")
            && w.contains("using the mean, 1.5")),
        "{shown:?}"
    );
    assert!(
        shown.iter().any(|w| w.contains("one specular term")),
        "{shown:?}"
    );
    // Two plastics with the same highlight and Ka / Kd: no warning.
    let text = scene(AMBIENT, [1.0, 1.0, 1.0], "Surface \"plastic\" \"Kd\" [0.5]").replace(
        "WorldEnd",
        "Surface \"plastic\" \"Ka\" [0.4] \"Kd\" [0.2]\nPolygon \"P\" [2 2 5  2 3 5  3 3 5  3 2 5]\nWorldEnd",
    );
    let rib = read(&text);
    assert!(rib.warnings.is_empty(), "{:?}", warnings(&rib));
}

#[test]
fn unknown_parameters_negative_weights_and_tiny_roughness_warn() {
    let rib = read(&scene(
        AMBIENT,
        [1.0, 1.0, 1.0],
        "Surface \"matte\" \"Ks\" [0.5] \"Kd\" [-1]",
    ));
    let shown = warnings(&rib);
    assert!(
        shown
            .iter()
            .any(|w| w.contains("Surface \"matte\" has no parameter \"Ks\"")),
        "{shown:?}"
    );
    assert!(
        shown
            .iter()
            .any(|w| w.contains("Kd -1 is negative; using 0")),
        "{shown:?}"
    );
    assert_color(&rib, [0.0, 0.0, 0.0]);
    let rib = read(&scene(
        AMBIENT,
        [1.0, 1.0, 1.0],
        "Surface \"plastic\" \"roughness\" [0]",
    ));
    assert!(close(rib.scene.specular.shininess, 1000.0));
    assert!(
        warnings(&rib)
            .iter()
            .any(|w| w.contains("roughness 0 is below")),
        "{:?}",
        warnings(&rib)
    );
    // An unknown shader is matte with a warning, as before.
    let rib = read(&scene(AMBIENT, [0.5, 0.5, 0.5], "Surface \"wood\""));
    assert_color(&rib, [0.5, 0.5, 0.5]);
    assert!(warnings(&rib)[0].contains("Surface \"wood\" is not supported"));
}

/// The middle pixel of the rendered scene, and the RenderMan value in
/// linear RGB encoded as the image is (sRGB, 8 bits).
fn assert_middle_pixel(text: &str, renderman: [f64; 3]) {
    let rib = read(text);
    let image = reyes::reference::render(&rib.prepare().unwrap()).image;
    let p = image.get_pixel(16, 16);
    for c in 0..3 {
        let want = linear_to_srgb8(renderman[c] as f32);
        assert!(
            p[c].abs_diff(want) <= 2,
            "channel {c}: rendered {}, RenderMan {want} ({:?})\n{text}",
            p[c],
            renderman
        );
    }
}

#[test]
fn rendered_surfaces_follow_the_renderman_formulas() {
    let lights = format!("{AMBIENT}\n{HEAD_LIGHT}");
    let (amb, light) = (0.2, 0.5);
    let cs = [0.8, 0.4, 0.2];
    // matte: Cs * (Ka * ambient + Kd * diffuse), N.L = 1.
    let (ka, kd) = (0.5, 0.8);
    assert_middle_pixel(
        &scene(&lights, cs, "Surface \"matte\" \"Ka\" [0.5] \"Kd\" [0.8]"),
        cs.map(|c| c * (ka * amb + kd * light)),
    );
    // plastic: Cs * (Ka * ambient + Kd * diffuse) + specularcolor * Ks *
    // specular, with N.H = 1 in the middle of the image.
    let (ka, kd, ks, grey) = (0.6, 0.4, 0.3, 0.5);
    assert_middle_pixel(
        &scene(
            &lights,
            cs,
            "Surface \"plastic\" \"Ka\" [0.6] \"Kd\" [0.4] \"Ks\" [0.3] \"specularcolor\" [0.5 0.5 0.5]",
        ),
        cs.map(|c| c * (ka * amb + kd * light) + grey * ks * light),
    );
    // metal, grey, without an ambient light (the renderer loses Ka):
    // Cs * Ks * specular.
    let (ks, grey) = (0.8, 0.7);
    assert_middle_pixel(
        &scene(HEAD_LIGHT, [grey; 3], "Surface \"metal\" \"Ks\" [0.8]"),
        [grey * ks * light; 3],
    );
    // constant under an ambient light of intensity 1 alone: Cs.
    assert_middle_pixel(
        &scene(
            "LightSource \"ambientlight\" 1 \"intensity\" [1]",
            cs,
            "Surface \"constant\"",
        ),
        cs,
    );
}
