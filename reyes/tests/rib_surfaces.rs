//! `Surface` with the standard shaders (`constant`, `matte`, `metal`,
//! `plastic`, `defaultsurface`, `null`) and their `Ka`, `Kd`, `Ks`,
//! `roughness` and `specularcolor`: each object keeps its own, the warnings
//! for what the renderer cannot follow, and rendered pixels against the
//! RenderMan Interface 3.2 (appendix A) formulas worked by hand.

use glam::Vec3;
use reyes::color::linear_to_srgb8;
use reyes::rib::RibScene;
use reyes::scene::{Light, Surface};

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

fn surface(rib: &RibScene) -> Surface {
    rib.scene.objects[0]
        .surface
        .clone()
        .expect("a RIB object names its surface")
}

const AMBIENT: &str = "LightSource \"ambientlight\" 1 \"intensity\" [0.2]";
/// A distant light travelling along +z (from behind the camera): on the
/// square, `N.L = 1`, and in the middle of the image `N.H = 1`.
const HEAD_LIGHT: &str =
    "LightSource \"distantlight\" 2 \"intensity\" [0.5] \"from\" [0 0 0] \"to\" [0 0 1]";

#[test]
fn each_shader_and_parameter_reaches_the_object() {
    let cases: [(&str, Surface); 7] = [
        (
            "Surface \"matte\" \"Ka\" [0.5] \"Kd\" [0.8]",
            Surface::Matte { ka: 0.5, kd: 0.8 },
        ),
        ("Surface \"matte\"", Surface::Matte { ka: 1.0, kd: 1.0 }),
        (
            "Surface \"plastic\" \"Ka\" [0.6] \"Kd\" [0.4] \"Ks\" [0.3] \"roughness\" [0.05] \
             \"specularcolor\" [1 0.5 0]",
            Surface::Plastic {
                ka: 0.6,
                kd: 0.4,
                ks: 0.3,
                roughness: 0.05,
                specular_color: Vec3::new(1.0, 0.5, 0.0),
            },
        ),
        ("Surface \"plastic\"", Surface::PLASTIC),
        (
            "Surface \"metal\" \"Ka\" [0.3] \"Ks\" [0.8] \"roughness\" [0.2]",
            Surface::Metal {
                ka: 0.3,
                ks: 0.8,
                roughness: 0.2,
            },
        ),
        ("Surface \"constant\"", Surface::Constant),
        (
            "Surface \"defaultsurface\" \"Kd\" [0.5]",
            Surface::DefaultSurface { ka: 0.2, kd: 0.5 },
        ),
    ];
    for (request, expected) in cases {
        let rib = read(&scene(AMBIENT, [0.8, 0.4, 0.2], request));
        assert!(rib.warnings.is_empty(), "{request}: {:?}", warnings(&rib));
        assert_eq!(surface(&rib), expected, "{request}");
        assert_eq!(rib.scene.objects[0].color, Vec3::new(0.8, 0.4, 0.2));
    }
    // Without a Surface: RenderMan's defaultsurface.
    let rib = read(&scene(AMBIENT, [0.8, 0.4, 0.2], ""));
    assert_eq!(surface(&rib), Surface::DEFAULT_SURFACE);
    // An ambient light is a light of its own, in colour.
    let rib = read(&scene(
        "LightSource \"ambientlight\" 1 \"intensity\" [0.5] \"lightcolor\" [1 0.5 0]",
        [1.0; 3],
        "",
    ));
    assert_eq!(rib.scene.ambient, 0.0);
    assert_eq!(
        rib.scene.lights,
        [Light::ambient(Vec3::new(1.0, 0.5, 0.0), 0.5)]
    );
}

