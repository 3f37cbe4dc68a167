//! Displacement mapping: the GPU renderer against the CPU reference on
//! displaced teapots, holes, the displacement bound, the statistics, and the
//! scene-file errors of `[objects.displacement]`. Renders are small (160 x
//! 120 or less, spp 4) so that lavapipe runs the whole file in seconds.

use std::path::PathBuf;

use glam::Vec3;
use gpu_test::gpu_test;
use reyes::dicing::DicingRule;
use reyes::displacement::{CpuHeight, DisplacementDesc, DisplacementError};
use reyes::gpu::{GpuRendered, GpuRenderer};
use reyes::model::{Model, Patch};
use reyes::params::DEFAULT_DICE_THRESHOLD;
use reyes::prepare::PreparedScene;
use reyes::reference::{self, ReferenceError, Rendered};
use reyes::scene::{Dicing, Sampling, Scene, SceneError};
use tests::reyes_support::{
    self, Agreement, agreement, assert_counts_close, camera_down_z, framed_teapot, gpu_turn,
};

/// The default teapot at `width x height`, spp 4, framed for that aspect
/// ratio with the field of view narrowed to 34 degrees (as in `reyes_gpu.rs`).
fn teapot(width: u32, height: u32) -> Scene {
    framed_teapot(width, height, 4)
}

/// A displacement table.
fn displacement(source: &str, scale: f32, tiling: f32) -> DisplacementDesc {
    DisplacementDesc {
        source: source.to_owned(),
        scale,
        bound: None,
        tiling,
        wgsl: None,
        file: None,
        parameters: Default::default(),
    }
}

/// `scene` with every object displaced by `desc`.
fn displaced(mut scene: Scene, desc: &DisplacementDesc) -> Scene {
    for object in &mut scene.objects {
        object.displacement = Some(desc.clone());
    }
    scene
}

/// Renders a prepared scene on both and reports their agreement.
fn compare(
    renderer: &mut GpuRenderer<'_>,
    prepared: &PreparedScene,
) -> (GpuRendered, Rendered, Agreement) {
    let gpu = renderer.render(prepared).expect("GPU render");
    let cpu = reference::try_render(prepared).expect("CPU render");
    let agreement = agreement(&gpu, &cpu);
    eprintln!("GPU stats: {:?}", gpu.stats);
    eprintln!("CPU stats: {:?}", cpu.stats);
    eprintln!(
        "agreement: {agreement:?}; retries: overflow {}, loop limit {}",
        gpu.overflow_retries, gpu.loop_retries
    );
    (gpu, cpu, agreement)
}

/// Pinholes: uncovered pixels whose 4 neighbours are all covered and which
/// `reference` (if given) covers.
fn pinholes(coverage: &[bool], width: u32, reference: Option<&[bool]>) -> usize {
    let w = width as usize;
    let h = coverage.len() / w;
    let mut count = 0;
    for y in 1..h.saturating_sub(1) {
        for x in 1..w - 1 {
            let i = y * w + x;
            let hole = !coverage[i]
                && coverage[i - 1]
                && coverage[i + 1]
                && coverage[i - w]
                && coverage[i + w]
                && reference.is_none_or(|r| r[i]);
            count += usize::from(hole);
        }
    }
    count
}

#[gpu_test]
fn displaced_teapot_matches_the_reference() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let scene = displaced(teapot(160, 120), &displacement("bumps", 0.06, 2.0));
    let prepared = PreparedScene::load(&scene).expect("scene prepares");
    let (g, c, a) = compare(&mut renderer, &prepared);
    assert!(a.coverage >= 0.15, "coverage {:.3} < 15%", a.coverage);
    a.assert_at_least("render", 0.995, 0.99);
    assert_counts_close("grids diced", g.stats.grids_diced, c.stats.grids_diced);
    assert_counts_close("splits", g.stats.splits, c.stats.splits);
    assert_counts_close("samples hit", g.stats.samples_hit, c.stats.samples_hit);
    assert_eq!(g.stats.depth_guard_drops, 0);
    assert_eq!(g.stats.displacement_bound_exceeded, 0);
    assert_eq!(c.stats.displacement_bound_exceeded, 0);
    assert!(
        (g.stats.largest_micropolygon_px - c.stats.largest_micropolygon_px).abs() < 0.05,
        "largest micropolygon: GPU {}, CPU {}",
        g.stats.largest_micropolygon_px,
        c.stats.largest_micropolygon_px
    );
}

