//! Shadow maps on the GPU against the CPU reference: frames of a sphere
//! over a plane lit by a spotlight and a distant light, each with a map
//! rendered from the light by the reference (`Aov::Z`), sharp and blurred;
//! and the megakernel's lookup itself (`shaders/reyes/library_shadow.wgsl`)
//! on random maps, points and filters against `ShadowMap::occlusion`.

use std::time::Duration;

use glam::{Mat4, Vec3, Vec4};
use gpu_test::gpu_test;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use reyes::camera::Camera;
use reyes::gpu::buffers::LightData;
use reyes::gpu::shadow_maps::{shadow_map_floats, shadow_table_entry, shadow_wgsl};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::rib::RibScene;
use reyes::shading::{PreparedLightKind, PreparedShadow};
use reyes::shadow::{LightShadowMaps, ShadowFilter, ShadowMap};
use scheduler::Item;
use scheduler::wgpu;
use tests::reyes_support::{agreement, gpu_turn, patient_renderer};

/// A unit sphere resting on a square of side 8 (y up), under a spotlight
/// and a distant light, both shining at it from above.
const SCENE: &str = "Format 96 72 1
PixelSamples 2 2
Projection \"perspective\" \"fov\" 40
WorldBegin
LightSource \"spotlight\" 1 \"from\" [2.5 5 1.5] \"to\" [0 0 0] \"intensity\" [30] \"coneangle\" [0.45]
LightSource \"distantlight\" 2 \"from\" [-1 2 -1] \"to\" [0 0 0] \"intensity\" [0.5]
Surface \"matte\"
AttributeBegin
Translate 0 1 0
Sphere 1 -1 1 360
AttributeEnd
Polygon \"P\" [-4 0 -4  -4 0 4  4 0 4  4 0 -4]
WorldEnd
";

/// The bias of the test's maps: the depth the plane spans across a texel
/// of the spotlight's map where it sees the plane most obliquely, and some.
const BIAS: f32 = 0.15;

/// The scene, seen from above and in front.
fn sphere_on_plane() -> PreparedScene {
    let rib = RibScene::from_text(SCENE, "shadow.rib").expect("the RIB reads");
    let mut scene = PreparedScene::new(&rib.scene, &rib.models).expect("scene prepares");
    scene.camera = Camera::new(
        Vec3::new(0.0, 4.0, 6.5),
        Vec3::new(0.0, 0.3, 0.0),
        Vec3::Y,
        40f32.to_radians(),
        96,
        72,
        0.5,
        50.0,
    );
    scene
}

/// The map `camera` sees of `scene`: the reference's depth frame.
fn map_from(scene: &PreparedScene, camera: Camera) -> ShadowMap {
    let mut from_light = scene.clone();
    from_light.camera = camera;
    from_light.aov = reyes::Aov::Z;
    let rendered = reference::render(&from_light);
    ShadowMap::from_camera(&camera, reyes::depth::depths(&rendered.linear))
}

/// `scene` with a map for each of its lights (a perspective one from the
/// spotlight over its cone, an orthographic one along the distant light)
/// looked up with `filter`.
fn with_shadows(scene: &PreparedScene, filter: ShadowFilter) -> PreparedScene {
    let mut shadowed = scene.clone();
    shadowed.shadow_maps.clear();
    for light in &mut shadowed.lights {
        let camera = match light.kind {
            PreparedLightKind::Spot => Camera::new(
                light.to_light,
                light.to_light + light.axis,
                Vec3::Y,
                2.0 * light.cos_outside.acos() + 0.1,
                128,
                128,
                1.0,
                20.0,
            ),
            PreparedLightKind::Distant => Camera::new(
                10.0 * light.to_light,
                Vec3::ZERO,
                Vec3::Y,
                1.0,
                128,
                128,
                1.0,
                30.0,
            )
            .orthographic(10.0),
            PreparedLightKind::Point => unreachable!("the scene has no point light"),
        };
        light.shadow = Some(PreparedShadow {
            first_map: shadowed.shadow_maps.len() as u32,
            map_count: 1,
            filter,
        });
        shadowed.shadow_maps.push(map_from(scene, camera));
    }
    assert_eq!(shadowed.shadow_maps.len(), 2, "a map per light");
    shadowed
}

