//! `blur-bench`: the 5D sampling modes side by side on a spinning model.
//!
//! ```text
//! cargo run --release -p benches --bin blur-bench -- [--model killeroo|teapot|FILE]
//!     [--width 800] [--height 600] [--spp 16,64] [--runs 5] [--no-warm-up]
//!     [--blurs motion,dof,both,pan] [--pan 5] [--modes bbox,simple,...]
//!     [--interleave-tile 2|3|4]
//!     [--table] [--adaptive]
//! ```
//!
//! `--table` (default) prints time, samples tested and skipped, and sample
//! test efficiency of every mode for motion blur alone (a 30 degree spin),
//! depth of field alone, and both;
//! `--blurs pan` adds camera motion (the camera panning 5 degrees), and
//! `--blurs mixed` a mixed scene: the spinning model beside a still copy.
//! `--adaptive` checks Adaptive against the better of INTERVAL and
//! Interleave UVT for small, medium and large spins, with and without depth
//! of field: its median must stay within 5% of the better one's
//! (`ADAPTIVE_TOLERANCE`).

use std::process::ExitCode;

use benches::blur::{
    BlurConfig, adaptive_ratio, format_rows, load_model, measure, renderer, scene,
};
use clap::Parser;
use reyes::prepare::PreparedScene;
use reyes::scene::Sampling;

#[derive(Debug, Parser)]
#[command(about = "Motion blur and depth of field: the sampling modes side by side")]
struct Args {
    /// `killeroo` (from ../shared/data), `teapot`, or a .bpt/.bez path.
    #[arg(long, default_value = "killeroo")]
    model: String,
    /// Image width.
    #[arg(long, default_value_t = 800)]
    width: u32,
    /// Image height.
    #[arg(long, default_value_t = 600)]
    height: u32,
    /// Samples per pixel to measure.
    #[arg(long, value_delimiter = ',', default_values_t = [16, 64])]
    spp: Vec<u32>,
    /// Timed frames per cell (after one warm-up frame, unless --no-warm-up).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    runs: u32,
    /// Time every frame, the first included (which also gives the counts).
    /// The times are GPU timestamps of the megakernel, which exclude
    /// pipeline creation, so this halves the cost of a single-run table.
    #[arg(long)]
    no_warm_up: bool,
    /// Rows of the table: `motion` (spin alone), `dof` (lens alone), `both`,
    /// `pan` (the camera panning, the model still).
    #[arg(long, value_delimiter = ',', default_values_t = ["motion".to_string(), "dof".into(), "both".into()])]
    blurs: Vec<String>,
    /// Degrees of spin of the table's motion-blur rows.
    #[arg(long, default_value_t = 30.0)]
    spin: f32,
    /// Degrees the camera pans during the shutter in the `pan` rows.
    #[arg(long, default_value_t = 5.0, allow_hyphen_values = true)]
    pan: f32,
    /// Lens radius of the depth-of-field rows, as a fraction of the model's
    /// bounding-box diagonal.
    #[arg(long, default_value_t = 0.01)]
    aperture: f32,
    /// Spins (degrees) of the Adaptive check's small, medium and large blur.
    #[arg(long, value_delimiter = ',', default_values_t = [3.0, 10.0, 30.0])]
    blur_levels: Vec<f32>,
    /// Print the table of every mode (the default unless --adaptive is given).
    #[arg(long)]
    table: bool,
    /// Run the Adaptive acceptance check.
    #[arg(long)]
    adaptive: bool,
    /// Side, in pixels, of Interleave UVT's tiles (Interleave and Adaptive).
    #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(2..=4))]
    interleave_tile: u32,
    /// Modes of the table.
    #[arg(long, value_delimiter = ',', default_values_t = ["bbox".to_string(), "simple".into(), "interleave".into(), "interval".into(), "adaptive".into()])]
    modes: Vec<String>,
}

/// How much slower than the better of INTERVAL and Interleave UVT Adaptive
/// may be in a cell of the acceptance check.
const ADAPTIVE_TOLERANCE: f64 = 1.05;

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!(
                "blur-bench: Adaptive was more than 5% slower than the better mode somewhere"
            );
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("blur-bench: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn mode(name: &str) -> Result<Sampling, Box<dyn std::error::Error>> {
    Sampling::ALL
        .into_iter()
        .find(|m| m.name() == name && m.supports_blur())
        .ok_or_else(|| format!("unknown 5D sampling mode {name:?}").into())
}

