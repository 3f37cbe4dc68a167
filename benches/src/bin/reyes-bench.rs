//! The Reyes GPU renderer on the teapot and the Killeroo: dicing to the
//! shading rate against the fixed 16 x 16 dicer, side by side in one run.
//!
//! ```text
//! cargo run --release -p benches --bin reyes-bench -- [--frames 5] [--spp 1,16]
//!     [--resolutions 800x600,1920x1080] [--rates 0.25,1,4,16] [--no-rounds]
//!     [--tables dicing,rates,interpolation,rounds,materials] [--killeroo PATH]
//! ```
//!
//! Prints five markdown tables measured in this one process:
//! 1. **Dicing**: every model, resolution and spp, rendered with `--dicing
//!    rate` and `--dicing fixed` in alternating frames (so both see the
//!    same machine load), with the median frame times, the grids,
//!    micropolygons per sample hit, the dice procedures' thread utilization
//!    and the ratio fixed / rate.
//! 2. **Shading rates**: each model at the first resolution, spp 1, for
//!    every `--rates` value.
//! 3. **Shading interpolation**: smooth against constant shading, each
//!    model at the first resolution and every spp, in alternating frames.
//! 4. **Megakernel vs. Rounds** on the rate-dicing graph, each model at the
//!    first resolution and spp 1, in alternating frames.
//! 5. **Materials**: RenderMan's `plastic` against the built-in WGSL
//!    `paintedplastic` with `docs/scenes/tiles.png`, each model at the
//!    first resolution and spp 1, in alternating frames: the look-development
//!    bound (a textured Killeroo within 1.5x of the plain one).
//!
//! Per configuration one warm-up frame creates the pipelines, the executor
//! and the buffers; the time reported is the median of `--frames` frames:
//! the megakernel's GPU time (timestamp queries) when the device has them,
//! else the whole frame's wall time. The Killeroo is read from
//! `<workspace>/../shared/data/` (or `--killeroo`) and skipped with a notice
//! when absent.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use reyes::gpu::{GpuOptions, GpuRendered, GpuRenderer};
use reyes::model::Model;
use reyes::prepare::PreparedScene;
use reyes::scene::{CameraDesc, Dicing, Scene, ShaderValue, ShadingInterpolation, Surface};
use scheduler::Strategy;

#[derive(Debug, Parser)]
#[command(about = "Reyes GPU renderer: rate dicing vs. the fixed dicer, shading rates, strategies")]
struct Args {
    /// Timed frames per configuration (median reported), after one warm-up frame.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    frames: u32,
    /// Samples per pixel of the dicing table.
    #[arg(long, value_delimiter = ',', default_values_t = [1, 16])]
    spp: Vec<u32>,
    /// Resolutions of the dicing table, `WxH`; the first one is used by the
    /// other tables.
    #[arg(long, value_delimiter = ',', default_values_t = ["800x600".to_owned(), "1920x1080".to_owned()])]
    resolutions: Vec<String>,
    /// Shading rates of the shading-rate table.
    #[arg(long, value_delimiter = ',', default_values_t = [0.25, 1.0, 4.0, 16.0])]
    rates: Vec<f32>,
    /// Skip the megakernel vs. Rounds table.
    #[arg(long)]
    no_rounds: bool,
    /// The tables to measure (default: all five).
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = Table::ALL)]
    tables: Vec<Table>,
    /// The Killeroo's patch file (default: `<workspace>/../shared/data/killeroo.bpt`).
    #[arg(long, default_value_os_t = killeroo_path())]
    killeroo: PathBuf,
}

/// One of the benchmark's tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Table {
    /// Rate dicing vs. the fixed dicer.
    Dicing,
    /// The shading-rate sweep.
    Rates,
    /// Smooth vs. constant shading.
    Interpolation,
    /// Megakernel vs. Rounds.
    Rounds,
    /// `plastic` vs. the textured `paintedplastic`.
    Materials,
}

impl Table {
    const ALL: [Table; 5] = [
        Table::Dicing,
        Table::Rates,
        Table::Interpolation,
        Table::Rounds,
        Table::Materials,
    ];
}