/// A displacement large enough to stretch micropolygons to several pixels:
/// bounding-box sampling still covers every pixel the surface covers, on
/// both renderers, while nearest-sample mode (which writes one sample per
/// micropolygon) leaves holes in the same scene, so the pinhole count does
/// detect holes.
#[gpu_test]
fn large_displacement_leaves_no_pinholes() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let scene = displaced(teapot(160, 120), &displacement("sines", 0.25, 2.0));
    let prepared = PreparedScene::load(&scene).expect("scene prepares");
    let (g, c, a) = compare(&mut renderer, &prepared);
    assert!(
        c.stats.largest_micropolygon_px > 2.0,
        "the displacement stretches micropolygons beyond a pixel (largest {} px)",
        c.stats.largest_micropolygon_px
    );
    let cpu_holes = pinholes(&c.coverage, 160, None);
    let gpu_holes = pinholes(&g.coverage, 160, Some(&c.coverage));
    assert_eq!(cpu_holes, 0, "pinholes in the CPU image");
    assert_eq!(
        gpu_holes, 0,
        "pinholes in the GPU image that the CPU covers"
    );
    assert!(a.iou >= 0.99, "coverage IoU {:.5}", a.iou);

    let mut nearest = prepared.clone();
    nearest.sampling = Sampling::Nearest;
    let sparse = reference::render(&nearest);
    let nearest_holes = pinholes(&sparse.coverage, 160, Some(&c.coverage));
    assert!(
        nearest_holes > 0,
        "nearest mode should leave holes where micropolygons exceed a pixel"
    );
}

