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

/// `MakeCubeFaceEnvironment` names the map it will write (in the current
/// directory, read as linear data) for `shinymetal`, and is handed over to
/// run between frames; its filter is not used, which it says once.
#[test]
fn a_cube_face_map_names_the_map_it_writes_for_shinymetal() {
    let rib = read(&scene(
        "MakeCubeFaceEnvironment \"px.tif\" \"nx.tif\" \"py.tif\" \"ny.tif\" \"pz.tif\" \"nz.tif\" \"room.env\" 95 \"gaussian\" 2 2",
        "Surface \"shinymetal\" \"texturename\" \"room.env\" \"Ks\" 0.5",
    ));
    let (file, parameters) = shader(&rib);
    assert_eq!(file, "builtin:shinymetal");
    assert_eq!(
        parameters["texturename"],
        ShaderValue::Texture(reyes::texture::TextureDesc {
            color_space: reyes::texture::ColorSpace::Linear,
            ..reyes::texture::TextureDesc::new(std::env::current_dir().unwrap().join("room.env"))
        })
    );
    let warnings: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    assert!(
        warnings
            .iter()
            .any(|w| w.starts_with("dir/env.rib:1: ")
                && w.contains("filter and widths are not used")),
        "{warnings:?}"
    );
    // Read as one scene, the request is not run, and says so.
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("MakeCubeFaceEnvironment is not run")),
        "{warnings:?}"
    );
    // A field of view under 90 degrees leaves gaps between the faces.
    let error = RibScene::from_text(
        &scene(
            "MakeCubeFaceEnvironment \"px.tif\" \"nx.tif\" \"py.tif\" \"ny.tif\" \"pz.tif\" \"nz.tif\" \"room.env\" 60 \"box\" 1 1",
            "",
        ),
        "env.rib",
    )
    .expect_err("a narrow field of view");
    let message = error.to_string();
    assert!(
        message.contains("env.rib:1") && message.contains("at least 90 degrees"),
        "{message}"
    );
}

/// End to end on the CPU reference: `reyes render` runs the request
/// between frames, writing the latitude-longitude map of six pictures, and
/// a `shinymetal` mirror facing the camera reflects the `nz` face (world
/// -z is back towards the camera), mirrored: the mirror's upper left shows
/// the face's upper right quadrant (`nz`'s right is world -x, its up +y).
#[test]
fn a_mirror_reflects_the_cube_face_behind_the_camera() {
    let dir = std::env::temp_dir().join(format!("reyes-cube-faces-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let plain = |rgb: [u8; 3]| image::RgbImage::from_pixel(64, 64, image::Rgb(rgb));
    let quadrant = [[200, 40, 40], [40, 200, 40], [40, 40, 200], [200, 200, 40]];
    for (name, picture) in [
        ("px.png", plain([90, 90, 90])),
        ("nx.png", plain([20, 120, 160])),
        ("py.png", plain([160, 20, 120])),
        ("ny.png", plain([120, 160, 20])),
        ("pz.png", plain([250, 250, 250])),
        (
            "nz.png",
            // Upper left, upper right, lower left, lower right.
            image::RgbImage::from_fn(64, 64, |x, y| {
                image::Rgb(quadrant[usize::from(x >= 32) + 2 * usize::from(y >= 32)])
            }),
        ),
    ] {
        picture.save(dir.join(name)).unwrap();
    }
    let text = "MakeCubeFaceEnvironment \"px.png\" \"nx.png\" \"py.png\" \"ny.png\" \"pz.png\" \"nz.png\" \"room.env\" 90 \"box\" 1 1
FrameBegin 1
Format 33 33 1
PixelSamples 2 2
Projection \"perspective\" \"fov\" [40]
Display \"mirror.png\" \"file\" \"rgba\"
WorldBegin
Surface \"shinymetal\" \"texturename\" \"room.env\" \"Ka\" 0 \"Ks\" 0 \"Kr\" 1
Polygon \"P\" [-1 -1 5  -1 1 5  1 1 5  1 -1 5]
WorldEnd
FrameEnd
";
    std::fs::write(dir.join("room.rib"), text).unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_reyes"))
        .current_dir(&dir)
        .args(["render", "--cpu", "room.rib"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.contains("wrote environment map room.env (256x128"),
        "{stdout}"
    );
    let picture = image::open(dir.join("mirror.png")).unwrap().to_rgb8();
    // Pixels a sixth of the way in from each corner of the mirror, which
    // spans about pixels 8 to 25.
    for ((x, y), expected) in [
        ((10, 10), quadrant[1]),
        ((23, 10), quadrant[0]),
        ((10, 23), quadrant[3]),
        ((23, 23), quadrant[2]),
    ] {
        let got = picture.get_pixel(x, y).0;
        let close = got
            .iter()
            .zip(expected)
            .all(|(&a, b)| (i32::from(a) - i32::from(b)).abs() <= 3);
        assert!(
            close,
            "pixel ({x}, {y}) is {got:?}, not the quadrant {expected:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
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
