//! `shadow(id, P)` in a user's WGSL surface shader (RenderMan's
//! `shadow(name, P)`): a square seen from straight above, whose shader
//! darkens it by a shadow map of a sphere floating over it, made by the
//! test from the sphere's equation along a random distant light. The
//! shadow on the GPU is checked against the sphere's projection along the
//! light (the arithmetic of a ray and a sphere, per pixel) and against the
//! shader's Rust twin in the CPU reference, sharp and blurred.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec3};
use gpu_test::gpu_test;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use reyes::gpu::GpuOptions;
use reyes::model::{Model, Patch};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{CameraDesc, Projection, Scene, SceneObject, ShaderValue, Surface};
use reyes::shadow::ShadowMap;
use reyes::surface_shader::{CpuSurface, ShadingContext, ShadingHost, ShadowDesc, SurfaceOutput};
use tests::reyes_support::{agreement, gpu_turn, renderer};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;
/// The view's height in world units (orthographic, looking down -y).
const VIEW_HEIGHT: f32 = 8.0;
/// The shadow map's side in texels, and its half-width in world units.
const MAP_SIZE: u32 = 512;
const MAP_HALF: f32 = 3.0;

/// The Rust twin of tests/shaders/shadowed.wgsl.
fn shadowed(ctx: &ShadingContext, host: &dyn ShadingHost, slots: &[[f32; 4]]) -> SurfaceOutput {
    let lit = (1.0 - host.shadow(slots[0], ctx.p)) * (1.0 - host.shadow(slots[1], ctx.p));
    SurfaceOutput {
        ci: ctx.cs * lit,
        oi: ctx.os,
    }
}

/// The sphere that casts the shadow, and the unit direction towards the
/// light.
#[derive(Debug, Clone, Copy)]
struct Caster {
    center: Vec3,
    radius: f32,
    to_light: Vec3,
}

impl Caster {
    fn random(rng: &mut StdRng) -> Caster {
        let elevation = rng.random_range(55f32..75.0).to_radians();
        let azimuth = rng.random_range(0.0..std::f32::consts::TAU);
        Caster {
            center: Vec3::new(
                rng.random_range(-0.8..0.8),
                rng.random_range(1.2..2.0),
                rng.random_range(-0.8..0.8),
            ),
            radius: rng.random_range(0.5..0.9),
            to_light: Vec3::new(
                elevation.cos() * azimuth.cos(),
                elevation.sin(),
                elevation.cos() * azimuth.sin(),
            ),
        }
    }

    /// Where the ray from `origin` along unit `direction` first meets the
    /// sphere (its distance), if it does.
    fn hit(&self, origin: Vec3, direction: Vec3) -> Option<f32> {
        let to_center = origin - self.center;
        let b = to_center.dot(direction);
        let c = to_center.length_squared() - self.radius * self.radius;
        let discriminant = b * b - c;
        if discriminant < 0.0 {
            return None;
        }
        let t = -b - discriminant.sqrt();
        (t > 0.0).then_some(t)
    }

    /// Whether the sphere stands between the ground point `p` and the light.
    fn shadows(&self, p: Vec3) -> bool {
        self.hit(p, self.to_light).is_some()
    }

    /// The map the light sees: an orthographic view along the light, centred
    /// on the sphere, each texel holding the depth of the sphere along its
    /// ray through the texel's centre (+inf where the ray misses).
    fn map(&self) -> ShadowMap {
        let eye = self.center + 10.0 * self.to_light;
        let world_to_camera = Mat4::look_at_rh(eye, self.center, Vec3::Y);
        let projection = Mat4::orthographic_rh(-MAP_HALF, MAP_HALF, -MAP_HALF, MAP_HALF, 0.1, 50.0);
        let camera_to_world = world_to_camera.inverse();
        let depths = (0..MAP_SIZE * MAP_SIZE)
            .map(|k| {
                let (i, j) = (k % MAP_SIZE, k / MAP_SIZE);
                let x = ((i as f32 + 0.5) / MAP_SIZE as f32 * 2.0 - 1.0) * MAP_HALF;
                let y = (1.0 - (j as f32 + 0.5) / MAP_SIZE as f32 * 2.0) * MAP_HALF;
                let origin = camera_to_world.transform_point3(Vec3::new(x, y, 0.0));
                self.hit(origin, -self.to_light).unwrap_or(f32::INFINITY)
            })
            .collect();
        ShadowMap {
            width: MAP_SIZE,
            height: MAP_SIZE,
            depths,
            world_to_camera,
            world_to_clip: projection * world_to_camera,
        }
    }
}