/// Fraction of pixels whose channels differ by more than 10/255.
fn changed_fraction(a: &reference::Rendered, b: &reference::Rendered) -> f64 {
    let (a, b) = (a.image.as_raw(), b.image.as_raw());
    let changed = a
        .chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 10))
        .count();
    changed as f64 / (a.len() / 4) as f64
}

#[gpu_test]
fn shadowed_frames_match_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = patient_renderer(gpu);
    let scene = sphere_on_plane();
    let unshadowed = reference::render(&scene);
    for (what, filter) in [
        (
            "sharp",
            ShadowFilter {
                bias: BIAS,
                ..ShadowFilter::default()
            },
        ),
        (
            "blurred",
            ShadowFilter {
                samples: 16,
                blur: 0.03,
                bias: BIAS,
                ..ShadowFilter::default()
            },
        ),
    ] {
        let shadowed = with_shadows(&scene, filter);
        let cpu = reference::render(&shadowed);
        // The shadows darken a good part of the frame: the comparison below
        // would catch a GPU that ignored them.
        let darkened = changed_fraction(&cpu, &unshadowed);
        println!("{what}: the shadows change {darkened:.4} of the pixels");
        assert!(darkened > 0.05, "{what}: the shadows change {darkened}");
        // The distant light's map alone casts a visible shadow too.
        let mut distant_only = shadowed.clone();
        for light in &mut distant_only.lights {
            if light.kind == PreparedLightKind::Spot {
                light.shadow = None;
            }
        }
        let distant = changed_fraction(&reference::render(&distant_only), &unshadowed);
        assert!(
            distant > 0.01,
            "{what}: the distant light's shadow changes {distant}"
        );
        let frame = renderer.render(&shadowed).expect("GPU render");
        assert!(renderer.variant().shadowed, "{what}: the shadow lookup");
        let a = agreement(&frame, &cpu);
        println!(
            "{what}: {:.4} of {} pixels within 2/255 of the reference (max diff {}, IoU {:.5})",
            a.within_2, a.both, a.max_diff, a.iou
        );
        a.assert_at_least(what, 0.995, 0.99);
    }
}

// ------------------------------------------------------------ lookups

/// The WGSL math helpers the lookup uses.
const MATH_WGSL: &str = include_str!("../../shaders/reyes/library_math.wgsl");

/// A compute module that writes, per point `(x, y, z, light)`, the
/// megakernel's `light_visibility` of that light there.
fn lookup_module() -> String {
    format!(
        "{}\n{MATH_WGSL}\n
@group(0) @binding(0) var<storage, read> height_texels: array<f32>;
@group(0) @binding(1) var<storage, read> lights: array<Light>;
@group(0) @binding(2) var<storage, read> points: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> visibility: array<f32>;
{}
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
    if (id.x < arrayLength(&points)) {{
        let p = points[id.x];
        visibility[id.x] = light_visibility(lights[u32(p.w)], p.xyz);
    }}
}}
",
        LightData::wgsl_declarations(),
        shadow_wgsl(true)
    )
}

/// A random light camera: perspective or orthographic, somewhere around
/// the origin, and the camera-space point at normalized device `(x, y)`
/// and depth `d` in front of it.
struct RandomView {
    view: Mat4,
    proj: Mat4,
    /// Half the view's width and height at depth 1 (perspective) or
    /// everywhere (orthographic).
    half: (f32, f32),
    perspective: bool,
}