/// A flat square patch in the plane `x = x0`, `y` in `[-1, 1]`, `z` in
/// `[-6, -4]`, whose normal `dP/du x dP/dv` is +x.
fn wall(x0: f32) -> Model {
    let points = std::array::from_fn(|k| {
        let (u, v) = ((k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0);
        Vec3::new(x0, 1.0 - 2.0 * u, -4.0 - 2.0 * v)
    });
    let patch = Patch { points };
    let n = (patch.point(1, 0) - patch.point(0, 0)).cross(patch.point(0, 1) - patch.point(0, 0));
    assert!(n.x > 0.0, "the wall's normal points +x");
    Model::new(vec![patch])
}

/// The wall scene: the eye at the origin looking down -z (60 degree square
/// view, so the left clip plane is `x = -0.577 * depth`), the wall just left
/// of it at `x = -3.6` (outside for every depth of the wall, 4..6) and
/// displaced by a constant 1.0 (a white height map) towards +x, into the
/// view for depths above 4.5. The prepared bound is then set to `bound`, as
/// a program could: scene files refuse a bound below `|scale| * max height`.
fn wall_scene(bound: f32) -> PreparedScene {
    let dir = temp_dir("wall");
    let map = dir.join("white.png");
    image::GrayImage::from_pixel(2, 2, image::Luma([255]))
        .save(&map)
        .unwrap();
    let mut scene = Scene::default();
    scene.resolution.width = 96;
    scene.resolution.height = 96;
    scene.camera = Some(camera_down_z());
    scene.lights[0].direction = Vec3::new(-1.0, -0.2, -0.5);
    scene.objects.push(reyes::scene::SceneObject {
        color: Vec3::splat(0.8),
        displacement: Some(displacement(&map.to_string_lossy(), 1.0, 1.0)),
        ..reyes::scene::SceneObject::new("wall")
    });
    let mut prepared = PreparedScene::new(&scene, &[wall(-3.6)]).expect("scene prepares");
    std::fs::remove_dir_all(&dir).ok();
    let d = prepared.objects[0].displacement.as_mut().unwrap();
    assert_eq!(d.bound, 1.0, "the default bound is |scale| * max height");
    d.bound = bound;
    prepared
}

/// The bound keeps a patch whose control points are all outside the view but
/// whose displaced surface is inside: with the right bound both renderers
/// draw it (and agree); with a zero bound the bound test culls it, which is
/// what the bound prevents; with a bound that is too small the renderers
/// report the grid points that leave it.
#[gpu_test]
fn displacement_bound_keeps_surface_displaced_into_view() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = reyes_support::patient_renderer(gpu);

    let (g, c, a) = compare(&mut renderer, &wall_scene(1.0));
    assert!(
        a.coverage > 0.02,
        "the displaced wall is visible (coverage {:.3})",
        a.coverage
    );
    a.assert_at_least("render", 0.99, 0.99);
    assert_eq!(c.stats.culled_patches, 0);
    assert_eq!(g.stats.culled_patches, 0);
    assert_eq!(g.stats.displacement_bound_exceeded, 0);

    // Without the bound the undisplaced patch is culled: nothing is drawn.
    let (g, c, _) = compare(&mut renderer, &wall_scene(0.0));
    assert_eq!(c.stats.culled_patches, 1);
    assert_eq!(g.stats.culled_patches, 1);
    assert!(!g.coverage.iter().any(|&c| c));

    // Too small a bound that still keeps the patch: diced, and every point
    // reported on both sides (fixed dicing: 256 points per grid; rate
    // dicing: as many on both sides).
    let mut fixed = wall_scene(0.9);
    fixed.dicing = DicingRule::new(
        Dicing::Fixed,
        fixed.dicing.shading_rate(),
        DEFAULT_DICE_THRESHOLD,
    );
    let (g, c, _) = compare(&mut renderer, &fixed);
    assert_eq!(c.stats.culled_patches, 0);
    let points = c.stats.grids_diced * 256;
    assert_eq!(c.stats.displacement_bound_exceeded, points);
    assert_eq!(
        g.stats.displacement_bound_exceeded,
        g.stats.grids_diced * 256
    );
    let (g, c, _) = compare(&mut renderer, &wall_scene(0.9));
    assert!(c.stats.displacement_bound_exceeded >= c.stats.micropolygons);
    assert_eq!(
        g.stats.displacement_bound_exceeded,
        c.stats.displacement_bound_exceeded
    );
}

/// Round bumps, one per tiled cell, and their Rust twin.
const BUMPS_WGSL: &str = "fn displacement_user(u: f32, v: f32) -> f32 {
        let du = u - floor(u) - 0.5;
        let dv = v - floor(v) - 0.5;
        return max(0.0, 0.2 - (du * du + dv * dv));
    }";

fn bumps(u: f32, v: f32) -> f32 {
    let du = u - u.floor() - 0.5;
    let dv = v - v.floor() - 0.5;
    (0.2 - (du * du + dv * dv)).max(0.0)
}

/// Ridges along u (a helper function of its own), and their Rust twin.
const RIDGES_WGSL: &str = "fn ridge(x: f32) -> f32 {
        return abs(x - floor(x) - 0.5);
    }
    fn displacement_user(u: f32, v: f32) -> f32 {
        return 0.4 * ridge(3.0 * u) - 0.1 * v;
    }";

fn ridges(u: f32, v: f32) -> f32 {
    let ridge = |x: f32| (x - x.floor() - 0.5).abs();
    0.4 * ridge(3.0 * u) - 0.1 * v
}