/// A table row's blur: the spin alone, the lens alone, both, or the camera's pan.
fn blur(name: &str, args: &Args) -> Result<BlurConfig, Box<dyn std::error::Error>> {
    let (spin_degrees, aperture_fraction, pan_degrees, still_copy) = match name {
        "motion" => (args.spin, 0.0, 0.0, false),
        "dof" => (0.0, args.aperture, 0.0, false),
        "both" => (args.spin, args.aperture, 0.0, false),
        "pan" => (0.0, 0.0, args.pan, false),
        "mixed" => (args.spin, 0.0, 0.0, true),
        other => {
            return Err(format!("unknown blur {other:?} (motion, dof, both, pan or mixed)").into());
        }
    };
    Ok(BlurConfig {
        spin_degrees,
        aperture_fraction,
        pan_degrees,
        still_copy,
    })
}

fn run(args: &Args) -> Result<bool, Box<dyn std::error::Error>> {
    let command_line = std::env::args().collect::<Vec<_>>().join(" ");
    let gpu = reyes::gpu::create_gpu()?;
    println!("command: {command_line}");
    println!("adapter: {}", gpu.describe());
    let (model_name, model) = load_model(&args.model)?;
    println!(
        "scene: {} ({} patches), {}x{}, seen from 60 degrees above",
        args.model,
        model.patches.len(),
        args.width,
        args.height
    );
    let mut renderer = renderer(&gpu)?;
    let prepare = |config: BlurConfig, spp: u32, modes: &[Sampling]| {
        modes
            .iter()
            .map(|&m| {
                let mut s = scene(&model_name, &model, config, args.width, args.height, spp, m);
                s.interleave_tile = args.interleave_tile;
                // One model per object (the mixed scene has two).
                let models = vec![model.clone(); s.objects.len()];
                PreparedScene::new(&s, &models).map(|p| (m, p))
            })
            .collect::<Result<Vec<_>, _>>()
    };
    let mut accepted = true;
    if args.table || !args.adaptive {
        let modes = args
            .modes
            .iter()
            .map(|m| mode(m))
            .collect::<Result<Vec<_>, _>>()?;
        let configs = args
            .blurs
            .iter()
            .map(|b| blur(b, args))
            .collect::<Result<Vec<_>, _>>()?;
        let mut rows = Vec::new();
        for &spp in &args.spp {
            for &config in &configs {
                let measured = measure(
                    &mut renderer,
                    &prepare(config, spp, &modes)?,
                    config,
                    args.runs,
                    !args.no_warm_up,
                );
                eprint!("{}", format_rows(&measured));
                rows.extend(measured);
            }
        }
        println!("\n{}", format_rows(&rows));
    }
    if args.adaptive {
        let modes = [Sampling::Interval, Sampling::Interleave, Sampling::Adaptive];
        println!(
            "\n{:<22}{:>5}{:>14}{:>14}{:>14}{:>9}  verdict",
            "blur", "spp", "interval ms", "interleave ms", "adaptive ms", "ratio"
        );
        for &spp in &args.spp {
            for &spin in &args.blur_levels {
                for aperture_fraction in [0.0, args.aperture] {
                    let config = BlurConfig {
                        spin_degrees: spin,
                        aperture_fraction,
                        pan_degrees: 0.0,
                        still_copy: false,
                    };
                    let rows = measure(
                        &mut renderer,
                        &prepare(config, spp, &modes)?,
                        config,
                        args.runs,
                        !args.no_warm_up,
                    );
                    // The cell's rows (counts, grids sent to Interleave,
                    // retries) go to stderr, the verdicts to stdout.
                    eprint!("{}", format_rows(&rows));
                    let ms = |i: usize| {
                        rows[i]
                            .1
                            .as_ref()
                            .map_or(f64::NAN, |r| r.median.as_secs_f64() * 1e3)
                    };
                    let ratio = adaptive_ratio(&rows).unwrap_or(f64::NAN);
                    // A failed frame (NaN) fails the check.
                    let ok = ratio <= ADAPTIVE_TOLERANCE;
                    accepted &= ok;
                    println!(
                        "{:<22}{:>5}{:>14.1}{:>14.1}{:>14.1}{:>9.3}  {}",
                        config.label(),
                        spp,
                        ms(0),
                        ms(1),
                        ms(2),
                        ratio,
                        if ok { "ok" } else { "SLOWER" }
                    );
                }
            }
        }
    }
    Ok(accepted)
}
