//! `MakeLatLongEnvironment`, `MakeCubeFaceEnvironment` and `Surface
//! "shinymetal"` with a `texturename`: the built-in WGSL `shinymetal` with
//! the standard shader's parameters, its map's picture, and RenderMan's
//! world space for the lookup. (The rendered shader is checked in
//! `tests/tests/reyes_environment_gpu.rs`.)

use reyes::rib::RibScene;
use reyes::scene::{ShaderValue, Surface};

/// A square in front of the camera with `surface`, after `before` (the
/// requests before `WorldBegin`).
fn scene(before: &str, surface: &str) -> String {
    format!(
        "{before}\nFormat 33 33 1\nProjection \"perspective\" \"fov\" [40]\n\
         WorldBegin\nLightSource \"ambientlight\" 1 \"intensity\" [0.2]\n{surface}\n\
         Polygon \"P\" [-1 -1 5  -1 1 5  1 1 5  1 -1 5]\nWorldEnd\n"
    )
}

fn read(text: &str) -> RibScene {
    RibScene::from_text(text, "dir/env.rib").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn shader(rib: &RibScene) -> (String, std::collections::BTreeMap<String, ShaderValue>) {
    match rib.scene.objects[0].surface.clone() {
        Some(Surface::Wgsl { file, parameters }) => {
            (file.to_string_lossy().into_owned(), parameters)
        }
        other => panic!("{other:?}"),
    }
}

fn vector(x: f64, y: f64, z: f64) -> ShaderValue {
    ShaderValue::Numbers(vec![x, y, z])
}

#[test]
fn a_lat_long_map_names_its_picture_for_shinymetal() {
    let rib = read(&scene(
        "MakeLatLongEnvironment \"sky.png\" \"sky.env\" \"gaussian\" 2 2",
        "Surface \"shinymetal\" \"texturename\" \"sky.env\" \"Ka\" 0.3 \"Ks\" 0.6 \"Kr\" 0.8 \"roughness\" 0.05",
    ));
    assert!(rib.warnings.is_empty(), "{:?}", rib.warnings);
    let (file, parameters) = shader(&rib);
    assert_eq!(file, "builtin:shinymetal");
    let number = |x: f32| ShaderValue::Number(f64::from(x));
    assert_eq!(parameters["Ka"], number(0.3));
    assert_eq!(parameters["Ks"], number(0.6));
    assert_eq!(parameters["Kr"], number(0.8));
    assert_eq!(parameters["roughness"], number(0.05));
    // The picture, beside the RIB file.
    assert_eq!(
        parameters["texturename"],
        ShaderValue::Texture(reyes::texture::TextureDesc::new("dir/sky.png"))
    );
    // No camera transform: RenderMan's world is its camera space, which is
    // the renderer's world with x mirrored.
    assert_eq!(parameters["world_x"], vector(-1.0, 0.0, 0.0));
    assert_eq!(parameters["world_y"], vector(0.0, 1.0, 0.0));
    assert_eq!(parameters["world_z"], vector(0.0, 0.0, 1.0));
    // The defaults are the specification's (Ka = Ks = Kr = 1, roughness
    // 0.1).
    let rib = read(&scene(
        "MakeLatLongEnvironment \"sky.png\" \"sky.env\" \"box\" 1 1",
        "Surface \"shinymetal\" \"texturename\" \"sky.env\"",
    ));
    let (_, parameters) = shader(&rib);
    for (name, value) in [("Ka", 1.0), ("Ks", 1.0), ("Kr", 1.0), ("roughness", 0.1)] {
        assert_eq!(parameters[name], number(value), "{name}");
    }
}

#[test]
fn the_lookup_is_in_renderman_world_space() {
    // The camera turned half a turn about z (either way round): world x
    // and y are camera -x and -y, so the renderer's x (camera -x) is world
    // +x and its y is world -y. A translation changes no direction.
    let rib = read(&scene(
        "MakeLatLongEnvironment \"sky.png\" \"sky.env\" \"box\" 1 1\n\
         Translate 3 -2 7\nRotate 180 0 0 1",
        "Surface \"shinymetal\" \"texturename\" \"sky.env\"",
    ));
    let (_, parameters) = shader(&rib);
    let close = |value: &ShaderValue, want: [f64; 3]| match value {
        ShaderValue::Numbers(v) => v.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12),
        _ => false,
    };
    assert!(
        close(&parameters["world_x"], [1.0, 0.0, 0.0]),
        "{parameters:?}"
    );
    assert!(
        close(&parameters["world_y"], [0.0, -1.0, 0.0]),
        "{parameters:?}"
    );
    assert!(
        close(&parameters["world_z"], [0.0, 0.0, 1.0]),
        "{parameters:?}"
    );
}

#[test]
fn a_texture_name_without_a_make_request_is_a_file_beside_the_rib() {
    let rib = read(&scene(
        "",
        "Surface \"shinymetal\" \"texturename\" \"sky.exr\"",
    ));
    let (_, parameters) = shader(&rib);
    assert_eq!(
        parameters["texturename"],
        ShaderValue::Texture(reyes::texture::TextureDesc::new("dir/sky.exr"))
    );
}

#[test]
fn a_cube_face_map_warns_at_its_line_and_leaves_shinymetal_metal() {
    let rib = read(&scene(
        "MakeCubeFaceEnvironment \"px.tif\" \"nx.tif\" \"py.tif\" \"ny.tif\" \"pz.tif\" \"nz.tif\" \"room.env\" 95 \"gaussian\" 2 2",
        "Surface \"shinymetal\" \"texturename\" \"room.env\" \"Ks\" 0.5",
    ));
    let warnings: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    assert!(
        warnings.iter().any(|w| w.starts_with("dir/env.rib:1: ")
            && w.contains("MakeCubeFaceEnvironment is not supported")),
        "{warnings:?}"
    );
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("\"room.env\" is a cube-face environment map")),
        "{warnings:?}"
    );
    assert_eq!(
        rib.scene.objects[0].surface,
        Some(Surface::Metal {
            ka: 1.0,
            ks: 0.5,
            roughness: 0.1
        })
    );
}

#[test]
fn make_lat_long_environment_needs_its_arguments() {
    let error = RibScene::from_text(
        "MakeLatLongEnvironment \"sky.png\"\nWorldBegin\nWorldEnd\n",
        "env.rib",
    )
    .expect_err("too few arguments");
    let message = error.to_string();
    assert!(
        message.contains("env.rib:1") && message.contains("MakeLatLongEnvironment"),
        "{message}"
    );
}