/// The ground: a flat square of side 12 in y = 0.
fn ground() -> Model {
    Model {
        patches: vec![Patch {
            points: std::array::from_fn(|k| {
                Vec3::new(
                    ((k % 4) as f32 / 3.0 - 0.5) * 12.0,
                    0.0,
                    ((k / 4) as f32 / 3.0 - 0.5) * 12.0,
                )
            }),
        }],
        ..Model::default()
    }
}

/// The ground point at the centre of pixel `(x, y)` offset by `(dx, dy)`
/// pixels: the view looks down -y with -z up the image.
fn ground_point(x: u32, y: u32, dx: f32, dy: f32) -> Vec3 {
    let scale = VIEW_HEIGHT / HEIGHT as f32;
    Vec3::new(
        (x as f32 + dx - 0.5 * WIDTH as f32) * scale,
        0.0,
        (y as f32 + dy - 0.5 * HEIGHT as f32) * scale,
    )
}

/// The fraction of each pixel (8 x 8 points) the sphere shadows.
fn projected_shadow(caster: &Caster) -> Vec<f32> {
    (0..WIDTH * HEIGHT)
        .map(|k| {
            let (x, y) = (k % WIDTH, k / WIDTH);
            let mut hits = 0;
            for j in 0..8 {
                for i in 0..8 {
                    let p = ground_point(x, y, (i as f32 + 0.5) / 8.0, (j as f32 + 0.5) / 8.0);
                    hits += u32::from(caster.shadows(p));
                }
            }
            hits as f32 / 64.0
        })
        .collect()
}

/// The ground under the map `key`, prepared, with the twin.
fn prepared(key: ShadowDesc) -> PreparedScene {
    let mut scene = Scene::default();
    scene.resolution.width = WIDTH;
    scene.resolution.height = HEIGHT;
    scene.spp = 16;
    // The shader runs at the grid's vertices and the pixels see it
    // interpolated, so a sharp shadow's area is counted in shading points:
    // at rate 1 (a point per pixel) a shadow of 250 pixels comes out up to
    // 5% off its projection by where the lattice falls, at 0.25 within 1%.
    scene.shading_rate = 0.25;
    scene.camera = Some(CameraDesc {
        eye: Vec3::new(0.0, 10.0, 0.0),
        target: Vec3::ZERO,
        up: Vec3::NEG_Z,
        fov_y_degrees: 40.0,
        near: 0.1,
        far: 100.0,
        projection: Projection::Orthographic,
        ortho_height: Some(VIEW_HEIGHT),
    });
    scene.objects.push(SceneObject {
        color: Vec3::ONE,
        surface: Some(Surface::Wgsl {
            file: PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("shaders/shadowed.wgsl"),
            parameters: BTreeMap::from([("key".to_owned(), ShaderValue::Shadow(key))]),
        }),
        ..SceneObject::new("ground")
    });
    let mut prepared = PreparedScene::new(&scene, &[ground()]).expect("scene prepares");
    assert_eq!(prepared.shadow_maps.len(), 1, "the map is read");
    Arc::make_mut(&mut prepared.shaders.shaders[0]).cpu = Some(CpuSurface::new(shadowed));
    prepared
}

/// Each pixel's occlusion: 1 - its red channel (Cs is white).
fn occlusion(linear: &image::Rgba32FImage) -> Vec<f32> {
    linear.pixels().map(|p| 1.0 - p[0]).collect()
}

