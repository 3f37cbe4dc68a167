//! Cracks: closed surfaces diced to a shading rate must render without
//! gaps at 16 spp, on the GPU and in the CPU reference, while the old fixed
//! 16 x 16 dicer shows cracks on the same scenes (so the count can fail).
//!
//! Every configuration is counted against an independent coverage
//! reference, a dense uniform tessellation of the input patches
//! ([`tests::watertight::dense_coverage`]): a crack is a pixel 2 or more
//! pixels inside the reference's coverage with fewer than 16 covered
//! samples ([`tests::watertight::cracks`]). The spheres of
//! [`tests::shapes`] are closed as data (their patches share boundary
//! control points bit for bit), so any crack in them comes from splitting
//! and dicing.
//!
//! Three things make coverage see the cracks that matter and nothing else:
//!
//! * The renderers draw surfaces two-sided, so a crack in a closed
//!   surface's front layer shows its back layer, which covers the lost
//!   samples. Each scene therefore renders only the patches that are not
//!   clearly hidden ([`tests::watertight::visible_patches`]): the same
//!   coverage, but the background shows through a crack in front. (With the
//!   whole spheres, the fixed dicer shows 1 crack in all 16 configurations
//!   instead of over 100.)
//! * Cracks are counted only where the front surface is smooth
//!   ([`tests::watertight::smooth_front`]): at a fold inside the coverage,
//!   where the next layer shows behind the front, the render's chords and
//!   the reference's end the front in slightly different places.
//! * The Killeroo is not closed as data (1164 of its patch edges have no
//!   bit-identical partner: near misses, T-junctions and gaps of up to about
//!   0.01 units), and no dicer closes gaps in the data: pixels near those
//!   edges are left out ([`tests::watertight::exclude_edges`]).
//!
//! The views are chosen so that neighbouring pieces split to different
//! depths, which is where a dicer that ignores its neighbours leaves
//! T-junctions: close to the sphere and looking across it (the near side is
//! 2 times closer than the limb and splits 1 to 2 levels deeper in each
//! direction), grazing over it towards its horizon (distance and
//! foreshortening change along the view, so split depths *and* directions
//! change from piece to piece), the octant sphere's pole (4 collapsed edges
//! meet there, and its latitude lines, along which it splits, curve
//! strongly on screen), and the Killeroo's head close up (its many small
//! patches project to very different sizes, so rate dicing gives neighbours
//! different grids even without splits). Each scene prints how many pieces
//! the fixed dicer dices at each split depth.
//!
//! Nothing is random (no jitter), so no seed is printed. Sizes are for
//! lavapipe on 2 cores: 256 x 192 (spheres) and 320 x 240 (the Killeroo) at
//! 16 spp. Set `REYES_WATERTIGHT_DUMP=<dir>` to get every GPU render as a PNG
//! with its cracks in red.

use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::Instant;

use glam::{Vec2, Vec3, Vec4};
use gpu_test::gpu_test;
use reyes::gpu::GpuRenderer;
use reyes::model::Model;
use reyes::params::{DEFAULT_DICE_THRESHOLD, NEAR_EPS};
use reyes::prepare::PreparedScene;
use reyes::reference;
use reyes::scene::{Dicing, Scene};
use tests::crack_scene::{CrackCount, CrackScene, CrackSettings};
use tests::reyes_support::{self, gpu_turn};
use tests::shapes::{bezier_sphere, bezier_sphere_with_poles, unmatched_edges};

/// Samples per pixel of every render: 16, a 4 x 4 grid, so a crack a
/// quarter of a pixel wide already loses samples.
const SPP: u32 = 16;

/// The shading rates (micropolygon areas in pixels) every scene is
/// rendered at: micropolygons of 1 to 8 pixels on a side.
const SHADING_RATES: [f32; 4] = [1.0, 4.0, 16.0, 64.0];

/// The coverage IoU a render must reach against the reference
/// ([`coverage_iou`]), so that a render that draws nothing (or draws a
/// different surface) cannot pass by having no cracks. The renders' chords
/// deflate convex silhouettes a little at coarse shading rates: the lowest
/// seen is about 0.995 (the Killeroo's head at rate 64).
const MIN_IOU: f64 = 0.99;

/// How far from a model's own open seams (patch edges not shared bit for
/// bit) pixels are left out of the crack count: the Killeroo's gaps are up
/// to about 0.01 units, under 2 pixels in its view here, and each side of a
/// gap is an open seam.
const SEAM_MARGIN_PX: f32 = 1.5;

