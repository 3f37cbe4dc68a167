//! RenderMan's `environment()` and the built-in `shinymetal`:
//!
//! * a flat mirror (`Ka = Ks = 0`, `Kr = 1`) facing the camera under a
//!   smooth environment shows, at each pixel, the colour the test works out
//!   from the reflected direction `D = I - 2 (I.N) N` with the
//!   specification's latitude-longitude convention, on the GPU and in the
//!   CPU reference, and the GPU frame agrees with the reference's;
//! * a RIB `shinymetal` sphere with a map made by `MakeLatLongEnvironment`,
//!   lit, on the GPU against the shader's Rust twin in the CPU reference;
//!
//! each at 1 and 16 samples per pixel, whole and in screen tiles.

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use gpu_test::gpu_test;
use reyes::gpu::GpuOptions;
use reyes::model::{Model, Patch};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{CameraDesc, Projection, Scene, SceneObject, ShaderValue, Surface};
use tests::reyes_support::{
    agreement, assert_whole_and_tiled_agree, gpu_turn, renderer, tiled_renderer,
};

/// The environment's linear colour in the direction of longitude `lon` and
/// latitude `lat` (radians): smooth, periodic in longitude, different in
/// every channel.
fn sky(lon: f64, lat: f64) -> [f64; 3] {
    [
        0.5 + 0.4 * (2.0 * lat).sin(),
        0.5 + 0.4 * (3.0 * lon).sin(),
        0.5 + 0.4 * (2.0 * lon + 0.5).cos() * lat.cos(),
    ]
}

/// A `width x height` latitude-longitude picture of [`sky`] as a 16-bit
/// PNG (read as linear): the texel of column `i`, row `j` (row 0 at the
/// top) holds the colour of its centre's direction, longitude
/// `2 pi (i + 1/2) / width` and latitude `pi/2 - pi (j + 1/2) / height`
/// (RenderMan Interface 3.2, `MakeLatLongEnvironment`).
fn write_sky(dir: &Path, width: u32, height: u32) -> PathBuf {
    let image = image::ImageBuffer::<image::Rgba<u16>, _>::from_fn(width, height, |i, j| {
        let lon = 2.0 * PI * (f64::from(i) + 0.5) / f64::from(width);
        let lat = PI / 2.0 - PI * (f64::from(j) + 0.5) / f64::from(height);
        let c = sky(lon, lat).map(|x| (x * 65535.0).round() as u16);
        image::Rgba([c[0], c[1], c[2], 65535])
    });
    let path = dir.join("sky.png");
    image.save(&path).expect("the environment is written");
    path
}

