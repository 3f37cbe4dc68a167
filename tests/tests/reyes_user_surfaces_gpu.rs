//! A user's WGSL surface shader that reads every input of the shading
//! context and every lighting helper, on the GPU against its Rust twin in
//! the CPU reference: three spheres (two with the shader, one with other
//! parameter values; one displaced, so that `N` and `Ng` differ) at 1 and
//! 16 samples per pixel, whole and in screen tiles (which equal the whole
//! frame bit for bit);
//! a user shader with a texture and noise, and RIB's `paintedplastic`, the
//! same way.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::displacement::DisplacementDesc;
use reyes::gpu::GpuOptions;
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Light, Scene, SceneObject, ShaderValue, Surface, Transform};
use reyes::surface_shader::{CpuSurface, ShadingContext, ShadingHost, SurfaceOutput};
use tests::reyes_support::{
    agreement, assert_identical, assert_whole_and_tiled_agree, camera_down_z, gpu_turn, renderer,
    tiled_renderer,
};
use tests::shapes::bezier_sphere;

fn shader_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("shaders/every_input.wgsl")
}

/// The Rust twin of tests/shaders/every_input.wgsl, line for line.
fn every_input(
    ctx: &ShadingContext,
    lights: &dyn ShadingHost,
    slots: &[[f32; 4]],
) -> SurfaceOutput {
    let kd = slots[0][0];
    let tint = Vec3::new(slots[1][0], slots[1][1], slots[1][2]);
    let bands = slots[2][0].to_bits();
    let striped = slots[3][0] != 0.0;
    let v = -ctx.i.normalize();
    let band = |x: f32| 0.5 + 0.5 * (std::f32::consts::TAU * x * bands as f32).sin();
    let stripe = if striped {
        0.6 + 0.4 * band(ctx.s + ctx.t)
    } else {
        1.0
    };
    let facing = ctx.ng.dot(v).abs();
    let steps = ((ctx.du + ctx.dv) * 0.02).clamp(0.0, 0.2);
    let tangents = (ctx.dp_du.cross(ctx.dp_dv).length() * 0.05).clamp(0.0, 0.2);
    let eye = ((ctx.e - ctx.p).normalize().dot(ctx.n) * 0.1).clamp(0.0, 0.1);
    let lit = lights.ambient()
        + lights.diffuse(ctx, ctx.n) * kd
        + lights.specular(ctx, ctx.n, v, 0.2) * 0.5;
    let rim = (0..lights.light_count())
        .map(|i| {
            let (l, cl) = lights.illuminance(i, ctx.p, ctx.n, 1.2);
            cl * (l.dot(ctx.n) - 1.2f32.cos()).max(0.0) * 0.3
        })
        .sum::<Vec3>();
    let base = ctx.cs * tint * stripe * (0.5 + 0.5 * facing);
    let ci =
        base * lit + Vec3::new(ctx.u * steps, ctx.v * tangents, eye) + rim + Vec3::splat(ctx.time);
    SurfaceOutput {
        ci: ctx.os * ci,
        oi: ctx.os,
    }
}

