//! Displacement shaders (docs/shaders.md) on the CPU path: RenderMan's
//! `bumpy` from RIB against the geometry it must make (a sphere grown or
//! shrunk by `Km` times its texture, its silhouette measured against the
//! projected radius computed here), the RIB requests and their warnings,
//! and the scene table's checks.

use std::path::{Path, PathBuf};

use reyes::displacement::HeightSource;
use reyes::rib::RibScene;
use reyes::scene::{Scene, SceneError};

/// A scratch directory with a white 8 x 8 texture (`white.png`, 1.0 once
/// read as linear data).
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("reyes-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    image::GrayImage::from_pixel(8, 8, image::Luma([255]))
        .save(dir.join("white.png"))
        .unwrap();
    dir
}

/// A unit sphere at distance 8 in a 30-degree, `side` x `side` view,
/// `constant` white, displaced by `displacement`.
fn sphere_rib(side: u32, displacement: &str) -> String {
    format!(
        "Format {side} {side} 1\nPixelSamples 4 4\nPixelFilter \"box\" 1 1\n\
         Projection \"perspective\" \"fov\" [30]\nTranslate 0 0 8\nWorldBegin\n\
         AttributeBegin\nSurface \"constant\"\n{displacement}\nSphere 1 -1 1 360\n\
         AttributeEnd\nWorldEnd\n"
    )
}