/// How far behind the front (as a fraction of the view depth) a patch must
/// be everywhere to be left out as hidden ([`visible_patches`]): far less
/// than the depth of a sphere's back layer or the Killeroo's body, more than
/// fingers pressed together.
const HIDDEN_MARGIN: f64 = 0.02;

/// The largest change in view depth (as a fraction) from one sample
/// position to the next where the front still counts as smooth for the
/// crack count ([`smooth_front`]): a surface within about 5 degrees of edge
/// on (the step is `tan(angle) / (4 * focal length in pixels)`), or a depth
/// jump at a silhouette, changes more.
const MAX_DEPTH_STEP: f64 = 0.01;

/// The Killeroo, read by path and never copied into the repository.
fn killeroo_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/killeroo.bpt")
}

/// `model` at `width x height`, 16 spp, seen from `eye` looking at
/// `target` (z up), lit over the camera's shoulder. The spheres come within
/// 0.25 of the eye: `view_scene`'s near plane at 0.01 keeps them unclipped.
fn scene_for(model: &Model, width: u32, height: u32, eye: Vec3, target: Vec3) -> Scene {
    tests::watertight::view_scene(model, (width, height, SPP), eye, target)
}

/// `shot`'s scene with `dicing` at `rate`. The fixed dicer ignores the
/// shading rate, so it gets the dice threshold that gives micropolygons of
/// about the same size instead (`16 * sqrt(rate)` pixels per 15 quads; at
/// rate 1 that is the default threshold, the old renderer exactly).
fn configured(shot: &CrackScene, dicing: Dicing, rate: f32) -> PreparedScene {
    let mut scene = shot.scene.clone();
    scene.dicing = dicing;
    scene.shading_rate = rate;
    if dicing == Dicing::Fixed {
        scene.dice_threshold = DEFAULT_DICE_THRESHOLD * rate.sqrt();
    }
    PreparedScene::new(&scene, std::slice::from_ref(&shot.model)).expect("the test scene prepares")
}

/// How many pieces the fixed dicer (at the default threshold) dices at each
/// split depth in `prepared`: a replay of its bound test (`docs/reyes.md`,
/// "Bound"), to show that a view does mix depths.
fn fixed_split_depths(prepared: &PreparedScene) -> Vec<usize> {
    let camera = &prepared.camera;
    let view_proj = camera.view_proj();
    let mut diced = vec![0; prepared.max_split_depth as usize + 1];
    let mut stack: Vec<([Vec3; 16], u32)> =
        prepared.patches.iter().map(|p| (p.points, 0)).collect();
    while let Some((points, depth)) = stack.pop() {
        let clip = points.map(|p| view_proj * p.extend(1.0));
        let all = |outside: fn(&Vec4) -> bool| clip.iter().all(outside);
        if all(|c| c.x < -c.w)
            || all(|c| c.x > c.w)
            || all(|c| c.y < -c.w)
            || all(|c| c.y > c.w)
            || all(|c| c.z > c.w)
            || all(|c| c.z < 0.0)
        {
            continue;
        }
        let direction = if clip.iter().any(|c| c.w <= NEAR_EPS || c.z < 0.0) {
            reyes::bezier::split_direction_3d(&points)
        } else {
            let pixels = clip.map(|c| camera.to_pixel(c).truncate());
            let (lo, hi) = pixels
                .iter()
                .fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(*p), hi.max(*p))
                });
            if (hi - lo).max_element() <= DEFAULT_DICE_THRESHOLD {
                diced[depth as usize] += 1;
                continue;
            }
            reyes::bezier::split_direction_2d(&pixels)
        };
        if depth < prepared.max_split_depth {
            let (a, b) = reyes::bezier::split(&points, direction);
            stack.extend([(a, depth + 1), (b, depth + 1)]);
        }
    }
    diced
}

/// `depth:count` for the depths that have pieces.
fn depth_histogram(diced: &[usize]) -> String {
    let entries: Vec<String> = diced
        .iter()
        .enumerate()
        .filter(|(_, count)| **count > 0)
        .map(|(depth, count)| format!("{depth}:{count}"))
        .collect();
    entries.join(" ")
}