/// A user WGSL function with a Rust twin renders like the twin on the CPU;
/// a broken function is a typed error naming its line, and so is asking
/// the CPU reference to run one without a twin.
#[gpu_test]
fn user_wgsl_displacement() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let desc = DisplacementDesc {
        bound: Some(0.2 * 0.3),
        wgsl: Some(BUMPS_WGSL.into()),
        ..displacement("wgsl", 0.3, 4.0)
    };
    let scene = displaced(teapot(128, 96), &desc);
    let mut prepared = PreparedScene::load(&scene).expect("scene prepares");
    assert!(matches!(
        reference::try_render(&prepared),
        Err(ReferenceError::UserDisplacement { object: 0 })
    ));
    assert!(prepared.set_height_twin(0, CpuHeight::new(bumps)));
    let (g, c, a) = compare(&mut renderer, &prepared);
    a.assert_at_least("render", 0.995, 0.99);
    assert_counts_close("grids diced", g.stats.grids_diced, c.stats.grids_diced);
    assert_eq!(g.stats.displacement_bound_exceeded, 0);

    // Refused on its own source, at its own line, before anything renders.
    let broken = DisplacementDesc {
        wgsl: Some("fn displacement_user(u: f32, v: f32) -> f32 { return u + ; }".into()),
        ..desc
    };
    match PreparedScene::load(&displaced(teapot(128, 96), &broken)) {
        Err(error) => assert!(error.to_string().contains("line 1"), "{error}"),
        Ok(_) => panic!("a broken function prepared"),
    }
}

/// Each object runs its own WGSL height function, in one frame: a teapot
/// with bumps and a smaller, mirrored one in front of it with ridges (a
/// helper function of its own, and the mirror's turned normal). The GPU
/// matches the CPU twins; with the second object's twin swapped for the
/// first's, the CPU frame differs, so the comparison sees which function
/// each object ran.
#[gpu_test]
fn each_object_runs_its_own_height_function() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let mut scene = teapot(128, 96);
    let mut front = scene.objects[0].clone();
    front.transform.scale = reyes::scene::Scale::PerAxis(Vec3::new(-0.5, 0.5, 0.5));
    front.transform.translate += Vec3::new(0.8, -0.6, 1.2);
    scene.objects.push(front);
    scene.objects[0].displacement = Some(DisplacementDesc {
        bound: Some(0.2 * 0.3),
        wgsl: Some(BUMPS_WGSL.into()),
        ..displacement("wgsl", 0.3, 4.0)
    });
    scene.objects[1].displacement = Some(DisplacementDesc {
        bound: Some(0.2 * 0.5),
        wgsl: Some(RIDGES_WGSL.into()),
        ..displacement("wgsl", 0.5, 2.0)
    });
    let mut prepared = PreparedScene::load(&scene).expect("scene prepares");
    assert_eq!(prepared.shaders.shaders.len(), 2, "one shader per function");
    assert!(prepared.set_height_twin(0, CpuHeight::new(bumps)));
    assert!(prepared.set_height_twin(1, CpuHeight::new(ridges)));
    let (g, _, a) = compare(&mut renderer, &prepared);
    a.assert_at_least("two functions", 0.995, 0.99);
    assert_eq!(g.stats.displacement_bound_exceeded, 0);

    let mut swapped = prepared.clone();
    assert!(swapped.set_height_twin(1, CpuHeight::new(bumps)));
    let wrong = agreement(&g, &reference::try_render(&swapped).expect("CPU render"));
    eprintln!("with the second object's twin swapped: {wrong:?}");
    assert!(
        wrong.iou < 0.99 || wrong.within_2 < 0.95,
        "the comparison cannot tell the functions apart: {wrong:?}"
    );
}

/// The largest-micropolygon statistic is present and grows with the
/// displacement, on both renderers.
#[gpu_test]
fn largest_micropolygon_grows_with_displacement() {
    let gpu = tests::gpu();
    let _turn = gpu_turn();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let plain = PreparedScene::load(&teapot(128, 96)).expect("scene prepares");
    let bumpy = PreparedScene::load(&displaced(
        teapot(128, 96),
        &displacement("sines", 0.6, 2.0),
    ))
    .expect("scene prepares");
    let (g_plain, c_plain, _) = compare(&mut renderer, &plain);
    let (g_bumpy, c_bumpy, _) = compare(&mut renderer, &bumpy);
    for (what, plain, bumpy) in [
        (
            "GPU",
            g_plain.stats.largest_micropolygon_px,
            g_bumpy.stats.largest_micropolygon_px,
        ),
        (
            "CPU",
            c_plain.stats.largest_micropolygon_px,
            c_bumpy.stats.largest_micropolygon_px,
        ),
    ] {
        // About a pixel, but a micropolygon whose border points snapped to
        // a coarser neighbour's vertices at a T-junction spans a few
        // (3.5 px here).
        assert!(
            plain > 0.1 && plain < 4.0,
            "{what}: undisplaced micropolygons are about a pixel ({plain} px)"
        );
        assert!(
            bumpy > 1.5 * plain,
            "{what}: displacement stretches micropolygons ({plain} -> {bumpy} px)"
        );
    }
    let json = serde_json::to_value(&g_bumpy.stats).unwrap();
    assert!(json["largest_micropolygon_px"].as_f64().unwrap() > 0.0);
    assert_eq!(json["displacement_bound_exceeded"], 0);
}