fn scene(spp: u32, displaced: bool) -> (Scene, Vec<Model>) {
    let mut scene = Scene::default();
    scene.resolution.width = 160;
    scene.resolution.height = 120;
    scene.spp = spp;
    scene.camera = Some(camera_down_z());
    scene.ambient = 0.1;
    let mut models = Vec::new();
    let other = BTreeMap::from([
        ("Kd".to_owned(), ShaderValue::Number(0.9)),
        ("tint".to_owned(), ShaderValue::Numbers(vec![0.5, 1.0, 0.7])),
        ("bands".to_owned(), ShaderValue::Number(3.0)),
        ("striped".to_owned(), ShaderValue::Bool(false)),
    ]);
    for (i, parameters) in [BTreeMap::new(), other.clone(), BTreeMap::new()]
        .into_iter()
        .enumerate()
    {
        let mut object = SceneObject {
            model: format!("sphere-{i}"),
            subdivision: None,
            transform: Transform {
                translate: Vec3::new((i as f32 - 1.0) * 1.2, 0.0, -5.0),
                scale: reyes::scene::Scale::Uniform(0.58),
                ..Transform::default()
            },
            color: Vec3::new(0.9, 0.6, 0.3 + 0.2 * i as f32),
            surface: Some(Surface::Wgsl {
                file: shader_path(),
                parameters,
            }),
            shading_rate: None,
            displacement: None,
            transform_close: None,
            keys: Vec::new(),
            sides: 2,
            reverse_orientation: false,
        };
        if i == 2 && displaced {
            object.displacement = Some(DisplacementDesc {
                source: "sines".to_owned(),
                scale: 0.03,
                bound: None,
                tiling: 2.0,
                wgsl: None,
                file: None,
                parameters: Default::default(),
            });
        }
        scene.objects.push(object);
        models.push(bezier_sphere());
    }
    scene.lights = vec![
        Light {
            direction: Vec3::new(1.0, -1.0, -1.0),
            intensity: 0.8,
            ..Light::default()
        },
        Light::point(Vec3::new(-2.0, 1.0, -3.0), Vec3::new(1.0, 0.8, 0.6), 3.0),
    ];
    (scene, models)
}

/// The scene prepared, with the shader's Rust twin attached.
fn prepared(spp: u32) -> PreparedScene {
    let (scene, models) = scene(spp, true);
    let mut prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    assert_eq!(prepared.shaders.shaders.len(), 1, "one shader, loaded once");
    Arc::make_mut(&mut prepared.shaders.shaders[0]).cpu = Some(CpuSurface::new(every_input));
    prepared
}

#[gpu_test]
fn a_user_shader_with_every_input_matches_its_twin_whole_and_in_tiles() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut whole = renderer(gpu, GpuOptions::default());
    for spp in [1, 16] {
        // Small enough that the frame needs several tiles.
        let mut tiled = tiled_renderer(gpu, 192 * 64 * u64::from(spp));
        let scene = prepared(spp);
        let cpu = reference::try_render(&scene).expect("the reference runs the twin");
        let frames = assert_whole_and_tiled_agree(
            &format!("user shader at spp {spp}"),
            &scene,
            &mut whole,
            &mut tiled,
            &cpu,
        );
        // A tile splits, dices and samples as the whole frame does, so the
        // displaced grid's normals (from its neighbours) are the same too.
        assert_identical(
            &format!("spp {spp}, tiled against whole"),
            &frames[1],
            &frames[0],
        );
    }
}

/// The Rust twin of tests/shaders/textured_noise.wgsl.
fn textured_noise(
    ctx: &ShadingContext,
    host: &dyn ShadingHost,
    slots: &[[f32; 4]],
) -> SurfaceOutput {
    let texel = host.texture(ctx, slots[0][0].to_bits(), ctx.s, ctx.t);
    let marble = slots[1][0] * reyes::noise::snoise3(ctx.p * 3.0);
    let lit = host.ambient() + host.diffuse(ctx, ctx.n);
    SurfaceOutput {
        ci: ctx.cs * texel.truncate() * lit + Vec3::splat(marble),
        oi: ctx.os,
    }
}

/// A 64 x 48 texture of coloured squares with smooth edges, written as a
/// PNG (sRGB, as 8-bit PNGs are read).
fn write_texture(dir: &std::path::Path) -> PathBuf {
    let image = image::RgbaImage::from_fn(64, 48, |x, y| {
        let fx = (x as f32 / 8.0).sin() * 0.5 + 0.5;
        let fy = (y as f32 / 6.0).cos() * 0.5 + 0.5;
        image::Rgba([(255.0 * fx) as u8, (255.0 * fy) as u8, 128, 255])
    });
    let path = dir.join("squares.png");
    image.save(&path).expect("the texture is written");
    path
}