/// The scenes, built once per test binary (the Killeroo's reference takes
/// a moment): two views of the cube sphere, one of the octant sphere's
/// pole, and the Killeroo when its file is present.
fn shots() -> &'static [CrackScene] {
    static SHOTS: OnceLock<Vec<CrackScene>> = OnceLock::new();
    SHOTS.get_or_init(|| {
        let start = Instant::now();
        let sphere = bezier_sphere();
        let poles = bezier_sphere_with_poles();
        assert!(unmatched_edges(&sphere).is_empty() && unmatched_edges(&poles).is_empty());
        let mut views: Vec<(&'static str, Model, Scene, u32)> = vec![
            (
                // 0.6 from the nearest point, 1.25 from the limb, which
                // crosses the right third of the image: the fixed dicer
                // dices at split depths 5 to 10, the limb's pieces
                // foreshortened into splits across the other direction.
                "sphere close, across",
                sphere.clone(),
                scene_for(&sphere, 256, 192, Vec3::new(0.0, -1.6, 0.0), Vec3::new(0.75, 0.0, 0.2)),
                64,
            ),
            (
                // 0.25 above the surface, looking at the horizon 0.75 away:
                // the bottom of the image is 2.4 times closer than the
                // horizon, and pieces flatten towards it (split depths 7 to
                // 12).
                "sphere grazing, to the horizon",
                sphere.clone(),
                scene_for(&sphere, 256, 192, Vec3::new(0.0, 0.0, 1.25), Vec3::new(0.0, -1.0, 0.5)),
                64,
            ),
            (
                // The pole where 4 collapsed edges meet, seen obliquely
                // from close by (split depths 5 to 10).
                "octant sphere, pole",
                poles.clone(),
                scene_for(&poles, 256, 192, Vec3::new(1.0, -1.2, 1.3), Vec3::new(0.0, 0.0, 0.7)),
                96,
            ),
        ];
        let path = killeroo_path();
        if path.exists() {
            let killeroo = Model::load(&path)
                .unwrap_or_else(|e| panic!("{} exists but does not load: {e}", path.display()));
            eprintln!(
                "Killeroo: {} patches, {} edges not shared bit for bit with exactly one other patch",
                killeroo.patches.len(),
                unmatched_edges(&killeroo).len()
            );
            // Head and shoulders from the front left, close enough that the
            // larger patches split (the whole Killeroo at this size dices
            // every patch unsplit) and neighbouring patches project to very
            // different sizes (the snout against the shoulder behind it).
            let scene = scene_for(
                &killeroo,
                320,
                240,
                Vec3::new(2.0, 3.4, 1.3),
                Vec3::new(0.0, 2.3, 0.6),
            );
            views.push(("Killeroo head", killeroo, scene, 16));
        } else {
            eprintln!(
                "NOTICE: {} not found; the Killeroo part of the crack tests is skipped",
                path.display()
            );
        }
        let shots = views
            .into_iter()
            .map(|(name, whole, scene, density)| {
                let shot = CrackScene::new(
                    name,
                    &whole,
                    scene,
                    SPP,
                    CrackSettings {
                        density,
                        hidden_margin: HIDDEN_MARGIN,
                        max_depth_step: MAX_DEPTH_STEP,
                        seam_margin_px: SEAM_MARGIN_PX,
                    },
                );
                let prepared = PreparedScene::new(&shot.scene, std::slice::from_ref(&shot.model))
                    .expect("the test scene prepares");
                eprintln!(
                    "{name}: {} of {} patches visible; the reference covers {} of {} pixels, {} counted for cracks; the fixed dicer dices at split depth:pieces {}",
                    shot.model.patches.len(),
                    whole.patches.len(),
                    shot.coverage.iter().filter(|&&c| c).count(),
                    shot.coverage.len(),
                    shot.counted_pixels(),
                    depth_histogram(&fixed_split_depths(&prepared))
                );
                shot
            })
            .collect();
        eprintln!("scenes and references ready in {:.1?}", start.elapsed());
        shots
    })
}

/// Both renderers' counts for one scene, dicing and rate.
struct Outcome {
    label: String,
    gpu: CrackCount,
    cpu: CrackCount,
}

/// Renders every scene at every shading rate with `dicing`, on the GPU and
/// in the CPU reference, printing each configuration's counts and time.
fn render_all(renderer: &mut GpuRenderer<'_>, dicing: Dicing) -> Vec<Outcome> {
    let mut outcomes = Vec::new();
    for shot in shots() {
        for rate in SHADING_RATES {
            let start = Instant::now();
            let prepared = configured(shot, dicing, rate);
            let gpu = renderer.render(&prepared).expect("GPU render");
            let gpu_time = start.elapsed();
            let cpu = reference::render(&prepared);
            let outcome = Outcome {
                label: format!(
                    "{} / {} dicing / shading rate {rate}",
                    shot.name,
                    dicing.name()
                ),
                gpu: shot.count(&gpu.covered_samples, SPP, 0),
                cpu: shot.count(&cpu.covered_samples, SPP, 0),
            };
            if let Some(dir) = std::env::var_os(DUMP_VARIABLE) {
                let name = format!(
                    "{}-{}-rate{rate}.png",
                    shot.name.replace([' ', ','], "-"),
                    dicing.name()
                );
                dump(
                    &gpu.image,
                    &outcome.gpu.cracks,
                    &PathBuf::from(dir).join(name),
                );
            }
            eprintln!(
                "{}: GPU {}; CPU {}; {} grids; GPU {:.1?} ({} tiles, retries: overflow {}, loop limit {}), CPU {:.1?}",
                outcome.label,
                outcome.gpu.describe(),
                outcome.cpu.describe(),
                gpu.stats.grids_diced,
                gpu_time,
                gpu.tiles,
                gpu.overflow_retries,
                gpu.loop_retries,
                start.elapsed() - gpu_time
            );
            outcomes.push(outcome);
        }
    }
    outcomes
}