/// A fresh directory for files the test writes.
fn temp_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("reyes-displacement-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn scene_with(table: &str) -> String {
    format!("[[objects]]\nmodel = \"teapot\"\n[objects.displacement]\n{table}\n")
}

fn field_of(error: &SceneError) -> Option<&str> {
    match error {
        SceneError::NonFinite { field } | SceneError::InvalidValue { field, .. } => Some(field),
        _ => None,
    }
}

#[test]
fn scene_errors_for_displacement_fields() {
    // Values: every problem names its field.
    for (table, field) in [
        (
            "source = \"bumps\"\nscale = nan",
            "objects[0].displacement.scale",
        ),
        (
            "source = \"bumps\"\nscale = inf",
            "objects[0].displacement.scale",
        ),
        (
            "source = \"bumps\"\nscale = 0.1\nbound = -0.5",
            "objects[0].displacement.bound",
        ),
        (
            "source = \"bumps\"\nscale = 0.1\nbound = nan",
            "objects[0].displacement.bound",
        ),
        (
            "source = \"bumps\"\nscale = 0.1\ntiling = 0.0",
            "objects[0].displacement.tiling",
        ),
        (
            "source = \"bumps\"\nscale = 0.1\ntiling = 5000.0",
            "objects[0].displacement.tiling",
        ),
        (
            "source = \"\"\nscale = 0.1",
            "objects[0].displacement.source",
        ),
        (
            "source = \"wgsl\"\nscale = 0.1\nbound = 0.1",
            "objects[0].displacement.wgsl",
        ),
        (
            "source = \"wgsl\"\nscale = 0.1\nwgsl = \"fn displacement_user(u: f32, v: f32) -> f32 { return u; }\"",
            "objects[0].displacement.bound",
        ),
        (
            "source = \"wgsl\"\nscale = 0.1\nbound = 0.1\nwgsl = \"fn other(u: f32) -> f32 { return u; }\"",
            "objects[0].displacement.wgsl",
        ),
        (
            "source = \"sines\"\nscale = 0.1\nwgsl = \"fn displacement_user(u: f32, v: f32) -> f32 { return u; }\"",
            "objects[0].displacement.wgsl",
        ),
        (
            "source = \"image\"\nscale = 0.1",
            "objects[0].displacement.file",
        ),
        (
            "source = \"bumps\"\nscale = 0.1\nfile = \"hm.png\"",
            "objects[0].displacement.file",
        ),
    ] {
        let error = Scene::from_toml_str(&scene_with(table)).unwrap_err();
        assert_eq!(field_of(&error), Some(field), "{table:?}: {error}");
    }
    // Syntax: a missing source, an unknown field, a wrong type (with the
    // line). A missing scale is 1 (docs/reyes-scene.md).
    assert_eq!(
        Scene::from_toml_str(&scene_with("source = \"bumps\""))
            .unwrap()
            .objects[0]
            .displacement
            .as_ref()
            .map(|d| d.scale),
        Some(1.0)
    );
    for table in [
        "scale = 0.1",
        "source = \"bumps\"\nscale = 0.1\ncolour = 1",
        "source = \"bumps\"\nscale = \"big\"",
    ] {
        let error = Scene::from_toml_str(&scene_with(table)).unwrap_err();
        assert!(
            matches!(error, SceneError::Parse { line: Some(_), .. }),
            "{table:?}: {error}"
        );
    }

    // Files, read when the scene is prepared: missing, not a PNG, not grey.
    let dir = temp_dir("errors");
    std::fs::write(dir.join("garbage.png"), b"not a png").unwrap();
    image::RgbImage::from_pixel(4, 4, image::Rgb([10, 200, 30]))
        .save(dir.join("colour.png"))
        .unwrap();
    image::GrayImage::from_pixel(4, 4, image::Luma([128]))
        .save(dir.join("grey.png"))
        .unwrap();
    let prepare = |source: &str, extra: &str| {
        let path = dir.join("scene.toml");
        std::fs::write(
            &path,
            scene_with(&format!("source = \"{source}\"\nscale = 0.1\n{extra}")),
        )
        .unwrap();
        PreparedScene::load(&Scene::load(&path).unwrap())
    };
    let displacement_error = |result: Result<PreparedScene, SceneError>| match result {
        Err(SceneError::Displacement {
            index: 0, source, ..
        }) => source,
        other => panic!("expected SceneError::Displacement, got {other:?}"),
    };
    assert!(matches!(
        displacement_error(prepare("missing.png", "")),
        DisplacementError::Io { .. }
    ));
    assert!(matches!(
        displacement_error(prepare("garbage.png", "")),
        DisplacementError::Decode { .. }
    ));
    let not_grey = displacement_error(prepare("colour.png", ""));
    assert!(
        matches!(not_grey, DisplacementError::NotGrey { .. }),
        "{not_grey}"
    );
    assert!(not_grey.to_string().contains("greyscale"), "{not_grey}");
    // A relative path is resolved against the scene's directory; the default
    // bound is |scale| * the largest texel.
    let grey = prepare("grey.png", "").expect("a grey PNG prepares");
    let bound = grey.objects[0].displacement.as_ref().unwrap().bound;
    assert!((bound - 0.1 * 128.0 / 255.0).abs() < 1e-6, "{bound}");
    // A declared bound below |scale| * max height is refused.
    assert!(matches!(
        displacement_error(prepare("sines", "bound = 0.05")),
        DisplacementError::BoundTooSmall { .. }
    ));
    assert!(prepare("sines", "bound = 0.1").is_ok());
    std::fs::remove_dir_all(&dir).ok();
}