/// Intersection over union of the pixels over half shadowed.
fn iou(a: &[f32], b: &[f32]) -> f64 {
    let (mut both, mut either) = (0u32, 0u32);
    for (&x, &y) in a.iter().zip(b) {
        both += u32::from(x > 0.5 && y > 0.5);
        either += u32::from(x > 0.5 || y > 0.5);
    }
    f64::from(both) / f64::from(either.max(1))
}

/// The shadow's area (in pixels, partial pixels by their fraction) and its
/// centroid.
fn area_and_centroid(occlusion: &[f32]) -> (f64, [f64; 2]) {
    let (mut area, mut x, mut y) = (0.0, 0.0, 0.0);
    for (k, &o) in occlusion.iter().enumerate() {
        let o = f64::from(o.clamp(0.0, 1.0));
        area += o;
        x += o * f64::from(k as u32 % WIDTH);
        y += o * f64::from(k as u32 / WIDTH);
    }
    (area, [x / area, y / area])
}

/// Pixels neither lit nor in shadow: the penumbra.
fn penumbra(occlusion: &[f32]) -> usize {
    occlusion.iter().filter(|&&o| o > 0.1 && o < 0.9).count()
}

fn write_map(dir: &Path, map: &ShadowMap) -> PathBuf {
    let path = dir.join("key.shad");
    std::fs::write(&path, reyes::shadow::file::encode(map, "shadow").unwrap()).unwrap();
    path
}

#[gpu_test]
fn a_shader_shadow_lookup_casts_the_projected_sphere() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let seed = tests::seed("a_shader_shadow_lookup_casts_the_projected_sphere");
    let caster = Caster::random(&mut StdRng::seed_from_u64(seed));
    eprintln!("{caster:?}");
    let dir = std::env::temp_dir().join(format!("reyes-user-shadow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = write_map(&dir, &caster.map());
    let expected = projected_shadow(&caster);
    let mut renderer = renderer(gpu, GpuOptions::default());
    let mut penumbrae = Vec::new();
    for blur in [0.0, 0.05] {
        let scene = prepared(ShadowDesc {
            blur: Some(blur),
            ..ShadowDesc::new(&path)
        });
        let frame = renderer.render(&scene).expect("GPU render");
        let cpu = reference::try_render(&scene).expect("the reference runs the twin");
        let a = agreement(&frame, &cpu);
        eprintln!("blur {blur}: GPU against the twin: {a:?}");
        a.assert_at_least(&format!("shadow() at blur {blur}"), 0.995, 0.99);
        let gpu_occlusion = occlusion(&frame.linear);
        let (area, centroid) = area_and_centroid(&gpu_occlusion);
        let (expected_area, expected_centroid) = area_and_centroid(&expected);
        let overlap = iou(&gpu_occlusion, &expected);
        let off_centre =
            (centroid[0] - expected_centroid[0]).hypot(centroid[1] - expected_centroid[1]);
        eprintln!(
            "blur {blur}: area {area:.1} pixels against the projection's {expected_area:.1}, \
             centroid {off_centre:.3} pixels off, IoU {overlap:.4}, penumbra {} pixels",
            penumbra(&gpu_occlusion)
        );
        assert!(
            expected_area > 100.0,
            "the shadow lies in the view: {expected_area} pixels"
        );
        // The blurred shadow spreads over its edge evenly: its area and
        // centre stay the sharp one's.
        let area_error = (area - expected_area).abs() / expected_area;
        let (most_area_error, most_off, least_iou) = if blur == 0.0 {
            (0.02, 0.15, 0.92)
        } else {
            (0.03, 0.25, 0.9)
        };
        assert!(
            area_error <= most_area_error && off_centre <= most_off && overlap >= least_iou,
            "blur {blur}: area off by {area_error}, centroid by {off_centre} pixels, IoU {overlap} \
             against the sphere's projection (seed {seed})"
        );
        penumbrae.push(penumbra(&gpu_occlusion));
    }
    assert!(
        penumbrae[1] >= 2 * penumbrae[0],
        "blur widens the penumbra: {penumbrae:?} pixels (seed {seed})"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