#[test]
fn objects_keep_their_own_surfaces() {
    let text = scene(AMBIENT, [1.0, 1.0, 1.0], "Surface \"matte\"").replace(
        "WorldEnd",
        "Color [0 0 1]\nSurface \"plastic\" \"Ks\" [0.7]\n\
         Polygon \"P\" [2 2 5  2 3 5  3 3 5  3 2 5]\nWorldEnd",
    );
    let rib = read(&text);
    assert!(rib.warnings.is_empty(), "{:?}", warnings(&rib));
    let objects = &rib.scene.objects;
    assert_eq!(objects.len(), 2);
    assert_eq!(
        objects[0].surface,
        Some(Surface::Matte { ka: 1.0, kd: 1.0 })
    );
    assert_eq!(objects[0].color, Vec3::ONE);
    assert_eq!(
        objects[1].surface,
        Some(Surface::Plastic {
            ka: 1.0,
            kd: 0.5,
            ks: 0.7,
            roughness: 0.1,
            specular_color: Vec3::ONE,
        })
    );
    assert_eq!(objects[1].color, Vec3::new(0.0, 0.0, 1.0));
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
        shown.iter().any(|w| w.contains("Kd -1 is negative")),
        "{shown:?}"
    );
    assert_eq!(surface(&rib), Surface::Matte { ka: 1.0, kd: 0.0 });
    let rib = read(&scene(
        AMBIENT,
        [1.0, 1.0, 1.0],
        "Surface \"plastic\" \"roughness\" [0]",
    ));
    assert!(matches!(
        surface(&rib),
        Surface::Plastic { roughness, .. } if roughness == 1e-4
    ));
    assert!(
        warnings(&rib)
            .iter()
            .any(|w| w.contains("roughness 0 is below")),
        "{:?}",
        warnings(&rib)
    );
    // An unknown shader is RenderMan's defaultsurface, with a warning.
    let rib = read(&scene(AMBIENT, [0.5, 0.5, 0.5], "Surface \"wood\""));
    assert_eq!(surface(&rib), Surface::DEFAULT_SURFACE);
    assert!(warnings(&rib)[0].contains("Surface \"wood\" is not supported"));
    // paintedplastic without a texture is plastic; with one, the built-in
    // WGSL shader with the request's parameters.
    let rib = read(&scene(
        AMBIENT,
        [0.5, 0.5, 0.5],
        "Surface \"paintedplastic\" \"Ks\" 0.3",
    ));
    assert!(matches!(surface(&rib), Surface::Plastic { ks, .. } if ks == 0.3));
    let rib = read(&scene(
        AMBIENT,
        [0.5, 0.5, 0.5],
        "Surface \"paintedplastic\" \"texturename\" \"wood.png\" \"Kd\" 0.7",
    ));
    let Surface::Wgsl { file, parameters } = surface(&rib) else {
        panic!("{:?}", surface(&rib));
    };
    assert_eq!(file.to_str(), Some("builtin:paintedplastic"));
    assert_eq!(
        parameters["Kd"],
        reyes::scene::ShaderValue::Number(0.7f32.into())
    );
    assert_eq!(
        parameters["texturename"],
        reyes::scene::ShaderValue::Texture(reyes::texture::TextureDesc::new("wood.png"))
    );
    // shinymetal without an environment map is metal, as RenderMan's is.
    let rib = read(&scene(
        AMBIENT,
        [0.5, 0.5, 0.5],
        "Surface \"shinymetal\" \"Ks\" [0.4] \"Kr\" [0.5]",
    ));
    assert!(rib.warnings.is_empty(), "{:?}", warnings(&rib));
    assert_eq!(
        surface(&rib),
        Surface::Metal {
            ka: 1.0,
            ks: 0.4,
            roughness: 0.1
        }
    );
}

#[test]
fn a_scene_without_lights_warns_only_where_a_surface_needs_them() {
    let rib = read(&scene("", [0.5, 0.5, 0.5], ""));
    assert!(rib.warnings.is_empty(), "{:?}", warnings(&rib));
    let rib = read(&scene("", [0.5, 0.5, 0.5], "Surface \"matte\""));
    assert!(
        warnings(&rib)
            .iter()
            .any(|w| w.contains("no light sources")),
        "{:?}",
        warnings(&rib)
    );
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
    // specular, with N.H = 1 in the middle of the image; a coloured
    // highlight.
    let (ka, kd, ks) = (0.6, 0.4, 0.3);
    let tint = [1.0, 0.5, 0.25];
    let expected: Vec<f64> = (0..3)
        .map(|i| cs[i] * (ka * amb + kd * light) + tint[i] * ks * light)
        .collect();
    assert_middle_pixel(
        &scene(
            &lights,
            cs,
            "Surface \"plastic\" \"Ka\" [0.6] \"Kd\" [0.4] \"Ks\" [0.3] \"specularcolor\" [1 0.5 0.25]",
        ),
        [expected[0], expected[1], expected[2]],
    );
    // metal: Cs * (Ka * ambient + Ks * specular).
    let (ka, ks) = (0.5, 0.8);
    assert_middle_pixel(
        &scene(&lights, cs, "Surface \"metal\" \"Ka\" [0.5] \"Ks\" [0.8]"),
        cs.map(|c| c * (ka * amb + ks * light)),
    );
    // constant ignores the lights: Cs.
    assert_middle_pixel(&scene(&lights, cs, "Surface \"constant\""), cs);
    // defaultsurface needs no lights: the viewer looks along the normal in
    // the middle of the image, d = 1: Cs * (Ka + Kd) = Cs.
    assert_middle_pixel(&scene("", cs, ""), cs);
    assert_middle_pixel(
        &scene(
            "",
            cs,
            "Surface \"defaultsurface\" \"Ka\" [0.1] \"Kd\" [0.3]",
        ),
        cs.map(|c| c * 0.4),
    );
}

