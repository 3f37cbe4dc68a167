//! `shadow-bench`: what automatic shadows cost, side by side in one run.
//!
//! ```text
//! cargo run --release -p benches --bin shadow-bench -- [--model killeroo|teapot|FILE]
//!     [--size 1024] [--map-size 1024] [--spp 16] [--runs 3]
//! ```
//!
//! The model stands on a ground square, framed at `size x size`, under a
//! distant light and a spotlight. Every run renders, interleaved so that
//! drift hits them alike:
//!
//! * `beauty spp 1`: the frame at 1 sample per pixel, no shadows;
//! * `depth pass`: the distant light's depth pass alone (a `map-size` map);
//! * `frame`: the frame at `spp`, no shadows;
//! * `frame + 2 shadows`: the same with both lights' shadows, their depth
//!   passes included.
//!
//! It prints the medians (wall time of `GpuRenderer::render`, read-backs
//! included) and the two ratios the shadows answer to: depth pass / beauty
//! spp 1, and frame with shadows / frame without.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use benches::blur::{load_model, renderer};
use benches::error::BenchError;
use clap::Parser;
use glam::Vec3;
use reyes::model::Model;
use reyes::prepare::{PreparedScene, depth_passes};
use reyes::scene::{
    CameraDesc, Light, LightKind, LightShadow, Scale, Scene, ShadowMaps, Transform,
};
use reyes::shadow::ShadowFilter;

#[derive(Debug, Parser)]
#[command(about = "Automatic shadows: depth passes and shadowed frames against plain frames")]
struct Args {
    /// `killeroo` (from ../shared/data), `teapot`, or a .bpt/.bez path.
    #[arg(long, default_value = "killeroo")]
    model: String,
    /// The frame's width and height.
    #[arg(long, default_value_t = 1024)]
    size: u32,
    /// The shadow maps' side.
    #[arg(long, default_value_t = 1024)]
    map_size: u32,
    /// Samples per pixel of the compared frames.
    #[arg(long, default_value_t = 16)]
    spp: u32,
    /// Timed runs of each (after one warm-up).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    runs: u32,
}

/// The ground square: `docs/scenes/ground.bpt`, one flat patch over
/// `[-1, 1]^2` at z = 0.
fn ground_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/scenes/ground.bpt")
}

/// The model on the ground, framed from above and in front, lit by a
/// distant light and a spotlight with `shadows` (automatic, `map_size`).
fn scene(name: &str, model: &Model, args: &Args, spp: u32, shadows: bool) -> Scene {
    let mut scene = Scene::for_model(name, model);
    scene.resolution.width = args.size;
    scene.resolution.height = args.size;
    scene.spp = spp;
    let (lo, hi) = model.bounds();
    let centre = 0.5 * (lo + hi);
    let extent = (hi - lo).max_element();
    // The ground under the model, twice its extent.
    let mut ground = scene.objects[0].clone();
    ground.model = ground_path().to_string_lossy().into_owned();
    ground.transform = Transform {
        translate: Vec3::new(centre.x, centre.y, lo.z),
        scale: Scale::Uniform(extent),
        ..Transform::default()
    };
    scene.objects.push(ground);
    let framed = CameraDesc::framing(lo - extent * 0.5, hi + extent * 0.5, 1.0);
    let distance = framed.eye.distance(framed.target);
    scene.camera = Some(CameraDesc {
        eye: framed.target + Vec3::new(0.0, -0.8, 0.6).normalize() * distance,
        up: Vec3::Z,
        ..framed
    });
    let shadow = shadows.then_some(LightShadow {
        maps: ShadowMaps::Automatic {
            map_size: args.map_size,
        },
        filter: ShadowFilter::default(),
    });
    let spot_position = centre + Vec3::new(extent, extent, 2.0 * extent);
    scene.lights = vec![
        Light {
            kind: LightKind::Distant,
            direction: Vec3::new(0.8, 0.45, -0.5),
            intensity: 0.8,
            shadow: shadow.clone(),
            ..Light::default()
        },
        Light {
            shadow,
            cone_angle_degrees: 40.0,
            ..Light::spot(
                spot_position,
                centre - spot_position,
                Vec3::ONE,
                6.0 * extent * extent,
            )
        },
    ];
    scene.ambient = 0.1;
    scene
}