/// The colour of direction `d` in [`sky`], from the specification's
/// `(cos lon cos lat, sin lon cos lat, sin lat)`.
fn sky_along(d: DVec3) -> [f64; 3] {
    let d = d.normalize();
    sky(d.y.atan2(d.x), d.z.asin())
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("reyes-env-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Larger than one 64 x 64 tile, so that the frame can be tiled.
const WIDTH: u32 = 96;
const HEIGHT: u32 = 72;
/// Half the side of the mirror, at distance [`DISTANCE`] along +x.
const HALF: f32 = 2.5;
const DISTANCE: f32 = 5.0;
const FOV_Y_DEGREES: f64 = 60.0;

/// The mirror scene: the eye at the origin looking along +x with +z up
/// (the map's north at the top of the image, and its seam behind the
/// eye), a square mirror across x = 5; `spp` samples per pixel.
fn mirror_scene(sky: &Path, spp: u32) -> (Scene, Vec<Model>) {
    let mut scene = Scene::default();
    scene.resolution.width = WIDTH;
    scene.resolution.height = HEIGHT;
    scene.spp = spp;
    scene.pixel_filter = reyes::filter::PixelFilter::PIXEL_BOX;
    scene.quantize.dither_amplitude = 0.0;
    scene.camera = Some(CameraDesc {
        eye: Vec3::ZERO,
        target: Vec3::X,
        up: Vec3::Z,
        fov_y_degrees: FOV_Y_DEGREES as f32,
        near: 0.1,
        far: 100.0,
        projection: Projection::Perspective,
        ortho_height: None,
    });
    let mut square = Patch::default();
    for (k, point) in square.points.iter_mut().enumerate() {
        let (i, j) = ((k % 4) as f32, (k / 4) as f32);
        *point = Vec3::new(
            DISTANCE,
            HALF * (2.0 * i / 3.0 - 1.0),
            HALF * (2.0 * j / 3.0 - 1.0),
        );
    }
    let number = ShaderValue::Number;
    scene.objects.push(SceneObject {
        color: Vec3::ONE,
        surface: Some(Surface::Wgsl {
            file: PathBuf::from("builtin:shinymetal"),
            parameters: BTreeMap::from([
                ("Ka".to_owned(), number(0.0)),
                ("Ks".to_owned(), number(0.0)),
                ("Kr".to_owned(), number(1.0)),
                (
                    "texturename".to_owned(),
                    ShaderValue::Text(sky.to_string_lossy().into_owned()),
                ),
            ]),
        }),
        ..SceneObject::new("mirror")
    });
    (scene, vec![Model::new(vec![square])])
}

/// The pixels well inside the mirror and the colour each must show (linear
/// RGB), worked out from the pinhole camera: the ray through the pixel's
/// centre meets the mirror at P; I = P (the eye is the origin), N = -x, and
/// D = I - 2 (I.N) N.
fn mirror_expectations() -> Vec<(u32, u32, [f64; 3])> {
    let tan = (FOV_Y_DEGREES.to_radians() / 2.0).tan();
    let aspect = f64::from(WIDTH) / f64::from(HEIGHT);
    let (forward, up) = (DVec3::X, DVec3::Z);
    let right = forward.cross(up);
    let mut out = Vec::new();
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let ndc_x = 2.0 * (f64::from(x) + 0.5) / f64::from(WIDTH) - 1.0;
            let ndc_y = 1.0 - 2.0 * (f64::from(y) + 0.5) / f64::from(HEIGHT);
            let ray = forward + right * (ndc_x * tan * aspect) + up * (ndc_y * tan);
            let p = ray * (f64::from(DISTANCE) / ray.x);
            // Two pixels from the edges: the pixel filter and the
            // micropolygons there see past the mirror.
            let pixel = 2.0 * f64::from(DISTANCE) * tan / f64::from(HEIGHT);
            if p.y.abs() > f64::from(HALF) - 2.0 * pixel
                || p.z.abs() > f64::from(HALF) - 2.0 * pixel
            {
                continue;
            }
            let n = -DVec3::X;
            let d = p - 2.0 * p.dot(n) * n;
            out.push((x, y, sky_along(d)));
        }
    }
    out
}

/// How many of `expected` the frame's 8-bit sRGB pixels show within 2/255,
/// and the largest difference.
fn mirror_match(image: &image::RgbaImage, expected: &[(u32, u32, [f64; 3])]) -> (usize, u8) {
    let (mut within, mut worst) = (0, 0u8);
    for &(x, y, want) in expected {
        let got = image.get_pixel(x, y);
        let diff = (0..3)
            .map(|c| got[c].abs_diff(reyes::color::linear_to_srgb8(want[c] as f32)))
            .max()
            .unwrap_or(0);
        worst = worst.max(diff);
        within += usize::from(diff <= 2);
    }
    (within, worst)
}

/// Most samples of a tile in a `WIDTH x HEIGHT` frame of `spp` samples per
/// pixel: two thirds of the frame's, so four tiles (64 x 64 pixels and what
/// is left of the frame).
fn tile_cap(spp: u32) -> u64 {
    u64::from(WIDTH * HEIGHT) * 2 / 3 * u64::from(spp)
}