/// A spotlight from the camera along +z lights the middle of the square as
/// `intensity / d^2` (the axis: cos = 1) and leaves the square dark beyond
/// its cone, where only the ambient light shows.
#[test]
fn a_spotlight_lights_its_cone() {
    // The square is 2 x 2 at depth 5, 18 pixels wide: a pixel 7 rows above
    // the middle is atan(7 / 16.5 * tan 20) = 8.8 degrees off the axis,
    // beyond a cone of 5 degrees.
    let spot = "LightSource \"spotlight\" 3 \"intensity\" [12.5] \"from\" [0 0 0] \"to\" [0 0 1] \
                \"coneangle\" [0.08726646] \"conedeltaangle\" [0.02]";
    let text = scene(&format!("{AMBIENT}\n{spot}"), [1.0; 3], "Surface \"matte\"");
    let rib = read(&text);
    assert!(rib.warnings.is_empty(), "{:?}", warnings(&rib));
    // 12.5 / 25 = 0.5 on the axis, plus the ambient 0.2.
    assert_middle_pixel(&text, [0.7; 3]);
    let image = reyes::reference::render(&rib.prepare().unwrap()).image;
    // The square's edge is beyond the cone: the ambient light alone.
    let edge = image.get_pixel(16, 9);
    assert!(
        edge[0].abs_diff(linear_to_srgb8(0.2)) <= 2,
        "{edge:?} vs {}",
        linear_to_srgb8(0.2)
    );
}

/// `ShadingRate` is an attribute: before `WorldBegin` the frame's, inside
/// an attribute block its objects'. Two spheres at rates 1 and 16 dice
/// into a number of micropolygons between those of both at 1 and both at
/// 16 (each sphere as it would be alone).
#[test]
fn shading_rate_is_per_object() {
    let text = |a: f32, b: f32| {
        format!(
            "Format 64 48 1\nShadingRate 2\nProjection \"perspective\" \"fov\" [40]\nWorldBegin\n\
             Surface \"constant\"\n\
             AttributeBegin\nShadingRate {a}\nTranslate -1.2 0 6\nSphere 1 -1 1 360\nAttributeEnd\n\
             AttributeBegin\nShadingRate {b}\nTranslate 1.2 0 6\nSphere 1 -1 1 360\nAttributeEnd\nWorldEnd\n"
        )
    };
    let rib = read(&text(1.0, 16.0));
    assert!(rib.warnings.is_empty(), "{:?}", warnings(&rib));
    assert_eq!(rib.scene.shading_rate, 2.0);
    let rates: Vec<Option<f32>> = rib.scene.objects.iter().map(|o| o.shading_rate).collect();
    assert_eq!(rates, [Some(1.0), Some(16.0)]);
    let micropolygons = |a, b| {
        let rib = read(&text(a, b));
        reyes::reference::render(&rib.prepare().unwrap())
            .stats
            .micropolygons
    };
    let (fine, coarse, mixed) = (
        micropolygons(1.0, 1.0),
        micropolygons(16.0, 16.0),
        micropolygons(1.0, 16.0),
    );
    eprintln!("micropolygons: both at 1: {fine}, both at 16: {coarse}, 1 and 16: {mixed}");
    assert!(
        coarse < mixed && mixed < fine,
        "{coarse} < {mixed} < {fine}"
    );
    // Each sphere dices as it would alone: the halves of both extremes.
    assert!(mixed.abs_diff((fine + coarse) / 2) * 20 < fine, "{mixed}");
}