/// Textures and noise in a user shader, on the GPU against the twin: a
/// sphere whose texture covers its (s, t), at two sizes on screen (the
/// mip level follows the footprint), at 1 and 16 samples per pixel, whole
/// and in screen tiles.
#[gpu_test]
fn a_textured_noisy_shader_matches_its_twin_whole_and_in_tiles() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let dir = std::env::temp_dir().join(format!("reyes-textured-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let texture = write_texture(&dir);
    let prepared = |spp: u32| {
        let (mut scene, mut models) = scene(spp, false);
        scene.objects.truncate(2);
        models.truncate(2);
        scene.objects[1].transform.scale = reyes::scene::Scale::Uniform(0.2);
        for object in &mut scene.objects {
            object.surface = Some(Surface::Wgsl {
                file: PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("shaders/textured_noise.wgsl"),
                parameters: BTreeMap::from([(
                    "map".to_owned(),
                    ShaderValue::Text(texture.to_string_lossy().into_owned()),
                )]),
            });
        }
        let mut prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
        assert_eq!(prepared.textures.len(), 1, "the texture is loaded once");
        Arc::make_mut(&mut prepared.shaders.shaders[0]).cpu = Some(CpuSurface::new(textured_noise));
        prepared
    };
    let mut whole = renderer(gpu, GpuOptions::default());
    for spp in [1, 16] {
        // A third of the frame's samples: six tiles of 64 x 64 pixels, whose
        // edges cross both spheres.
        let mut tiled = tiled_renderer(gpu, 160 * 120 / 3 * u64::from(spp));
        let prepared = prepared(spp);
        let cpu = reference::try_render(&prepared).expect("the reference runs the twin");
        assert_whole_and_tiled_agree(
            &format!("textured noisy shader at spp {spp}"),
            &prepared,
            &mut whole,
            &mut tiled,
            &cpu,
        );
    }
    // The same renderer and buffers (those of the last frame, at 16 samples
    // per pixel) with another texture of the same size: the texels are
    // uploaded again (they are kept only while the texture set is the same).
    let inverted = image::open(&texture).unwrap().to_rgba8();
    let inverted = image::RgbaImage::from_fn(64, 48, |x, y| {
        let p = inverted.get_pixel(x, y);
        image::Rgba([255 - p[0], 255 - p[1], p[2], 255])
    });
    inverted.save(&texture).unwrap();
    let prepared = prepared(16);
    let cpu = reference::try_render(&prepared).expect("the reference runs the twin");
    let frame = whole.render(&prepared).expect("GPU render");
    let a = agreement(&frame, &cpu);
    eprintln!("textured, another texture: {a:?}");
    a.assert_at_least("textured noisy shader, texture replaced", 0.995, 0.99);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A square that fills an orthographic view, textured at one texel per
/// pixel, gives the texture back: PSNR at least 40 dB against the PNG's own
/// values (image row r shows texel row height - 1 - r: t grows upwards).
/// Shaded at a quarter of a pixel (`ShadingRate 0.25`), so that the colours
/// interpolated between grid points and the footprint's filter blur the
/// texture by well under a texel (42.9 dB on lavapipe); at a shading rate of
/// 1 the same image measures 38.6 dB, the blur of shading once per pixel.
#[gpu_test]
fn a_texture_at_one_texel_per_pixel_comes_back() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let (width, height) = (64u32, 48u32);
    let dir = std::env::temp_dir().join(format!("reyes-texel-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Whole periods across the texture, which wraps periodically (the
    // default): the texels at its edges blend with the opposite edge's.
    let texture = image::RgbaImage::from_fn(width, height, |x, y| {
        let r = 0.5 + 0.4 * (std::f32::consts::TAU * x as f32 / 16.0).sin();
        let g = 0.5 + 0.4 * (std::f32::consts::TAU * y as f32 / 16.0).cos();
        image::Rgba([(255.0 * r) as u8, (255.0 * g) as u8, 128, 255])
    });
    let path = dir.join("smooth.png");
    texture.save(&path).unwrap();
    let mut scene = Scene::default();
    scene.resolution.width = width;
    scene.resolution.height = height;
    scene.spp = 4;
    scene.pixel_filter = reyes::filter::PixelFilter::PIXEL_BOX;
    scene.quantize.dither_amplitude = 0.0;
    let aspect = width as f32 / height as f32;
    scene.camera = Some(reyes::scene::CameraDesc {
        projection: reyes::scene::Projection::Orthographic,
        ortho_height: Some(2.0),
        ..camera_down_z()
    });
    let mut square = reyes::model::Patch::default();
    for (k, point) in square.points.iter_mut().enumerate() {
        let (i, j) = ((k % 4) as f32, (k / 4) as f32);
        *point = Vec3::new(aspect * (2.0 * i / 3.0 - 1.0), 2.0 * j / 3.0 - 1.0, -5.0);
    }
    scene.objects.push(SceneObject {
        color: Vec3::ONE,
        surface: Some(Surface::Wgsl {
            file: PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("shaders/texture_only.wgsl"),
            parameters: BTreeMap::from([(
                "map".to_owned(),
                ShaderValue::Text(path.to_string_lossy().into_owned()),
            )]),
        }),
        shading_rate: Some(0.25),
        ..SceneObject::new("square")
    });
    let models = vec![Model::new(vec![square])];
    let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    let mut renderer = renderer(gpu, GpuOptions::default());
    let frame = renderer.render(&prepared).expect("GPU render");
    let mut squared = 0.0f64;
    for y in 0..height {
        for x in 0..width {
            let got = frame.image.get_pixel(x, y);
            let want = texture.get_pixel(x, height - 1 - y);
            for c in 0..3 {
                squared += (f64::from(got[c]) - f64::from(want[c])).powi(2);
            }
        }
    }
    let mse = squared / f64::from(3 * width * height);
    let psnr = 10.0 * (255.0f64 * 255.0 / mse.max(1e-12)).log10();
    eprintln!("one texel per pixel: PSNR {psnr:.1} dB (mse {mse:.3})");
    assert!(psnr >= 40.0, "PSNR {psnr:.1} dB < 40");
    let _ = std::fs::remove_dir_all(&dir);
}

/// RIB's `paintedplastic` with a texture made by `MakeTexture`: the
/// built-in WGSL shader on the GPU against its Rust twin in the reference,
/// at 1 and 16 samples per pixel, whole and in screen tiles.
#[gpu_test]
fn rib_paintedplastic_matches_the_reference_whole_and_in_tiles() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let dir = std::env::temp_dir().join(format!("reyes-painted-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    write_texture(&dir);
    let rib = dir.join("painted.rib");
    std::fs::write(
        &rib,
        "MakeTexture \"squares.png\" \"squares.tx\" \"periodic\" \"periodic\" \"gaussian\" 2 2\n\
         Format 96 72 1\nPixelSamples 2 2\nProjection \"perspective\" \"fov\" [40]\n\
         WorldBegin\nLightSource \"ambientlight\" 1 \"intensity\" [0.2]\n\
         LightSource \"distantlight\" 2 \"from\" [0 0 0] \"to\" [0.3 -0.4 1]\n\
         Color [1 0.9 0.8]\n\
         Surface \"paintedplastic\" \"texturename\" \"squares.tx\" \"Ks\" 0.6 \"roughness\" 0.08\n\
         Translate 0 0 5\nRotate 30 1 0 0\nSphere 1.5 -1.5 1.5 360\nWorldEnd\n",
    )
    .unwrap();
    let mut loaded = reyes::rib::RibScene::load(&rib).expect("the RIB loads");
    let mut whole = renderer(gpu, GpuOptions::default());
    for spp in [1, 16] {
        // Two thirds of the frame's samples: four tiles, 64 x 64 pixels and
        // what is left of the 96 x 72 frame, whose edges cross the sphere.
        let mut tiled = tiled_renderer(gpu, 96 * 72 * 2 / 3 * u64::from(spp));
        loaded.scene.spp = spp;
        let prepared = loaded.prepare().expect("the scene prepares");
        assert_eq!(prepared.textures.len(), 1);
        let cpu = reference::try_render(&prepared).expect("the built-in shader has a twin");
        assert_whole_and_tiled_agree(
            &format!("RIB paintedplastic at spp {spp}"),
            &prepared,
            &mut whole,
            &mut tiled,
            &cpu,
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_reference_refuses_a_user_shader_without_a_twin() {
    let (scene, models) = scene(1, false);
    let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    let error = reference::try_render(&prepared).expect_err("no twin");
    let message = error.to_string();
    assert!(
        message.contains("every_input.wgsl") && message.contains("GPU"),
        "{message}"
    );
}
