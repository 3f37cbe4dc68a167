//! The WGSL noise (`reyes::noise::noise_wgsl`, from
//! `shaders/reyes/library_noise.wgsl`) against the CPU's (`reyes::noise`)
//! at thousands of random points, negative and large coordinates
//! included: a plain compute shader evaluates every function at every
//! point.

use std::time::Duration;

use glam::{Vec2, Vec4};
use gpu_test::gpu_test;
use rand::{Rng, SeedableRng, rngs::StdRng};
use reyes::noise;
use scheduler::readback::read_buffer;
use scheduler::wgpu::{self, util::DeviceExt as _};
use tests::reyes_support::gpu_turn;

/// Results per point: noise1..4, vnoise3's three components, snoise4.
const PER_POINT: usize = 8;
/// The largest difference allowed between the CPU's and the GPU's value.
const TOLERANCE: f32 = 1.0e-5;

/// The compute shader: the noise library and one entry point.
fn shader(library: &str) -> String {
    format!(
        "{library}\n\
         @group(0) @binding(0) var<storage, read> points: array<vec4<f32>>;\n\
         @group(0) @binding(1) var<storage, read_write> results: array<f32>;\n\
         @compute @workgroup_size(64)\n\
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
             let i = id.x;\n\
             if i >= arrayLength(&points) {{ return; }}\n\
             let c = points[i];\n\
             let v = vnoise3(c.xyz);\n\
             let o = i * {PER_POINT}u;\n\
             results[o] = noise1(c.x);\n\
             results[o + 1u] = noise2(c.xy);\n\
             results[o + 2u] = noise3(c.xyz);\n\
             results[o + 3u] = noise4(c.xyz, c.w);\n\
             results[o + 4u] = v.x;\n\
             results[o + 5u] = v.y;\n\
             results[o + 6u] = v.z;\n\
             results[o + 7u] = snoise4(c.xyz, c.w);\n\
         }}\n"
    )
}

/// The CPU's results at `c`, in the shader's order.
fn cpu(c: Vec4) -> [f32; PER_POINT] {
    let p = c.truncate();
    let v = noise::vnoise3(p);
    [
        noise::noise1(c.x),
        noise::noise2(Vec2::new(c.x, c.y)),
        noise::noise3(p),
        noise::noise4(p, c.w),
        v.x,
        v.y,
        v.z,
        noise::snoise4(p, c.w),
    ]
}

/// Runs `library` over `points` on the shared device.
fn gpu_results(library: &str, points: &[Vec4]) -> Vec<f32> {
    let gpu = tests::gpu();
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("noise test"),
        source: wgpu::ShaderSource::Wgsl(shader(library).into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("noise test"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("noise points"),
        contents: bytemuck::cast_slice(points),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("noise results"),
        size: (points.len() * PER_POINT * 4) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("noise test"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((points.len() as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    let bytes = read_buffer(device, &gpu.queue, &output, Duration::from_secs(60))
        .expect("the results read back");
    bytemuck::cast_slice(&bytes).to_vec()
}

/// Random points: coordinates small, moderate, large and huge, of both
/// signs, some on the lattice and some just beside a cell boundary.
fn points(rng: &mut StdRng, n: usize) -> Vec<Vec4> {
    let mut coordinate = || match rng.random_range(0..6) {
        0 => rng.random_range(-4.0f32..4.0),
        1 => rng.random_range(-300.0..300.0),
        2 => rng.random_range(-1.0e5..1.0e5),
        3 => rng.random_range(-1.0e9..1.0e9),
        4 => rng.random_range(-600i32..600) as f32,
        _ => rng.random_range(-600i32..600) as f32 + rng.random_range(-1.0e-4..1.0e-4),
    };
    (0..n)
        .map(|_| Vec4::new(coordinate(), coordinate(), coordinate(), coordinate()))
        .collect()
}

/// The largest difference between the GPU's `results` and the CPU's at
/// `points`, and where.
fn max_difference(points: &[Vec4], results: &[f32]) -> (f32, Vec4, usize) {
    let mut worst = (0.0f32, Vec4::ZERO, 0);
    for (c, gpu) in points.iter().zip(results.chunks_exact(PER_POINT)) {
        for (k, (a, b)) in cpu(*c).iter().zip(gpu).enumerate() {
            let d = (a - b).abs();
            // A NaN on either side is a mismatch.
            if d.is_nan() || d > worst.0 {
                worst = (if d.is_nan() { f32::INFINITY } else { d }, *c, k);
            }
        }
    }
    worst
}

#[gpu_test]
fn wgsl_noise_matches_the_cpu() {
    let _turn = gpu_turn();
    let seed = tests::seed("noise_gpu");
    let mut rng = StdRng::seed_from_u64(seed);
    let points = points(&mut rng, 8192);
    let results = gpu_results(&noise::noise_wgsl(), &points);
    let (worst, at, k) = max_difference(&points, &results);
    eprintln!("noise GPU vs CPU: max |difference| {worst:e} (result {k} at {at})");
    assert!(
        worst <= TOLERANCE,
        "result {k} at {at} differs by {worst:e} (more than {TOLERANCE:e}); seed {seed}"
    );
    // The lattice points are exactly one half on the GPU too.
    let lattice: Vec<Vec4> = points.iter().map(|c| c.round()).collect();
    let halves = gpu_results(&noise::noise_wgsl(), &lattice);
    for (c, r) in lattice.iter().zip(halves.chunks_exact(PER_POINT)) {
        assert_eq!(&r[..7], &[0.5; 7], "at {c}");
    }
}

#[gpu_test]
fn the_comparison_catches_a_wrong_fade_curve() {
    // The cubic fade of Perlin's original noise instead of the quintic:
    // the same values at the lattice and the cell centres, different
    // elsewhere. The comparison must see it.
    let _turn = gpu_turn();
    let library = noise::noise_wgsl();
    let quintic = "return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);";
    assert!(library.contains(quintic), "the fade is where it was");
    let broken = library.replace(quintic, "return t * t * (3.0 - 2.0 * t);");
    let mut rng = StdRng::seed_from_u64(tests::seed("noise_gpu_broken"));
    let points = points(&mut rng, 1024);
    let (worst, at, k) = max_difference(&points, &gpu_results(&broken, &points));
    eprintln!("broken fade: max |difference| {worst:e} (result {k} at {at})");
    assert!(worst > 100.0 * TOLERANCE, "only {worst:e}");
}