/// `Surface "name"` with `name.wgsl` beside the RIB file is that user
/// shader, with the request's parameters; without the file it warns and
/// shades as `defaultsurface`.
#[test]
fn a_surface_named_after_a_wgsl_file_beside_the_rib_is_that_shader() {
    let dir = std::env::temp_dir().join(format!("reyes-rib-wgsl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("stripes.wgsl"),
        "struct Parameters { Kd: f32, tint: vec3<f32>, map: TextureId }\n\
         fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {\n\
             return SurfaceOutput(ctx.Cs * params.tint * params.Kd, ctx.Os);\n\
         }\n",
    )
    .unwrap();
    let rib = dir.join("scene.rib");
    let text = scene(
        "",
        [1.0, 1.0, 1.0],
        "Surface \"stripes\" \"float Kd\" 0.5 \"color tint\" [1 0.5 0.25] \"string map\" \"wood.png\"",
    );
    std::fs::write(&rib, &text).unwrap();
    let loaded = RibScene::load(&rib).expect("the RIB loads");
    let Some(Surface::Wgsl { file, parameters }) = loaded.scene.objects[0].surface.clone() else {
        panic!("{:?}", loaded.scene.objects[0].surface);
    };
    assert_eq!(file, dir.join("stripes.wgsl"));
    use reyes::scene::ShaderValue;
    assert_eq!(parameters["Kd"], ShaderValue::Number(0.5));
    assert_eq!(
        parameters["tint"],
        ShaderValue::Numbers(vec![1.0, 0.5, 0.25])
    );
    assert_eq!(parameters["map"], ShaderValue::Text("wood.png".to_owned()));
    // A texture made by MakeTexture reads its picture, beside the RIB.
    let made = format!(
        "MakeTexture \"wood.tif\" \"wood.tx\" \"periodic\" \"clamp\" \"gaussian\" 2 2\n{}",
        text.replace("\"wood.png\"", "\"wood.tx\"")
    );
    std::fs::write(&rib, made).unwrap();
    let loaded = RibScene::load(&rib).expect("the RIB loads");
    let Some(Surface::Wgsl { parameters, .. }) = loaded.scene.objects[0].surface.clone() else {
        panic!("{:?}", loaded.scene.objects[0].surface);
    };
    // ... with its wrap modes.
    assert_eq!(
        parameters["map"],
        ShaderValue::Texture(reyes::texture::TextureDesc {
            wrap_t: reyes::texture::Wrap::Clamp,
            ..reyes::texture::TextureDesc::new(dir.join("wood.tif"))
        })
    );
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    // A wrap mode RenderMan does not have is an error with the line.
    let wrong = text.replace("\"wood.png\"", "\"wood.tx\"");
    std::fs::write(
        &rib,
        format!(
            "MakeTexture \"wood.tif\" \"wood.tx\" \"mirror\" \"clamp\" \"gaussian\" 2 2\n{wrong}"
        ),
    )
    .unwrap();
    let error = RibScene::load(&rib).unwrap_err().to_string();
    assert!(
        error.contains(":1:") && error.contains("\"mirror\" is not a wrap mode"),
        "{error}"
    );
    // A parameter the shader does not declare warns with the request's line
    // and is dropped.
    std::fs::write(
        &rib,
        text.replace("\"float Kd\" 0.5", "\"float Kd\" 0.5 \"float Ks\" 1"),
    )
    .unwrap();
    let loaded = RibScene::load(&rib).expect("the RIB loads");
    let line = text.lines().position(|l| l.starts_with("Surface")).unwrap() + 1;
    assert!(
        loaded.warnings.iter().any(|w| {
            let w = w.to_string();
            w.contains(&format!("scene.rib:{line}:")) && w.contains("no parameter \"Ks\"")
        }),
        "{:?}",
        loaded.warnings
    );
    let Some(Surface::Wgsl { parameters, .. }) = loaded.scene.objects[0].surface.clone() else {
        panic!("{:?}", loaded.scene.objects[0].surface);
    };
    assert!(!parameters.contains_key("Ks"));
    // A name with no file beside the RIB.
    let missing = read(&scene("", [1.0, 1.0, 1.0], "Surface \"marble\""));
    assert_eq!(surface(&missing), Surface::DEFAULT_SURFACE);
    assert!(
        warnings(&missing).iter().any(|w| w.contains("marble.wgsl")),
        "{:?}",
        warnings(&missing)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
