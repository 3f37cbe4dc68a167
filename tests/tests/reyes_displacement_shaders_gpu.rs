//! Displacement shaders on the GPU against the CPU reference: a user's
//! WGSL displacement shader that reads every input of the context, noise
//! and a texture (through its Rust twin), and the standard `bumpy` from a
//! RIB file, in one frame, at 1 and 16 samples per pixel.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::displacement::DisplacementDesc;
use reyes::gpu::GpuOptions;
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Light, Scene, SceneObject, ShaderValue, Surface, Transform};
use reyes::surface_shader::{CpuDisplacement, ShadingContext, ShadingHost};
use tests::reyes_support::{agreement, camera_down_z, gpu_turn, renderer};
use tests::shapes::bezier_sphere;

/// The Rust twin of tests/shaders/every_input_displacement.wgsl.
fn every_input(ctx: &ShadingContext, host: &dyn ShadingHost, slots: &[[f32; 4]]) -> Vec3 {
    let (amplitude, frequency) = (slots[0][0], slots[1][0]);
    let wave = (6.283_185_5 * frequency * (ctx.s + 0.5 * ctx.t)).sin();
    let grain = reyes::noise::snoise3(ctx.p * 4.0);
    let bump = host.texture(ctx, slots[2][0].to_bits(), ctx.u, ctx.v).x;
    let facing = 0.2 * (ctx.e - ctx.p).normalize().dot(ctx.n) + 0.1 * ctx.i.normalize().dot(ctx.ng);
    let stretch = 0.05 * ctx.dp_du.cross(ctx.dp_dv).length() + 0.1 * (ctx.dst_du.x + ctx.dst_dv.y);
    let steps = ctx.du + ctx.dv + ctx.time;
    let h = amplitude * (wave + 0.5 * grain + bump + facing + stretch + ctx.cs.y) + steps;
    ctx.p + ctx.n * h + ctx.os * 0.0
}

/// A grey ramp with bumps, written as a 16-bit PNG (read as linear).
fn write_bumps(dir: &std::path::Path) -> PathBuf {
    let image = image::ImageBuffer::<image::Luma<u16>, _>::from_fn(32, 32, |x, y| {
        let h = 0.5 + 0.25 * ((x as f32 / 3.0).sin() + (y as f32 / 5.0).cos());
        image::Luma([(65535.0 * h) as u16])
    });
    let path = dir.join("bumps16.png");
    image.save(&path).expect("the texture is written");
    path
}

fn sphere(i: usize, displacement: DisplacementDesc) -> SceneObject {
    SceneObject {
        model: format!("sphere-{i}"),
        subdivision: None,
        transform: Transform {
            translate: Vec3::new((i as f32 - 1.0) * 1.2, 0.0, -5.0),
            scale: reyes::scene::Scale::Uniform(0.55),
            ..Transform::default()
        },
        color: Vec3::new(0.9, 0.6, 0.3 + 0.2 * i as f32),
        surface: Some(Surface::Matte { ka: 0.2, kd: 0.8 }),
        shading_rate: None,
        displacement: Some(displacement),
        transform_close: None,
        keys: Vec::new(),
        sides: 2,
        reverse_orientation: false,
    }
}

fn shader_desc(
    file: PathBuf,
    bound: Option<f32>,
    parameters: BTreeMap<String, ShaderValue>,
) -> DisplacementDesc {
    DisplacementDesc {
        source: "shader".to_owned(),
        scale: 1.0,
        bound,
        tiling: 1.0,
        wgsl: None,
        file: Some(file),
        parameters,
    }
}

/// Three spheres: the every-input shader (one of them mirrored, so that
/// its `N` turns to the model's side), and `bumpy` over the same texture.
fn scene(spp: u32, bumps: &std::path::Path) -> PreparedScene {
    let mut scene = Scene::default();
    scene.resolution.width = 160;
    scene.resolution.height = 120;
    scene.spp = spp;
    scene.camera = Some(camera_down_z());
    scene.ambient = 0.1;
    let texture = ShaderValue::Text(bumps.to_string_lossy().into_owned());
    let every =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("shaders/every_input_displacement.wgsl");
    let parameters = BTreeMap::from([("bumps".to_owned(), texture.clone())]);
    scene.objects.push(sphere(
        0,
        shader_desc(every.clone(), Some(0.4), parameters.clone()),
    ));
    let mut mirrored = sphere(1, shader_desc(every, Some(0.4), parameters));
    mirrored.transform.scale = reyes::scene::Scale::PerAxis(Vec3::new(-0.55, 0.55, 0.55));
    scene.objects.push(mirrored);
    let bumpy = BTreeMap::from([
        ("Km".to_owned(), ShaderValue::Number(0.08)),
        ("texturename".to_owned(), texture),
    ]);
    scene
        .objects
        .push(sphere(2, shader_desc("builtin:bumpy".into(), None, bumpy)));
    scene.lights = vec![Light {
        direction: Vec3::new(1.0, -1.0, -1.0),
        intensity: 0.9,
        ..Light::default()
    }];
    let models = vec![bezier_sphere(); 3];
    let mut prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
    assert_eq!(prepared.shaders.shaders.len(), 2, "each shader file once");
    Arc::make_mut(&mut prepared.shaders.shaders[0]).cpu_displacement =
        Some(CpuDisplacement::new(every_input));
    prepared
}

#[gpu_test]
fn displacement_shaders_match_their_twins() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let dir =
        std::env::temp_dir().join(format!("reyes-displacement-shaders-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bumps = write_bumps(&dir);
    let mut renderer = renderer(gpu, GpuOptions::default());
    for spp in [1, 16] {
        let prepared = scene(spp, &bumps);
        let cpu = reference::try_render(&prepared).expect("the reference runs both twins");
        assert_eq!(
            cpu.stats.displacement_bound_exceeded, 0,
            "the declared bounds and bumpy's own hold"
        );
        let frame = renderer.render(&prepared).expect("GPU render");
        assert_eq!(frame.stats.displacement_bound_exceeded, 0);
        let a = agreement(&frame, &cpu);
        eprintln!("spp {spp}: {a:?}");
        a.assert_at_least("displacement shaders", 0.995, 0.99);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