/// Set to a directory to get every GPU render there as a PNG, its cracks
/// painted red.
const DUMP_VARIABLE: &str = "REYES_WATERTIGHT_DUMP";

/// Writes `image` to `path` with the `cracks` painted red (a failure to
/// write is reported, not fatal: the dump is a debugging aid).
fn dump(image: &image::RgbaImage, cracks: &[(u32, u32)], path: &std::path::Path) {
    let mut marked = image.clone();
    for &(x, y) in cracks {
        marked.put_pixel(x, y, image::Rgba([255, 0, 0, 255]));
    }
    match reyes::output::write_png(&marked, path) {
        Ok(()) => eprintln!("wrote {}", path.display()),
        Err(e) => eprintln!("cannot write {}: {e}", path.display()),
    }
}

#[gpu_test]
fn rate_dicing_is_watertight() {
    let gpu = tests::gpu();
    let shots = shots();
    let _turn = gpu_turn();
    let start = Instant::now();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let outcomes = render_all(&mut renderer, Dicing::Rate);
    let mut failures = Vec::new();
    for outcome in &outcomes {
        for (side, count) in [("GPU", &outcome.gpu), ("CPU", &outcome.cpu)] {
            if !count.cracks.is_empty() || count.iou < MIN_IOU {
                failures.push(format!(
                    "{} ({side}): {} (IoU floor {MIN_IOU})",
                    outcome.label,
                    count.describe()
                ));
            }
        }
    }
    eprintln!(
        "rate_dicing_is_watertight: {} configurations of {} scenes in {:.1?}",
        outcomes.len(),
        shots.len(),
        start.elapsed()
    );
    assert!(
        failures.is_empty(),
        "rate dicing shows cracks (or misses the surface):\n{}",
        failures.join("\n")
    );
}

/// The fixed dicer dices each piece without regard to its neighbours, so
/// where a piece meets two pieces split one level deeper its border is one
/// chord per two of theirs, and samples in the sliver between fall through
/// (where the curve bends away from the coarser piece). The slivers are
/// about `L^2 / 8R` pixels wide for chords of `L` pixels on a curve of
/// radius `R` pixels on screen: thin at 1-pixel micropolygons, which is why
/// the coarser rates (larger dice thresholds) matter here. On these scenes
/// it shows over 100 cracks in all, most at rates 16 and 64 on the grazing
/// and pole views, and some in every scene; the test only asks for one, on
/// each renderer.
#[gpu_test]
fn fixed_dicing_cracks_on_the_same_scenes() {
    let gpu = tests::gpu();
    let shots = shots();
    let _turn = gpu_turn();
    let start = Instant::now();
    let mut renderer = reyes_support::patient_renderer(gpu);
    let outcomes = render_all(&mut renderer, Dicing::Fixed);
    let gpu_total: usize = outcomes.iter().map(|o| o.gpu.cracks.len()).sum();
    let cpu_total: usize = outcomes.iter().map(|o| o.cpu.cracks.len()).sum();
    eprintln!(
        "fixed_dicing_cracks_on_the_same_scenes: {gpu_total} cracks on the GPU, {cpu_total} in the CPU reference, over {} configurations of {} scenes in {:.1?}",
        outcomes.len(),
        shots.len(),
        start.elapsed()
    );
    for outcome in &outcomes {
        for (side, count) in [("GPU", &outcome.gpu), ("CPU", &outcome.cpu)] {
            assert!(
                count.iou >= MIN_IOU,
                "{} ({side}): the render misses the reference: {}",
                outcome.label,
                count.describe()
            );
        }
    }
    assert!(
        gpu_total > 0,
        "the fixed dicer shows no cracks on the GPU: the crack test cannot fail"
    );
    assert!(
        cpu_total > 0,
        "the fixed dicer shows no cracks in the CPU reference: the crack test cannot fail"
    );
}