impl std::fmt::Display for Table {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use clap::ValueEnum;
        let value = self.to_possible_value().ok_or(std::fmt::Error)?;
        f.write_str(value.get_name())
    }
}

fn killeroo_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/killeroo.bpt")
}

/// The texture of the materials table: the one docs/shaders.md's gallery paints.
fn tiles_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/scenes/tiles.png")
}

/// The built-in `paintedplastic` with `plastic`'s defaults (its own
/// `DEFAULTS`) and `texture`, so that it differs from [`Surface::PLASTIC`]
/// only by the texture lookup and the WGSL call.
fn painted_plastic(texture: &std::path::Path) -> Surface {
    Surface::Wgsl {
        file: PathBuf::from("builtin:paintedplastic"),
        parameters: BTreeMap::from([(
            "texturename".to_owned(),
            ShaderValue::Text(texture.to_string_lossy().into_owned()),
        )]),
    }
}

/// `scene` with every object shaded by `surface`.
fn with_surface(mut scene: Scene, surface: &Surface) -> Scene {
    for object in &mut scene.objects {
        object.surface = Some(surface.clone());
    }
    scene
}

fn parse_resolution(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once('x')
        .ok_or_else(|| format!("resolution {text:?}: expected WxH"))?;
    let parse = |s: &str| {
        s.parse::<u32>()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("resolution {text:?}: {s:?} is not a positive integer"))
    };
    Ok((parse(w)?, parse(h)?))
}