impl RandomView {
    fn new(rng: &mut StdRng, aspect: f32) -> Self {
        let eye = Vec3::new(
            rng.random_range(-5.0..5.0),
            rng.random_range(2.0..8.0),
            rng.random_range(-5.0..5.0),
        );
        let target = Vec3::new(
            rng.random_range(-1.0..1.0),
            0.0,
            rng.random_range(-1.0..1.0),
        );
        let view = Mat4::look_at_rh(eye, target, Vec3::Y);
        let perspective = rng.random_bool(0.6);
        let (proj, half) = if perspective {
            let fov: f32 = rng.random_range(0.3..1.4);
            let t = (0.5 * fov).tan();
            (
                Mat4::perspective_rh(fov, aspect, 0.5, 40.0),
                (t * aspect, t),
            )
        } else {
            let h: f32 = rng.random_range(2.0..10.0);
            (
                Mat4::orthographic_rh(
                    -0.5 * h * aspect,
                    0.5 * h * aspect,
                    -0.5 * h,
                    0.5 * h,
                    0.5,
                    40.0,
                ),
                (0.5 * h * aspect, 0.5 * h),
            )
        };
        RandomView {
            view,
            proj,
            half,
            perspective,
        }
    }

    /// The world point at normalized device `(x, y)` and view depth `d`.
    fn point(&self, x: f32, y: f32, d: f32) -> Vec3 {
        let scale = if self.perspective { d } else { 1.0 };
        let camera = Vec4::new(x * self.half.0 * scale, y * self.half.1 * scale, -d, 1.0);
        (self.view.inverse() * camera).truncate()
    }
}

/// A random map with depths between 2 and 12 (a fifth of them empty), and
/// its view.
fn random_map(rng: &mut StdRng) -> (ShadowMap, RandomView) {
    let (width, height) = (rng.random_range(1..40u32), rng.random_range(1..40u32));
    let view = RandomView::new(rng, width as f32 / height as f32);
    let depths = (0..width * height)
        .map(|_| {
            if rng.random_bool(0.2) {
                f32::INFINITY
            } else {
                rng.random_range(2.0..12.0)
            }
        })
        .collect();
    let map = ShadowMap {
        width,
        height,
        depths,
        world_to_camera: view.view,
        world_to_clip: view.proj * view.view,
    };
    (map, view)
}

fn random_filter(rng: &mut StdRng) -> ShadowFilter {
    ShadowFilter {
        samples: rng.random_range(1..300),
        width: rng.random_range(0.0..4.0),
        blur: if rng.random_bool(0.5) {
            0.0
        } else {
            rng.random_range(0.0..0.2)
        },
        bias: rng.random_range(0.0..0.5),
    }
}

/// A storage buffer holding `data`.
fn storage(device: &wgpu::Device, data: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("shadow lookup test"),
        contents: data,
        usage: wgpu::BufferUsages::STORAGE | usage,
    })
}