/// The table round-trips through TOML and prepares with the documented
/// defaults; a mirroring transform keeps the displacement on the model's side.
#[test]
fn displacement_table_defaults_and_round_trip() {
    let text = scene_with("source = \"sines\"\nscale = -0.2");
    let scene = Scene::from_toml_str(&text).unwrap();
    let again = Scene::from_toml_str(&scene.to_toml_string()).unwrap();
    assert_eq!(again, scene);
    let desc = scene.objects[0].displacement.as_ref().unwrap();
    assert_eq!((desc.tiling, desc.bound), (1.0, None));
    let prepared = PreparedScene::load(&scene).unwrap();
    let d = prepared.objects[0].displacement.as_ref().unwrap();
    assert_eq!((d.scale, d.bound), (-0.2, 0.2));

    let mut mirrored = scene.clone();
    mirrored.objects[0].transform.scale = reyes::scene::Scale::PerAxis(Vec3::new(-1.0, 1.0, 1.0));
    let prepared = PreparedScene::load(&mirrored).unwrap();
    assert_eq!(
        prepared.objects[0].displacement.as_ref().unwrap().scale,
        0.2
    );
}

/// Every TOML example in docs/reyes-scene.md parses and validates (the
/// displacement examples included).
#[test]
fn documented_scene_examples_parse() {
    let doc = include_str!("../../docs/reyes-scene.md");
    let mut blocks = 0;
    for (start, _) in doc.match_indices("```toml\n") {
        let body = &doc[start + "```toml\n".len()..];
        let text = &body[..body.find("```").expect("a closed block")];
        let scene = Scene::from_toml_str(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert!(!scene.objects.is_empty());
        blocks += 1;
    }
    assert!(blocks >= 2, "the full example and the displacement example");
}
