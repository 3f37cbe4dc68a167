//! `texture_sample` (`shaders/reyes/library_texture.wgsl`) on a real
//! adapter against the CPU filter (`reyes::texture::TextureSet::sample`):
//! random positions and footprints (magnified, minified through every
//! level, past the coarsest) on random textures of every wrap mode, of
//! power-of-two and other sizes, float and 8-bit sRGB. Likewise
//! `texture_environment` against `TextureSet::environment`: random
//! directions (the poles and the seam among them) and changes of direction.

use std::path::Path;
use std::time::Duration;

use glam::{Vec2, Vec3, Vec4};
use gpu_test::gpu_test;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use reyes::texture::{TEXTURE_WGSL, TextureDesc, TextureId, TextureInfo, TextureSet, Wrap};
use scheduler::{Item, readback::read_buffer, wgpu};

/// One lookup, WGSL struct `Query`.
#[scheduler::item]
#[derive(Debug)]
struct Query {
    id: u32,
    pad: u32,
    st: Vec2,
    axis_a: Vec2,
    axis_b: Vec2,
}

/// One environment lookup, WGSL struct `EnvironmentQuery` (the `w`s are
/// not read).
#[scheduler::item]
#[derive(Debug)]
struct EnvironmentQuery {
    id: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    r: Vec4,
    dr_du: Vec4,
    dr_dv: Vec4,
}

/// Queries per run.
const QUERIES: usize = 6000;

/// Largest difference accepted between the GPU and the CPU. Both read the
/// same f16 texels through the same operations; only the rounding of
/// `log2`, `sqrt` and of contracted multiply-adds may differ.
const TOLERANCE: f32 = 1e-4;

/// The module: the structs (`query` declares the queries' type,
/// `query_type`), the two globals `texture_sample` reads, the library, and
/// one invocation per query, which stores `lookup` (an expression of the
/// query `q`).
fn module_source(query: &str, query_type: &str, lookup: &str) -> String {
    format!(
        "{}\n{}\n\
         @group(0) @binding(0) var<storage, read> texture_infos: array<TextureInfo>;\n\
         @group(0) @binding(1) var<storage, read> texels: array<vec2<u32>>;\n\
         fn texture_count() -> u32 {{ return arrayLength(&texture_infos); }}\n\
         fn texture_info(id: u32) -> TextureInfo {{ return texture_infos[id]; }}\n\
         fn texture_packed_count() -> u32 {{ return arrayLength(&texels); }}\n\
         fn texture_packed(at: u32) -> vec2<u32> {{ return texels[at]; }}\n\
         @group(0) @binding(2) var<storage, read> queries: array<{query_type}>;\n\
         @group(0) @binding(3) var<storage, read_write> results: array<vec4<f32>>;\n\
         {TEXTURE_WGSL}\n\
         @compute @workgroup_size(64)\n\
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
             if (id.x >= arrayLength(&queries)) {{\n\
                 return;\n\
             }}\n\
             let q = queries[id.x];\n\
             results[id.x] = {lookup};\n\
         }}\n",
        TextureInfo::wgsl_declarations(),
        query,
    )
}

/// `texture_sample` of every query on the GPU.
fn run_on_gpu(gpu: &scheduler::Gpu, set: &TextureSet, queries: &[Query]) -> Vec<Vec4> {
    let source = module_source(
        &Query::wgsl_declarations(),
        "Query",
        "texture_sample(q.id, q.st, q.axis_a, q.axis_b)",
    );
    run_module(
        gpu,
        set,
        bytemuck::cast_slice(queries),
        queries.len(),
        source,
    )
}