/// `scene` at `width x height`, framed again for that aspect ratio.
fn sized(mut scene: Scene, model: &Model, width: u32, height: u32, spp: u32) -> Scene {
    scene.resolution.width = width;
    scene.resolution.height = height;
    scene.spp = spp;
    let (lo, hi) = model.bounds();
    scene.camera = Some(CameraDesc::framing(lo, hi, width as f32 / height as f32));
    scene
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// The frames of one configuration: their times and the last frame.
struct Measured {
    ms: Vec<f64>,
    last: Option<GpuRendered>,
}

impl Measured {
    fn new() -> Self {
        Self {
            ms: Vec::new(),
            last: None,
        }
    }

    fn add(&mut self, frame: GpuRendered) {
        self.ms.push(
            frame
                .timings
                .megakernel_gpu_ms
                .unwrap_or(frame.timings.total_wall_ms),
        );
        self.last = Some(frame);
    }

    fn median_ms(&self) -> f64 {
        median(self.ms.clone())
    }

    fn frame(&self) -> &GpuRendered {
        self.last.as_ref().expect("at least one frame")
    }
}

/// Renders each of `configs` once to warm up, then `frames` times in
/// alternation; progress goes to stderr.
fn measure(
    configs: &mut [(&mut GpuRenderer<'_>, &PreparedScene)],
    frames: u32,
    label: &str,
) -> Result<Vec<Measured>, Box<dyn std::error::Error>> {
    for (renderer, scene) in configs.iter_mut() {
        renderer.render(scene)?;
    }
    let mut measured: Vec<Measured> = configs.iter().map(|_| Measured::new()).collect();
    for frame in 0..frames {
        for ((renderer, scene), m) in configs.iter_mut().zip(&mut measured) {
            m.add(renderer.render(scene)?);
        }
        eprintln!("{label}: frame {}/{frames}", frame + 1);
    }
    Ok(measured)
}

fn grids(frame: &GpuRendered) -> String {
    let [s, m, l] = frame.stats.grids_by_class;
    format!("{s}/{m}/{l}")
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let resolutions = args
        .resolutions
        .iter()
        .map(|r| parse_resolution(r))
        .collect::<Result<Vec<_>, _>>()?;
    let Some(&first) = resolutions.first() else {
        return Err("--resolutions needs at least one resolution".into());
    };
    let gpu = reyes::gpu::create_gpu()?;
    let device = gpu.describe();
    let mut models: Vec<(&str, Scene, Model)> =
        vec![("teapot", Scene::default_teapot(), Model::teapot())];
    let killeroo = &args.killeroo;
    if killeroo.exists() {
        let model = Model::load(killeroo)?;
        let scene = Scene::for_model(killeroo.to_string_lossy(), &model);
        models.push(("killeroo", scene, model));
    } else {
        println!(
            "NOTICE: {} not found; skipping the Killeroo rows",
            killeroo.display()
        );
    }
    let options = GpuOptions {
        // Large frames with the fixed dicer take a while on a software rasterizer.
        timeout: Duration::from_secs(600),
        ..GpuOptions::default()
    };
    let mut renderer = GpuRenderer::new(&gpu, options.clone())?;
    let mut fixed_renderer = GpuRenderer::new(&gpu, options.clone())?;
    let prepare = |scene: &Scene, model: &Model, (w, h): (u32, u32), spp, dicing, rate| {
        let mut scene = sized(scene.clone(), model, w, h, spp);
        scene.dicing = dicing;
        scene.shading_rate = rate;
        PreparedScene::load(&scene)
    };

    println!("device: {device}");
    let wants = |table: Table| args.tables.contains(&table);
    if wants(Table::Dicing) {
        println!(
            "\n### Dicing: to the shading rate (1) vs. the fixed 16 x 16 dicer\n\nMedian of {} frames after a warm-up, in alternating frames; ms = megakernel GPU time (timestamp queries) where the device has them, else the frame's wall time; mp/hit = micropolygons per sample hit; util = the dice procedures' thread utilization; grids = small/medium/large.\n",
            args.frames
        );
        println!(
            "| model | resolution | spp | rate ms | fixed ms | fixed / rate | rate grids | rate micropolygons | rate mp/hit | rate util | fixed micropolygons | fixed mp/hit | retries |"
        );
        println!("|---|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|");
        for (name, scene, model) in &models {
            for &(w, h) in &resolutions {
                for &spp in &args.spp {
                    let rate = prepare(scene, model, (w, h), spp, Dicing::Rate, 1.0)?;
                    let fixed = prepare(scene, model, (w, h), spp, Dicing::Fixed, 1.0)?;
                    let label = format!("{name} {w}x{h} spp {spp}");
                    let m = measure(
                        &mut [(&mut renderer, &rate), (&mut fixed_renderer, &fixed)],
                        args.frames,
                        &label,
                    )?;
                    let (r, f) = (m[0].frame(), m[1].frame());
                    println!(
                        "| {name} | {w}x{h} | {spp} | {:.1} | {:.1} | {:.2} | {} | {} | {:.2} | {:.2} | {} | {:.2} | {} |",
                        m[0].median_ms(),
                        m[1].median_ms(),
                        m[1].median_ms() / m[0].median_ms(),
                        grids(r),
                        r.stats.micropolygons,
                        r.stats.micropolygons_per_hit(),
                        r.stats.thread_utilization(),
                        f.stats.micropolygons,
                        f.stats.micropolygons_per_hit(),
                        r.overflow_retries + r.loop_retries + f.overflow_retries + f.loop_retries,
                    );
                }
            }
        }
    }

    if wants(Table::Rates) {
        println!(
            "\n### Shading rates ({}x{}, spp 1)\n\n| model | shading rate | ms | grids | micropolygons | samples hit | mp/hit | util | largest micropolygon px |\n|---|---:|---:|---|---:|---:|---:|---:|---:|",
            first.0, first.1
        );
        for (name, scene, model) in &models {
            for &rate in &args.rates {
                let prepared = prepare(scene, model, first, 1, Dicing::Rate, rate)?;
                let m = measure(
                    &mut [(&mut renderer, &prepared)],
                    args.frames,
                    &format!("{name} shading rate {rate}"),
                )?;
                let s = &m[0].frame().stats;
                println!(
                    "| {name} | {rate} | {:.1} | {} | {} | {} | {:.2} | {:.2} | {:.2} |",
                    m[0].median_ms(),
                    grids(m[0].frame()),
                    s.micropolygons,
                    s.samples_hit,
                    s.micropolygons_per_hit(),
                    s.thread_utilization(),
                    s.largest_micropolygon_px,
                );
            }
        }
    }

    if wants(Table::Interpolation) {
        println!(
            "\n### Shading interpolation: smooth vs. constant ({}x{}, shading rate 1)\n\n| model | spp | smooth ms | constant ms | smooth / constant | samples hit |\n|---|---:|---:|---:|---:|---:|",
            first.0, first.1
        );
        let mut constant_renderer = GpuRenderer::new(&gpu, options.clone())?;
        for (name, scene, model) in &models {
            for &spp in &args.spp {
                let smooth = prepare(scene, model, first, spp, Dicing::Rate, 1.0)?;
                let mut constant_scene = sized(scene.clone(), model, first.0, first.1, spp);
                constant_scene.shading_interpolation = ShadingInterpolation::Constant;
                let constant = PreparedScene::load(&constant_scene)?;
                let m = measure(
                    &mut [
                        (&mut renderer, &smooth),
                        (&mut constant_renderer, &constant),
                    ],
                    args.frames,
                    &format!("{name} spp {spp} shading interpolation"),
                )?;
                println!(
                    "| {name} | {spp} | {:.1} | {:.1} | {:.3} | {} |",
                    m[0].median_ms(),
                    m[1].median_ms(),
                    m[0].median_ms() / m[1].median_ms(),
                    m[0].frame().stats.samples_hit,
                );
            }
        }
    }

    if wants(Table::Rounds) && !args.no_rounds {
        let mut rounds = GpuRenderer::new(
            &gpu,
            GpuOptions {
                strategy: Strategy::rounds(),
                ..options.clone()
            },
        )?;
        println!(
            "\n### Megakernel vs. Rounds, rate dicing ({}x{}, spp 1)\n\n| model | megakernel ms | Rounds ms | Rounds / megakernel | rounds |\n|---|---:|---:|---:|---:|",
            first.0, first.1
        );
        for (name, scene, model) in &models {
            let prepared = prepare(scene, model, first, 1, Dicing::Rate, 1.0)?;
            let m = measure(
                &mut [(&mut renderer, &prepared), (&mut rounds, &prepared)],
                args.frames,
                &format!("{name} strategies"),
            )?;
            let round_count = m[1].frame().report.as_ref().map_or(0, |r| r.rounds);
            println!(
                "| {name} | {:.1} | {:.1} | {:.2} | {round_count} |",
                m[0].median_ms(),
                m[1].median_ms(),
                m[1].median_ms() / m[0].median_ms(),
            );
        }
    }

    if wants(Table::Materials) {
        let tiles = tiles_path();
        println!(
            "\n### Materials: paintedplastic vs. plastic ({}x{}, spp 1)\n\nMedian of {} frames after a warm-up, in alternating frames; ms as in the dicing table (the megakernel's GPU time, which includes the shading). plastic is RenderMan's with its defaults; paintedplastic is the built-in WGSL shader with the same defaults and `docs/scenes/tiles.png` over s, t (each patch's u, v where the model has no st).\n\n| model | plastic ms | paintedplastic ms | paintedplastic / plastic |\n|---|---:|---:|---:|",
            first.0, first.1, args.frames
        );
        let mut painted_renderer = GpuRenderer::new(&gpu, options)?;
        for (name, scene, model) in &models {
            let plain = with_surface(scene.clone(), &Surface::PLASTIC);
            let plain = prepare(&plain, model, first, 1, Dicing::Rate, 1.0)?;
            let painted = with_surface(scene.clone(), &painted_plastic(&tiles));
            let painted = prepare(&painted, model, first, 1, Dicing::Rate, 1.0)?;
            let m = measure(
                &mut [(&mut renderer, &plain), (&mut painted_renderer, &painted)],
                args.frames,
                &format!("{name} materials"),
            )?;
            println!(
                "| {name} | {:.1} | {:.1} | {:.2} |",
                m[0].median_ms(),
                m[1].median_ms(),
                m[1].median_ms() / m[0].median_ms(),
            );
        }
    }
    Ok(())
}