/// Every pixel well inside the mirror shows the environment along its
/// reflected direction, on the GPU (whole and in tiles) and in the CPU
/// reference, and the GPU frames agree with the reference's.
#[gpu_test]
fn a_flat_mirror_shows_the_environment_along_the_reflected_direction() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let dir = scratch("mirror");
    let sky = write_sky(&dir, 512, 256);
    let expected = mirror_expectations();
    assert!(expected.len() > 2700, "{} pixels", expected.len());
    let mut whole = renderer(gpu, GpuOptions::default());
    for spp in [1, 16] {
        let mut tiled = tiled_renderer(gpu, tile_cap(spp));
        let (scene, models) = mirror_scene(&sky, spp);
        let prepared = PreparedScene::new(&scene, &models).expect("scene prepares");
        let cpu = reference::try_render(&prepared).expect("shinymetal has a twin");
        let mut frames = vec![(format!("CPU at spp {spp}"), cpu.image.clone())];
        for (mode, renderer) in [("whole", &mut whole), ("tiled", &mut tiled)] {
            let frame = renderer.render(&prepared).expect("GPU render");
            let what = format!("GPU at spp {spp}, {mode}");
            assert_eq!(
                frame.tiles > 1,
                mode == "tiled",
                "{what}: {} tile(s)",
                frame.tiles
            );
            let a = agreement(&frame, &cpu);
            eprintln!("{what} ({} tile(s)) against the CPU: {a:?}", frame.tiles);
            a.assert_at_least(&what, 0.995, 0.99);
            frames.push((what, frame.image));
        }
        for (what, image) in &frames {
            let (within, worst) = mirror_match(image, &expected);
            eprintln!(
                "{what}: {within} of {} mirror pixels within 2/255 (worst {worst})",
                expected.len()
            );
            assert_eq!(
                within,
                expected.len(),
                "{what}: {} mirror pixels off by more than 2/255 (worst {worst})",
                expected.len() - within
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// RIB: a lit `shinymetal` sphere reflecting a map made by
/// `MakeLatLongEnvironment`, on the GPU against its twin, at 1 and 16
/// samples per pixel, whole and in screen tiles.
#[gpu_test]
fn rib_shinymetal_matches_the_reference_whole_and_in_tiles() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let dir = scratch("rib");
    // An 8-bit picture (sRGB) with detail, smaller than the sphere's
    // reflection so that lookups magnify it.
    let picture = image::RgbaImage::from_fn(96, 48, |x, y| {
        let fx = (x as f32 / 5.0).sin() * 0.5 + 0.5;
        let fy = (y as f32 / 4.0).cos() * 0.5 + 0.5;
        image::Rgba([
            (255.0 * fx) as u8,
            (255.0 * fy) as u8,
            (255.0 * fx * fy) as u8,
            255,
        ])
    });
    picture.save(dir.join("room.png")).unwrap();
    let rib = dir.join("shiny.rib");
    // The frame is WIDTH x HEIGHT, so that `tile_cap` gives four tiles.
    std::fs::write(
        &rib,
        "MakeLatLongEnvironment \"room.png\" \"room.env\" \"gaussian\" 2 2\n\
         Format 96 72 1\nPixelSamples 2 2\nProjection \"perspective\" \"fov\" [40]\n\
         Rotate -20 1 0 0\n\
         WorldBegin\nLightSource \"ambientlight\" 1 \"intensity\" [0.1]\n\
         LightSource \"distantlight\" 2 \"from\" [0 0 0] \"to\" [0.3 -0.4 1]\n\
         Color [1 0.85 0.6]\n\
         Surface \"shinymetal\" \"texturename\" \"room.env\" \"Ks\" 0.5 \"Kr\" 0.8 \"roughness\" 0.08\n\
         Translate 0 0 5\nRotate 30 1 0 0\nSphere 1.5 -1.5 1.5 360\nWorldEnd\n",
    )
    .unwrap();
    let mut loaded = reyes::rib::RibScene::load(&rib).expect("the RIB loads");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(
        (
            loaded.scene.resolution.width,
            loaded.scene.resolution.height
        ),
        (WIDTH, HEIGHT)
    );
    let mut whole = renderer(gpu, GpuOptions::default());
    for spp in [1, 16] {
        let mut tiled = tiled_renderer(gpu, tile_cap(spp));
        loaded.scene.spp = spp;
        let prepared = loaded.prepare().expect("the scene prepares");
        assert_eq!(prepared.textures.len(), 1);
        let cpu = reference::try_render(&prepared).expect("shinymetal has a twin");
        assert_whole_and_tiled_agree(
            &format!("RIB shinymetal at spp {spp}"),
            &prepared,
            &mut whole,
            &mut tiled,
            &cpu,
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