/// The compiled `source` over `count` queries (`queries`, their bytes).
fn run_module(
    gpu: &scheduler::Gpu,
    set: &TextureSet,
    queries: &[u8],
    count: usize,
    source: String,
) -> Vec<Vec4> {
    use wgpu::util::DeviceExt;
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("texture_sample test"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
    let pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("texture_sample test"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
    let (infos, texels) = set.gpu_tables();
    let buffer = |label: &str, contents: &[u8]| {
        gpu.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            })
    };
    let infos = buffer("texture_infos", bytemuck::cast_slice(&infos));
    let texels = buffer("texels", bytemuck::cast_slice(texels));
    let query_buffer = buffer("queries", queries);
    let results = buffer("results", &vec![0xffu8; count * 16]);
    let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("texture_sample test"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[&infos, &texels, &query_buffer, &results]
            .iter()
            .enumerate()
            .map(|(binding, buffer)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect::<Vec<_>>(),
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(count.div_ceil(64) as u32, 1, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    let bytes = read_buffer(&gpu.device, &gpu.queue, &results, Duration::from_secs(120))
        .expect("results read back");
    bytemuck::cast_slice::<u8, [f32; 4]>(&bytes)
        .iter()
        .map(|&v| Vec4::from_array(v))
        .collect()
}

/// A `width x height` texture of random linear values in `[0, 2)`.
fn random_texture(
    set: &mut TextureSet,
    rng: &mut StdRng,
    (width, height): (u32, u32),
    wrap_s: Wrap,
    wrap_t: Wrap,
) -> TextureId {
    let texels = (0..width * height)
        .map(|_| Vec4::from_array([(); 4].map(|_| rng.random_range(0.0..2.0))))
        .collect();
    set.add_linear(Path::new("random"), width, height, texels, wrap_s, wrap_t)
        .expect("texture fits")
}

/// A random 8-bit sRGB PNG, written and loaded like a scene's texture.
fn random_png(
    set: &mut TextureSet,
    rng: &mut StdRng,
    (width, height): (u32, u32),
    wrap: Wrap,
) -> TextureId {
    let dir = std::env::temp_dir().join(format!("texture-gpu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{width}x{height}-{wrap:?}.png"));
    let bytes: Vec<u8> = (0..width * height * 4).map(|_| rng.random()).collect();
    image::save_buffer(&path, &bytes, width, height, image::ColorType::Rgba8).unwrap();
    let id = set
        .add(&TextureDesc::new(&path).with_wrap(wrap))
        .expect("PNG loads");
    std::fs::remove_file(&path).unwrap();
    id
}

/// A footprint axis: a random direction, a length log-uniform between
/// 1e-4 and 4 (in s and t units), now and then zero.
fn random_axis(rng: &mut StdRng) -> Vec2 {
    if rng.random_range(0..20) == 0 {
        return Vec2::ZERO;
    }
    let angle = rng.random_range(0.0..std::f32::consts::TAU);
    let length = 10f32.powf(rng.random_range(-4.0..0.6));
    Vec2::from_angle(angle) * length
}

#[gpu_test]
fn texture_sample_matches_the_cpu_filter() {
    let seed = tests::seed("texture_sample_matches_the_cpu_filter");
    let mut rng = StdRng::seed_from_u64(seed);
    let mut set = TextureSet::default();
    let mut ids = vec![
        random_texture(&mut set, &mut rng, (64, 64), Wrap::Periodic, Wrap::Periodic),
        random_texture(&mut set, &mut rng, (37, 23), Wrap::Clamp, Wrap::Clamp),
        random_texture(&mut set, &mut rng, (100, 7), Wrap::Black, Wrap::Black),
        random_texture(&mut set, &mut rng, (1, 13), Wrap::Periodic, Wrap::Black),
        random_texture(&mut set, &mut rng, (129, 66), Wrap::Clamp, Wrap::Periodic),
        random_png(&mut set, &mut rng, (45, 30), Wrap::Periodic),
        random_png(&mut set, &mut rng, (16, 9), Wrap::Black),
    ];
    // An id past the table samples black on both sides.
    ids.push(TextureId(set.len() as u32));
    let queries: Vec<Query> = (0..QUERIES)
        .map(|_| Query {
            id: ids[rng.random_range(0..ids.len())].0,
            pad: 0,
            st: Vec2::new(rng.random_range(-1.5..2.5), rng.random_range(-1.5..2.5)),
            axis_a: random_axis(&mut rng),
            axis_b: random_axis(&mut rng),
        })
        .collect();
    let gpu = run_on_gpu(tests::gpu(), &set, &queries);
    let mut worst = (0.0f32, 0);
    for (k, (q, &got)) in queries.iter().zip(&gpu).enumerate() {
        let want = set.sample(TextureId(q.id), q.st, q.axis_a, q.axis_b);
        let error = (got - want).abs().max_element();
        assert!(
            error <= TOLERANCE,
            "seed {seed}: query {k} {q:?} (texture {:?}): GPU {got}, CPU {want}",
            set.info(TextureId(q.id))
        );
        if error > worst.0 {
            worst = (error, k);
        }
    }
    eprintln!(
        "{} queries, largest difference {:e} (query {})",
        queries.len(),
        worst.0,
        worst.1
    );
}

/// Largest difference accepted for an environment lookup: `atan2` is not
/// correctly rounded on a GPU (Vulkan allows thousands of ulps), so `s` and
/// `t` may differ in their last bits, and that moves the lookup on random
/// texels (up to 2 apart) a little. Lavapipe differs by 5e-5 at most.
const ENVIRONMENT_TOLERANCE: f32 = 2e-3;

/// A direction: random, or now and then a pole, the seam (+x, from
/// either side) or zero.
fn random_direction(rng: &mut StdRng) -> Vec3 {
    match rng.random_range(0..24) {
        0 => Vec3::Z * rng.random_range(0.1..3.0),
        1 => -Vec3::Z,
        2 => Vec3::new(1.0, 0.0, rng.random_range(-1.0..1.0)),
        3 => Vec3::new(1.0, -1e-7, rng.random_range(-1.0..1.0)),
        4 => Vec3::ZERO,
        _ => Vec3::from_array([(); 3].map(|_| rng.random_range(-2.0..2.0))),
    }
}

/// A change of direction: zero now and then, else random, of a length
/// log-uniform between 1e-4 and 1.
fn random_change(rng: &mut StdRng) -> Vec3 {
    if rng.random_range(0..6) == 0 {
        return Vec3::ZERO;
    }
    let d = Vec3::from_array([(); 3].map(|_| rng.random_range(-1.0..1.0))).normalize_or_zero();
    d * 10f32.powf(rng.random_range(-4.0..0.0))
}

#[gpu_test]
fn texture_environment_matches_the_cpu_lookup() {
    let seed = tests::seed("texture_environment_matches_the_cpu_lookup");
    let mut rng = StdRng::seed_from_u64(seed);
    let mut set = TextureSet::default();
    // Wrap modes the lookup overrides (periodic in s, clamped in t).
    let mut ids = vec![
        random_texture(&mut set, &mut rng, (64, 32), Wrap::Black, Wrap::Black),
        random_texture(&mut set, &mut rng, (37, 23), Wrap::Clamp, Wrap::Periodic),
        random_png(&mut set, &mut rng, (48, 24), Wrap::Periodic),
    ];
    ids.push(TextureId(set.len() as u32));
    let queries: Vec<EnvironmentQuery> = (0..QUERIES)
        .map(|_| EnvironmentQuery {
            id: ids[rng.random_range(0..ids.len())].0,
            pad0: 0,
            pad1: 0,
            pad2: 0,
            r: random_direction(&mut rng).extend(0.0),
            dr_du: random_change(&mut rng).extend(0.0),
            dr_dv: random_change(&mut rng).extend(0.0),
        })
        .collect();
    let source = module_source(
        &EnvironmentQuery::wgsl_declarations(),
        "EnvironmentQuery",
        "texture_environment(q.id, q.r.xyz, q.dr_du.xyz, q.dr_dv.xyz)",
    );
    let gpu = run_module(
        tests::gpu(),
        &set,
        bytemuck::cast_slice(&queries),
        queries.len(),
        source,
    );
    let mut worst = (0.0f32, 0);
    for (k, (q, &got)) in queries.iter().zip(&gpu).enumerate() {
        let want = set.environment(
            TextureId(q.id),
            q.r.truncate(),
            q.dr_du.truncate(),
            q.dr_dv.truncate(),
        );
        let error = (got - want).abs().max_element();
        assert!(
            error <= ENVIRONMENT_TOLERANCE,
            "seed {seed}: query {k} {q:?}: GPU {got}, CPU {want}"
        );
        if error > worst.0 {
            worst = (error, k);
        }
    }
    eprintln!(
        "{} environment queries, largest difference {:e} (query {})",
        queries.len(),
        worst.0,
        worst.1
    );
}