fn prepare(scene: &Scene, model: &Model) -> Result<PreparedScene, BenchError> {
    let ground = Model::load(ground_path())
        .map_err(|e| BenchError::Config(format!("{}: {e}", ground_path().display())))?;
    PreparedScene::new(scene, &[model.clone(), ground])
        .map_err(|e| BenchError::Config(format!("scene: {e}")))
}

fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times[times.len() / 2]
}

fn run(args: &Args) -> Result<(), BenchError> {
    let (name, model) = load_model(&args.model)?;
    let beauty_spp1 = prepare(&scene(&name, &model, args, 1, false), &model)?;
    let frame = prepare(&scene(&name, &model, args, args.spp, false), &model)?;
    let shadowed = prepare(&scene(&name, &model, args, args.spp, true), &model)?;
    let depth_pass = depth_passes(&shadowed)
        .into_iter()
        .next()
        .ok_or_else(|| BenchError::Config("the shadowed scene has no depth pass".into()))?
        .scene;
    let cases: [(&str, &PreparedScene); 4] = [
        ("beauty spp 1", &beauty_spp1),
        ("depth pass", &depth_pass),
        ("frame", &frame),
        ("frame + 2 shadows", &shadowed),
    ];
    let gpu = reyes::gpu::create_gpu().map_err(|e| BenchError::Config(format!("GPU: {e}")))?;
    let mut renderer = renderer(&gpu)?;
    let mut times: Vec<Vec<Duration>> = vec![Vec::new(); cases.len()];
    let mut micropolygons = vec![0u64; cases.len()];
    for run in 0..=args.runs {
        for (i, (label, prepared)) in cases.iter().enumerate() {
            let start = Instant::now();
            let rendered = renderer
                .render(prepared)
                .map_err(|e| BenchError::Config(format!("{label}: {e}")))?;
            let wall = start.elapsed();
            // A shadowed frame lists every pass, itself included.
            micropolygons[i] = if rendered.stats.passes.is_empty() {
                rendered.stats.micropolygons
            } else {
                rendered.stats.passes.iter().map(|p| p.micropolygons).sum()
            };
            eprintln!(
                "run {run}/{}: {label}: {:.1} ms{}",
                args.runs,
                wall.as_secs_f64() * 1e3,
                if run == 0 { " (warm-up)" } else { "" }
            );
            if run > 0 {
                times[i].push(wall);
            }
            for pass in &rendered.stats.passes {
                eprintln!(
                    "    {}: {} micropolygons, {:.1} ms",
                    pass.name,
                    pass.micropolygons,
                    pass.frame_time_ms.unwrap_or(f64::NAN)
                );
            }
        }
    }
    let medians: Vec<Duration> = times.into_iter().map(median).collect();
    println!(
        "shadow-bench: {name}, {0}x{0} frame, {1}x{1} maps, spp {2}, median of {3} runs (wall time of render)",
        args.size, args.map_size, args.spp, args.runs
    );
    println!("{:<22} {:>12} {:>15}", "case", "median ms", "micropolygons");
    for (i, (label, _)) in cases.iter().enumerate() {
        println!(
            "{label:<22} {:>12.1} {:>15}",
            medians[i].as_secs_f64() * 1e3,
            micropolygons[i]
        );
    }
    let ratio = |a: usize, b: usize| medians[a].as_secs_f64() / medians[b].as_secs_f64();
    println!(
        "depth pass / beauty spp 1:        {:.2} (goal <= 1)",
        ratio(1, 0)
    );
    println!(
        "frame + 2 shadows / frame:        {:.2} (goal <= 1.5)",
        ratio(3, 2)
    );
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("shadow-bench: {e}");
            ExitCode::FAILURE
        }
    }
}