fn load(dir: &Path, text: &str) -> RibScene {
    let path = dir.join("scene.rib");
    std::fs::write(&path, text).unwrap();
    RibScene::load(&path).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn warnings(rib: &RibScene) -> Vec<String> {
    rib.warnings.iter().map(ToString::to_string).collect()
}

/// The radius, in pixels, of the disc with the image's coverage (white on
/// black: the sum of the pixels' linear values).
fn coverage_radius(rib: &RibScene) -> f64 {
    let prepared = rib.prepare().expect("scene prepares");
    let image = reyes::reference::try_render(&prepared)
        .expect("the reference renders bumpy")
        .linear;
    let covered: f64 = image.pixels().map(|p| f64::from(p[1])).sum();
    (covered / std::f64::consts::PI).sqrt()
}

/// The projected radius in pixels of a sphere of radius `r` at distance
/// `d` under a `fov`-degree perspective of `side` pixels: the silhouette's
/// half angle is asin(r / d).
fn projected_radius(r: f64, d: f64, fov: f64, side: f64) -> f64 {
    let focal = side / 2.0 / (fov.to_radians() / 2.0).tan();
    focal * (r / d).asin().tan()
}

#[test]
fn bumpy_moves_the_surface_along_its_outward_normal_by_km_times_the_texture() {
    let dir = scratch("bumpy-radius");
    let side = 160;
    for km in [0.0, 0.3, -0.3] {
        let rib = load(
            &dir,
            &sphere_rib(
                side,
                &format!("Displacement \"bumpy\" \"Km\" [{km}] \"texturename\" \"white.png\""),
            ),
        );
        let measured = coverage_radius(&rib);
        let expected = projected_radius(1.0 + km, 8.0, 30.0, f64::from(side));
        eprintln!("Km {km}: radius {measured:.2} px, expected {expected:.2} px");
        assert!(
            (measured - expected).abs() < 0.6,
            "Km {km}: the silhouette's radius is {measured} px, {expected} px expected"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bumpy_knows_its_bound_and_a_declared_one_is_carried_into_world_units() {
    let dir = scratch("bumpy-bound");
    let rib = load(
        &dir,
        &sphere_rib(
            32,
            "Displacement \"bumpy\" \"Km\" [0.25] \"texturename\" \"white.png\"",
        ),
    );
    let prepared = rib.prepare().unwrap();
    let bound = prepared.objects[0].displacement_bound();
    assert!(
        (bound - 0.25).abs() < 1e-6,
        "|Km| times the texture's largest value: {bound}"
    );
    // An object-space bound under Scale 2 is twice as large in the world.
    let rib = load(
        &dir,
        &sphere_rib(
            32,
            "Scale 2 2 2\nAttribute \"displacementbound\" \"sphere\" [0.3]\n\
             Displacement \"bumpy\" \"Km\" [0.1] \"texturename\" \"white.png\"",
        ),
    );
    let bound = rib.prepare().unwrap().objects[0].displacement_bound();
    assert!(
        (bound - 0.6).abs() < 1e-5,
        "0.3 in object space under Scale 2: {bound}"
    );
    // In world space, the scale does not apply.
    let rib = load(
        &dir,
        &sphere_rib(
            32,
            "Scale 2 2 2\nAttribute \"displacementbound\" \"sphere\" [0.3] \"coordinatesystem\" [\"world\"]\n\
             Displacement \"bumpy\" \"Km\" [0.1] \"texturename\" \"white.png\"",
        ),
    );
    let bound = rib.prepare().unwrap().objects[0].displacement_bound();
    assert!((bound - 0.3).abs() < 1e-5, "{bound}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn displacement_requests_that_do_nothing_say_so() {
    let dir = scratch("displacement-warnings");
    let cases = [
        (
            "Displacement \"bumpy\" \"Km\" [0.1]",
            "without a \"texturename\"",
        ),
        (
            "Displacement \"dented\" \"Km\" [1]",
            "no dented.wgsl beside the RIB file",
        ),
        (
            "Displacement \"bumpy\" \"Km\" [0.1] \"amplitude\" [2] \"texturename\" \"white.png\"",
            "has no parameter \"amplitude\"",
        ),
    ];
    for (request, expected) in cases {
        let rib = load(&dir, &sphere_rib(16, request));
        let all = warnings(&rib);
        assert!(
            all.iter().any(|w| w.contains(expected)),
            "{request}: {all:?}"
        );
    }
    // `null` displaces nothing, silently.
    let rib = load(&dir, &sphere_rib(16, "Displacement \"null\""));
    assert!(rib.scene.objects[0].displacement.is_none());
    assert!(warnings(&rib).is_empty(), "{:?}", warnings(&rib));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_wgsl_displacement_shader_beside_the_rib_runs_and_wants_a_bound() {
    let dir = scratch("displacement-wgsl");
    std::fs::write(
        dir.join("swell.wgsl"),
        "struct Parameters { amount: f32 }\nconst DEFAULTS = Parameters(0.1);\n\
         fn displacement(ctx: ShadingContext, params: Parameters) -> vec3<f32> {\n\
         return ctx.P + ctx.N * params.amount;\n}\n",
    )
    .unwrap();
    let rib = load(
        &dir,
        &sphere_rib(16, "Displacement \"swell\" \"amount\" [0.2]"),
    );
    let all = warnings(&rib);
    assert!(
        all.iter()
            .any(|w| w.contains("without Attribute \"displacementbound\"")),
        "{all:?}"
    );
    let prepared = rib.prepare().unwrap();
    let displacement = prepared.objects[0].displacement.as_ref().unwrap();
    assert!(matches!(displacement.source, HeightSource::Shader(_)));
    assert_eq!(prepared.shaders.parameters[0][0], 0.2, "the RIB's value");
    // The CPU reference has no twin for it, and says so with the file.
    let error = reyes::reference::try_render(&prepared)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("swell.wgsl") && error.contains("displacement shader"),
        "{error}"
    );
    // A parameter the shader does not declare warns at the request's line
    // (the Displacement request is line 9 of `sphere_rib`).
    let rib = load(
        &dir,
        &sphere_rib(16, "Displacement \"swell\" \"amount\" [0.2] \"wobble\" [1]"),
    );
    let all = warnings(&rib);
    assert!(
        all.iter()
            .any(|w| w.contains("scene.rib:9:") && w.contains("no parameter \"wobble\"")),
        "{all:?}"
    );
    // A shader that does not compile, or of the other kind, is an error at
    // the request's line that names the shader's own line.
    std::fs::write(
        dir.join("broken.wgsl"),
        "fn displacement(ctx: ShadingContext) -> vec3<f32> {\n  return ctx.Q;\n}\n",
    )
    .unwrap();
    let path = dir.join("scene.rib");
    std::fs::write(&path, sphere_rib(16, "Displacement \"broken\"")).unwrap();
    let error = RibScene::load(&path).unwrap_err().to_string();
    assert!(
        error.contains("scene.rib:9") && error.contains("broken.wgsl") && error.contains("line 2"),
        "{error}"
    );
    std::fs::write(&path, sphere_rib(16, "Surface \"swell\"")).unwrap();
    let error = RibScene::load(&path).unwrap_err().to_string();
    assert!(error.contains("is a displacement shader"), "{error}");
    // With a bound, no warning.
    let rib = load(
        &dir,
        &sphere_rib(
            16,
            "Attribute \"displacementbound\" \"sphere\" [0.2]\nDisplacement \"swell\" \"amount\" [0.2]",
        ),
    );
    assert!(warnings(&rib).is_empty(), "{:?}", warnings(&rib));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_scene_table_checks_a_shader_displacement() {
    let dir = scratch("displacement-toml");
    std::fs::write(
        dir.join("shade.wgsl"),
        "fn surface(ctx: ShadingContext) -> SurfaceOutput { return SurfaceOutput(ctx.Cs, ctx.Os); }\n",
    )
    .unwrap();
    let scene = |table: &str| {
        let text = format!("[[objects]]\nmodel = \"teapot\"\n[objects.displacement]\n{table}\n");
        let path = dir.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        Scene::load(&path).and_then(|scene| reyes::prepare::PreparedScene::load(&scene).map(|_| ()))
    };
    let error = |table: &str| scene(table).expect_err(table).to_string();
    assert!(error("source = \"shader\"\nbound = 0.1").contains("`file`"));
    assert!(error("source = \"shader\"\nfile = \"x.wgsl\"").contains("bound"));
    assert!(
        error("source = \"sines\"\nfile = \"x.wgsl\"")
            .contains("only used with source = \"shader\"")
    );
    assert!(
        error("source = \"sines\"\nparameters = { Km = 1 }")
            .contains("only used with source = \"shader\"")
    );
    let wrong_kind = error("source = \"shader\"\nfile = \"shade.wgsl\"\nbound = 0.1");
    assert!(wrong_kind.contains("is a surface shader"), "{wrong_kind}");
    // bumpy needs no bound: it knows its own.
    scene(
        "source = \"shader\"\nfile = \"builtin:bumpy\"\nparameters = { Km = 0.1, texturename = \"white.png\" }",
    )
    .expect("bumpy bounds itself");
    assert!(matches!(
        scene("source = \"shader\"\nfile = \"missing.wgsl\"\nbound = 0.1"),
        Err(SceneError::Displacement { .. })
    ));
    let _ = std::fs::remove_dir_all(&dir);
}