/// Runs [`lookup_module`] over `points` with `lights` and `floats` (the
/// height_texels buffer).
fn gpu_visibility(lights: &[LightData], floats: &[f32], points: &[Vec4]) -> Vec<f32> {
    let gpu = tests::gpu();
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("shadow lookup test"),
        source: wgpu::ShaderSource::Wgsl(lookup_module().into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("shadow lookup test"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let none = wgpu::BufferUsages::empty();
    let texels = storage(device, bytemuck::cast_slice(floats), none);
    let lights = storage(device, bytemuck::cast_slice(lights), none);
    let points_buffer = storage(device, bytemuck::cast_slice(points), none);
    let out = storage(
        device,
        &vec![0u8; 4 * points.len()],
        wgpu::BufferUsages::COPY_SRC,
    );
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("shadow lookup test"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: texels.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: lights.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: points_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: out.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups((points.len() as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    let bytes =
        scheduler::readback::read_buffer(device, &gpu.queue, &out, Duration::from_secs(600))
            .expect("the lookups read back");
    bytemuck::cast_slice(&bytes).to_vec()
}

/// The [`LightData`] of a light with `map_count` maps from `first_map` of
/// the table at float `table`, looked up with `filter`.
fn shadowed_light(table: u64, first_map: u32, map_count: u32, filter: ShadowFilter) -> LightData {
    LightData {
        to_light: Vec4::ZERO,
        radiance: Vec4::ONE,
        axis: Vec4::ZERO,
        kind: 0,
        cos_outside: 0.0,
        cos_inside: 0.0,
        beam_distribution: 0.0,
        shadow_table: shadow_table_entry(table, first_map),
        shadow_maps: map_count,
        shadow_side: filter.grid_side(),
        shadow_width: filter.width,
        shadow_blur: filter.blur,
        shadow_bias: filter.bias,
        pad0: 0,
        pad1: 0,
    }
}

#[gpu_test]
fn lookups_match_the_reference_occlusion() {
    let _turn = gpu_turn();
    let mut rng = StdRng::seed_from_u64(tests::seed("lookups_match_the_reference_occlusion"));
    // Light 0: one map; light 1: three (a point light's first that holds
    // the point counts); light 2: none, so no shadow.
    let views: Vec<(ShadowMap, RandomView)> = (0..4).map(|_| random_map(&mut rng)).collect();
    let maps: Vec<ShadowMap> = views.iter().map(|(m, _)| m.clone()).collect();
    let filters = [random_filter(&mut rng), random_filter(&mut rng)];
    println!("filters {filters:?}");
    // The table starts after some unrelated floats, as in the megakernel.
    let base = 7u64;
    let mut floats = vec![0.0f32; base as usize];
    floats.extend(shadow_map_floats(&maps, base));
    let lights = [
        shadowed_light(base, 0, 1, filters[0]),
        shadowed_light(base, 1, 3, filters[1]),
        shadowed_light(base, 0, 0, filters[0]),
    ];
    let mut points = Vec::new();
    let mut expected = Vec::new();
    for _ in 0..8192 {
        let light: u32 = rng.random_range(0..3);
        let map = match light {
            0 => 0,
            1 => rng.random_range(1..4),
            _ => rng.random_range(0..4),
        };
        // Mostly inside the map, some beyond its edges, some behind the light.
        let (x, y) = (
            rng.random_range(-1.2..1.2f32),
            rng.random_range(-1.2..1.2f32),
        );
        let d = rng.random_range(-1.0..13.0f32);
        let p = views[map].1.point(x, y, d);
        let reference = match light {
            2 => 1.0,
            0 => LightShadowMaps {
                maps: &maps[0..1],
                filter: filters[0],
            }
            .visibility(p),
            _ => LightShadowMaps {
                maps: &maps[1..4],
                filter: filters[1],
            }
            .visibility(p),
        };
        points.push(p.extend(light as f32));
        expected.push(reference);
    }
    let partial = expected.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
    let lit = expected.iter().filter(|&&v| v == 1.0).count();
    println!("{partial} points partly shadowed, {lit} lit");
    // An eighth of the points or more in penumbrae: narrow random filters
    // (seed 7553306397150960153: 1969 of 8192) still test the filter.
    assert!(partial > 1000 && lit > 500, "the points test the filter");
    let got = gpu_visibility(&lights, &floats, &points);
    let mut worst = (0.0f32, 0usize);
    let mut close = 0usize;
    for (i, (g, e)) in got.iter().zip(&expected).enumerate() {
        // A NaN from the GPU counts as far off.
        let diff = if g.is_nan() {
            f32::INFINITY
        } else {
            (g - e).abs()
        };
        if diff <= 1e-4 {
            close += 1;
        } else {
            eprintln!("point {i} {:?}: GPU {g}, reference {e}", points[i]);
        }
        if diff > worst.0 {
            worst = (diff, i);
        }
    }
    let fraction = close as f64 / points.len() as f64;
    println!(
        "{fraction:.5} of {} lookups within 1e-4 of the reference (worst {} at point {})",
        points.len(),
        worst.0,
        worst.1
    );
    // A float contraction on the GPU may move a grid sample across a
    // texel's depth test, rarely.
    assert!(fraction >= 0.999, "{fraction} of the lookups agree");
}
