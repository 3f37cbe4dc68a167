//! `reyes`: render a scene or a Bezier patch model on the GPU.
//!
//! ```text
//! reyes render [SCENE] -o out.png [--width W] [--height H] [--spp N]
//!              [--sampling bbox|simple|interleave|interval|adaptive|nearest] [--interleave-tile 2|3|4]
//!              [--stats] [--stats-json FILE]
//!              [--spin DEG] [--move x,y,z] [--camera-move x,y,z] [--camera-pan DEG]
//!              [--shutter F] [--aperture R] [--focus D]
//!              [--eye x,y,z] [--target x,y,z] [--up x,y,z] [--fov DEG] [--cpu]
//!              [--displace bumps|sines|FILE.png|FILE.wgsl --displace-scale S
//!               [--displace-bound B] [--displace-tiling T]] [--timeout SECONDS]
//!              [--chunks N] [--dicing rate|fixed] [--shading-rate R] [--shading-interpolation smooth|constant] [--flat-shading]
//!              [--aov shaded|grids|depth|normal] [--sides 1|2] [--reverse-orientation]
//!              [--max-input-bytes BYTES]
//! reyes view [SCENE] [the options of render] [--frames N --screenshot PNG] [--hide-overlay]
//! ```

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use glam::Vec3;
use reyes::aov::Aov;
use reyes::displacement::DisplacementDesc;
use reyes::displacement::desc::{SOURCE_BUMPS, SOURCE_SINES, SOURCE_WGSL};
use reyes::gpu::{GpuOptions, GpuRenderer};
use reyes::input::{InputKind, Limits};
use reyes::model::Model;
use reyes::prepare::{PreparedScene, far_plane_covering_motion};
use reyes::scene::{CameraDesc, Dicing, Sampling, Scene, ShadingInterpolation};
use reyes::stats::RenderStats;

#[derive(Debug, Parser)]
#[command(
    name = "reyes",
    version,
    about = "A Reyes renderer for bicubic Bezier patches on the GPU"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
#[allow(
    clippy::large_enum_variant,
    reason = "one command is parsed once per process"
)]
enum Command {
    /// Render a scene (.toml or RenderMan .rib), a model (.bpt/.bez) or,
    /// without SCENE, the teapot.
    Render(RenderArgs),
    /// Convert a RenderMan RIB scene to a TOML scene plus `.bpt` models
    /// (written beside the TOML as `<stem>-<i>.bpt`).
    Convert(ConvertArgs),
    /// Open a window on a scene (the inputs and options of `render`), orbit
    /// it with the mouse and re-render as the view changes. `-o` names the
    /// PNG that `P` saves (default `reyes-view.png`).
    #[cfg(feature = "viewer")]
    View(ViewArgs),
}

#[cfg(feature = "viewer")]
#[derive(Debug, clap::Args)]
struct ViewArgs {
    #[command(flatten)]
    render: RenderArgs,
    /// Close after N frames have been presented and the view is refined
    /// (for headless use under `xvfb-run`).
    #[arg(long, value_name = "N")]
    frames: Option<u64>,
    /// With --frames: save the last presented image as this PNG.
    #[arg(long, value_name = "PNG", requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Start with the overlay hidden (`H` shows it).
    #[arg(long)]
    hide_overlay: bool,
    /// Scripted input steps (see `reyes::view::script`), for tests.
    #[arg(long, value_name = "STEPS", hide = true)]
    script: Option<String>,
    /// Write what was rendered (cameras, frame times) as JSON, for tests.
    #[arg(long, value_name = "FILE", hide = true)]
    log_json: Option<PathBuf>,
}

/// `reyes view`: the viewer on the scene `render` would draw.
#[cfg(feature = "viewer")]
fn view(args: &ViewArgs) -> Result<(), BoxError> {
    let render = &args.render;
    if render.cpu {
        return Err("reyes view renders on the GPU: --cpu does not apply".into());
    }
    if render.stats || render.stats_json.is_some() {
        return Err(
            "reyes view shows the statistics in its overlay: --stats and --stats-json do not apply"
                .into(),
        );
    }
    if let Some(bytes) = render.max_input_bytes {
        reyes::input::set_limits(Limits::all(bytes));
    }
    let script = match &args.script {
        Some(text) => reyes::view::script::parse(text)?,
        None => Vec::new(),
    };
    let scene = prepare(render)?;
    let mut gpu_options = GpuOptions::default();
    if let Some(seconds) = render.timeout {
        gpu_options.timeout = std::time::Duration::from_secs(seconds.max(1));
    }
    gpu_options.chunks_per_batch = render.chunks;
    let command = reyes::view::save::CommandBase {
        prefix: render_prefix(std::env::args().collect()),
        shutter: render.shutter,
        dice_threshold: scene.dice_threshold,
    };
    let config = reyes::view::ViewConfig {
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        script,
        overlay: !args.hide_overlay,
        save_path: render
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from("reyes-view.png")),
        command,
        gpu_options,
        ..Default::default()
    };
    let log = reyes::view::run(scene, config)?;
    if let Some(path) = &args.log_json {
        std::fs::write(path, serde_json::to_string_pretty(&log)?)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(())
}

/// `reyes render` and the `reyes view` arguments it shares, without those
/// the viewer sets itself (the camera, the resolution, the settings it can
/// change, the output) or that only the viewer has.
#[cfg(feature = "viewer")]
fn render_prefix(argv: Vec<String>) -> Vec<String> {
    // Options followed by a value.
    const SET_BY_VIEW: [&str; 16] = [
        "--width",
        "--height",
        "--eye",
        "--target",
        "--up",
        "--fov",
        "--spp",
        "--sampling",
        "--shading-rate",
        "--aov",
        "--aperture",
        "--focus",
        "--shutter",
        "-o",
        "--output",
        "--frames",
    ];
    const VIEW_ONLY: [&str; 3] = ["--screenshot", "--script", "--log-json"];
    let mut prefix = vec!["reyes".to_owned(), "render".to_owned()];
    let mut args = argv.into_iter().skip_while(|a| a != "view").skip(1);
    while let Some(arg) = args.next() {
        let name = arg.split_once('=').map_or(arg.as_str(), |(n, _)| n);
        let takes_value = SET_BY_VIEW.contains(&name) || VIEW_ONLY.contains(&name);
        if takes_value {
            if !arg.contains('=') {
                args.next();
            }
        } else if arg != "--hide-overlay" {
            prefix.push(arg);
        }
    }
    prefix
}

#[derive(Debug, clap::Args)]
struct ConvertArgs {
    /// The ASCII RIB file.
    input: PathBuf,
    /// The TOML scene to write.
    #[arg(short, long)]
    output: PathBuf,
}

/// `reyes convert`: RIB to TOML plus `.bpt` files.
fn convert(args: &ConvertArgs) -> Result<(), BoxError> {
    let rib = reyes::rib::RibScene::load(&args.input)?;
    for warning in &rib.warnings {
        eprintln!("warning: {warning}");
    }
    let written = rib.write(&args.output)?;
    for path in &written {
        println!("wrote {}", path.display());
    }
    if let Some(display) = &rib.display {
        println!(
            "the RIB's Display file is {display}: reyes render writes the image there unless -o is given"
        );
    }
    Ok(())
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum SamplingArg {
    /// Test every sample in each micropolygon triangle's bounding box
    /// (grown by its motion and circle of confusion).
    Bbox,
    /// Simple UVT: one time/lens tuple per sample index, shared by all pixels.
    Simple,
    /// Interleave UVT: 2x2-pixel tiles with 4 * spp distinct tuples.
    Interleave,
    /// INTERVAL: one box per time interval.
    Interval,
    /// INTERVAL or Interleave UVT per grid, whichever is cheaper.
    Adaptive,
    /// Write only the sample nearest each micropolygon's centroid (no blur).
    Nearest,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum DicingArg {
    /// Grids sized to the shading rate, watertight.
    Rate,
    /// 16 x 16 points for every piece under the dice threshold.
    Fixed,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum InterpolationArg {
    /// Each sample blends its triangle's corner colours.
    Smooth,
    /// One colour per micropolygon.
    Constant,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum AovArg {
    /// The shaded surface.
    Shaded,
    /// Micropolygons coloured by their grid's size.
    Grids,
    /// Grey by view depth.
    Depth,
    /// The shading normal.
    Normal,
}

#[derive(Debug, clap::Args)]
struct RenderArgs {
    /// A scene file (.toml) or a bare model (.bpt/.bez, framed automatically
    /// with a default light). Default: the embedded teapot.
    scene: Option<PathBuf>,
    /// Output image; the extension chooses the format: `.png` (8-bit sRGB)
    /// or `.exr` (OpenEXR, float linear RGBA), case-insensitive. Missing
    /// directories are created. Checked before rendering, written through a
    /// temporary file renamed over it, so a failure leaves no partial file.
    /// Default: a RIB scene's `Display` file (relative to the current
    /// directory), else `reyes.png`.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Image width in pixels (default: the scene's, 800).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels (default: the scene's, 600).
    #[arg(long)]
    height: Option<u32>,
    /// Samples per pixel: 1, 4, 9, 16, 25, 36, 49 or 64 (default: the scene's, 4).
    #[arg(long)]
    spp: Option<u32>,
    /// Sampling mode (default: the scene's, bbox).
    #[arg(long, value_enum)]
    sampling: Option<SamplingArg>,
    /// Side, in pixels, of Interleave UVT's tiles: 2, 3 or 4 (default: the
    /// scene's, 2). Interleave UVT and Adaptive use it.
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(2..=4))]
    interleave_tile: Option<u32>,
    /// How pieces are diced (default: the scene's, rate).
    #[arg(long, value_enum)]
    dicing: Option<DicingArg>,
    /// Target micropolygon area in pixels for rate dicing (default: the
    /// scene's, 1).
    #[arg(long, value_name = "R")]
    shading_rate: Option<f32>,
    /// How colour varies over a micropolygon (default: the scene's, smooth).
    #[arg(long, value_enum)]
    shading_interpolation: Option<InterpolationArg>,
    /// One colour per micropolygon, the mean of its corners' (the same as
    /// `--shading-interpolation constant`).
    #[arg(long, conflicts_with = "shading_interpolation")]
    flat_shading: bool,
    /// What the image shows: the shaded surface, each micropolygon coloured
    /// by its grid's size (checkered), the view depth or the shading normal.
    #[arg(long, value_enum)]
    aov: Option<AovArg>,
    /// 1: draw only the front of every object (RenderMan's `Sides 1`;
    /// default: the scene's, 2).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=2))]
    sides: Option<u8>,
    /// The front of every object is the other side (RenderMan's
    /// `ReverseOrientation`).
    #[arg(long)]
    reverse_orientation: bool,
    /// Print the statistics table.
    #[arg(long)]
    stats: bool,
    /// Write the statistics as JSON to FILE (any name but the image's;
    /// missing directories are created, as for `-o`). The image and FILE
    /// are replaced together, or neither is.
    #[arg(long, value_name = "FILE")]
    stats_json: Option<PathBuf>,
    /// Camera position, e.g. `4,-12,7`.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    eye: Option<Vec3>,
    /// Point the camera looks at.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    target: Option<Vec3>,
    /// Camera up direction.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    up: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(long)]
    fov: Option<f32>,
    /// Render with the CPU reference instead of the GPU. It refuses frames
    /// whose RGBA image exceeds 128 MiB (as the GPU does) or whose sample
    /// framebuffer exceeds 2 GiB, and stops after 2^26 work items, 2^30
    /// micropolygons or the --timeout.
    #[arg(long)]
    cpu: bool,
    /// Displace every object: `bumps` (the embedded height map), `sines`
    /// (built-in procedural bumps), a grey PNG height map, or a `.wgsl` file
    /// defining `fn displacement_user(u: f32, v: f32) -> f32` (GPU only;
    /// needs --displace-bound). Replaces any displacement of the scene.
    #[arg(long, value_name = "SOURCE", requires = "displace_scale")]
    displace: Option<String>,
    /// World units of displacement per unit of height (negative: inwards).
    #[arg(
        long,
        value_name = "S",
        requires = "displace",
        allow_hyphen_values = true
    )]
    displace_scale: Option<f32>,
    /// Displacement bound in world units (default: |scale| * max height).
    #[arg(
        long,
        value_name = "B",
        requires = "displace",
        allow_hyphen_values = true
    )]
    displace_bound: Option<f32>,
    /// Repetitions of the displacement source per patch (default 1).
    #[arg(long, value_name = "T", requires = "displace")]
    displace_tiling: Option<f32>,
    /// Longest a frame may take, in seconds (default 600), on the GPU or
    /// with --cpu. On the GPU it includes the driver's first compile of the
    /// megakernel, which takes longer than a minute on lavapipe when its
    /// shader cache is cold (e.g. for a new `--displace FILE.wgsl` function).
    #[arg(long, value_name = "SECONDS")]
    timeout: Option<u64>,
    /// Chunks per batch of the megakernel, 1 to 64: how many workgroup-fulls
    /// of items one batch claims (default 4 on CPU adapters, else 1). The
    /// image is the same for any value. On lavapipe at most 4: its compile
    /// of the megakernel grows with the count (96 s at 2 chunks on a cold
    /// shader cache, 324 s at 8).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=i64::from(scheduler::MAX_CHUNKS_PER_BATCH)))]
    chunks: Option<u32>,
    /// Motion blur: spin every object by DEG degrees about its vertical
    /// (model z) axis between shutter open and close.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    spin: Option<f32>,
    /// Motion blur: move every object by this world-space vector between
    /// shutter open and close, e.g. `0.5,0,0`.
    #[arg(long = "move", value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    move_by: Option<Vec3>,
    /// Motion blur from camera motion: move the eye and the target by this
    /// world-space vector between shutter open and close, e.g. `0.2,0,0`.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    camera_move: Option<Vec3>,
    /// Motion blur from camera motion: pan the camera by DEG degrees about
    /// its up axis through the eye between shutter open and close (positive
    /// turns left, so the scene sweeps right), in (-180, 180); combines with
    /// `--camera-move`.
    #[arg(long, value_name = "DEG", value_parser = parse_pan, allow_hyphen_values = true)]
    camera_pan: Option<f32>,
    /// Fraction of the open-to-close motion the shutter sees, in [0, 1]
    /// (default: the scene's, 1).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    shutter: Option<f32>,
    /// Depth of field: lens radius in world units (default: the scene's, 0).
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    aperture: Option<f32>,
    /// Depth of field: distance in focus (default: the scene's, or the
    /// distance from the eye to the camera target).
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    focus: Option<f32>,
    /// Largest input file read, in bytes, for every kind of input: models,
    /// scenes, .wgsl functions and height-map PNGs (suffixes K, M, G, T:
    /// KiB, MiB, GiB, TiB). Default: 1G for models, 16M for scenes and
    /// .wgsl files, 64M for height maps. Only regular files are read.
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    max_input_bytes: Option<u64>,
}

/// A byte count: digits with an optional binary suffix K, M, G or T
/// (case-insensitive, an optional trailing `B` or `iB` allowed: `16M`, `2GiB`).
fn parse_bytes(text: &str) -> Result<u64, String> {
    let trimmed = text.trim();
    let upper = trimmed.to_ascii_uppercase();
    let unitless = upper
        .strip_suffix("IB")
        .or_else(|| upper.strip_suffix('B'))
        .unwrap_or(&upper);
    let (digits, shift) = match unitless.as_bytes().last() {
        Some(b'K') => (&unitless[..unitless.len() - 1], 10),
        Some(b'M') => (&unitless[..unitless.len() - 1], 20),
        Some(b'G') => (&unitless[..unitless.len() - 1], 30),
        Some(b'T') => (&unitless[..unitless.len() - 1], 40),
        _ => (unitless, 0),
    };
    let value: u64 = digits
        .trim()
        .parse()
        .map_err(|_| format!("{text:?} is not a byte count (e.g. 1048576, 512K, 16M, 2G)"))?;
    value
        .checked_mul(1u64 << shift)
        .ok_or_else(|| format!("{text:?} is too large"))
}

fn parse_vec3(text: &str) -> Result<Vec3, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected x,y,z (three comma-separated numbers), got {text:?}"
        ));
    }
    let mut v = [0.0f32; 3];
    for (slot, part) in v.iter_mut().zip(&parts) {
        *slot = part
            .parse()
            .map_err(|e| format!("{part:?} is not a number: {e}"))?;
        if !slot.is_finite() {
            return Err(format!("{part:?} is not finite"));
        }
    }
    Ok(Vec3::from_array(v))
}

/// A camera pan in degrees, within (-180, 180): the orientation in between
/// turns the shorter way (slerp), so a larger pan would turn the other way.
fn parse_pan(text: &str) -> Result<f32, String> {
    let degrees: f32 = text
        .trim()
        .parse()
        .map_err(|e| format!("{text:?} is not a number: {e}"))?;
    if degrees.abs() < 180.0 {
        Ok(degrees)
    } else {
        Err(format!(
            "{text} is not in (-180, 180): the camera turns the shorter way between its two poses"
        ))
    }
}

type BoxError = Box<dyn std::error::Error>;

/// The scene named on the command line, before overrides, and the models
/// of a scene that brings them in memory (RIB) rather than by path.
fn base_scene(path: Option<&Path>) -> Result<(Scene, Option<Vec<Model>>), BoxError> {
    let Some(path) = path else {
        return Ok((Scene::default_teapot(), None));
    };
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("toml") => Ok((Scene::load(path)?, None)),
        Some("rib") => {
            let rib = reyes::rib::RibScene::load(path)?;
            for warning in &rib.warnings {
                eprintln!("warning: {warning}");
            }
            if let Some(display) = &rib.display {
                eprintln!(
                    "note: the RIB's Display file is {display}: the image goes there unless -o is given"
                );
            }
            // The models stay in memory: nothing is written for a render.
            Ok((rib.scene, Some(rib.models)))
        }
        Some("bpt" | "bez") => {
            let model = Model::load(path).map_err(|e| -> BoxError {
                // Parse errors give only the line; name the file as the
                // read errors already do.
                match e.line() {
                    Some(_) => format!("{}: {e}", path.display()).into(),
                    None => e.into(),
                }
            })?;
            Ok((Scene::for_model(path.to_string_lossy(), &model), None))
        }
        _ => Err(format!(
            "{}: unknown scene type; expected a .toml or .rib scene or a .bpt/.bez model",
            path.display()
        )
        .into()),
    }
}

/// The displacement the command line asks for, if any. A `.wgsl` source is
/// read here; the values are checked with the scene.
fn displacement(args: &RenderArgs) -> Result<Option<DisplacementDesc>, BoxError> {
    let (Some(source), Some(scale)) = (&args.displace, args.displace_scale) else {
        return Ok(None);
    };
    let is_wgsl = Path::new(source)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("wgsl"));
    let (source, wgsl) = if is_wgsl {
        let text =
            reyes::input::read_text(Path::new(source), InputKind::Wgsl, InputKind::Wgsl.limit())?;
        (SOURCE_WGSL.to_owned(), Some(text))
    } else if source == SOURCE_WGSL {
        return Err(format!(
            "--displace {SOURCE_WGSL} needs the function: pass the path of a .wgsl file"
        )
        .into());
    } else {
        // A relative PNG path means the current directory, not the scene's:
        // make it absolute so the scene's base directory does not apply.
        let path = Path::new(source);
        let source = if source == SOURCE_BUMPS || source == SOURCE_SINES || path.is_absolute() {
            source.clone()
        } else {
            std::env::current_dir()?
                .join(path)
                .to_string_lossy()
                .into_owned()
        };
        (source, None)
    };
    Ok(Some(DisplacementDesc {
        source,
        scale,
        bound: args.displace_bound,
        tiling: args.displace_tiling.unwrap_or(1.0),
        wgsl,
    }))
}

/// Loads the scene, applies the command-line overrides and prepares it.
fn prepare(args: &RenderArgs) -> Result<PreparedScene, BoxError> {
    let (mut scene, in_memory) = base_scene(args.scene.as_deref())?;
    let prepared = |scene: &Scene| match &in_memory {
        Some(models) => PreparedScene::new(scene, models),
        None => PreparedScene::load(scene),
    };
    if let Some(desc) = displacement(args)? {
        for object in &mut scene.objects {
            object.displacement = Some(desc.clone());
        }
    }
    let resized = args.width.is_some() || args.height.is_some();
    if let Some(width) = args.width {
        scene.resolution.width = width;
    }
    if let Some(height) = args.height {
        scene.resolution.height = height;
    }
    if let Some(spp) = args.spp {
        scene.spp = spp;
    }
    if let Some(sampling) = args.sampling {
        scene.sampling = match sampling {
            SamplingArg::Bbox => Sampling::Bbox,
            SamplingArg::Simple => Sampling::Simple,
            SamplingArg::Interleave => Sampling::Interleave,
            SamplingArg::Interval => Sampling::Interval,
            SamplingArg::Adaptive => Sampling::Adaptive,
            SamplingArg::Nearest => Sampling::Nearest,
        };
    }
    if let Some(dicing) = args.dicing {
        scene.dicing = match dicing {
            DicingArg::Rate => Dicing::Rate,
            DicingArg::Fixed => Dicing::Fixed,
        };
    }
    if let Some(rate) = args.shading_rate {
        scene.shading_rate = rate;
    }
    if let Some(interpolation) = args.shading_interpolation {
        scene.shading_interpolation = match interpolation {
            InterpolationArg::Smooth => ShadingInterpolation::Smooth,
            InterpolationArg::Constant => ShadingInterpolation::Constant,
        };
    }
    if args.flat_shading {
        scene.shading_interpolation = ShadingInterpolation::Constant;
    }
    if let Some(tile) = args.interleave_tile {
        scene.interleave_tile = tile;
    }
    if let Some(aov) = args.aov {
        scene.aov = match aov {
            AovArg::Shaded => Aov::Shaded,
            AovArg::Grids => Aov::Grids,
            AovArg::Depth => Aov::Depth,
            AovArg::Normal => Aov::Normal,
        };
    }
    for object in &mut scene.objects {
        if let Some(sides) = args.sides {
            object.sides = sides;
        }
        object.reverse_orientation |= args.reverse_orientation;
    }
    if args.spin.is_some() || args.move_by.is_some() {
        for object in &mut scene.objects {
            let mut close = object.transform_close.unwrap_or(object.transform);
            close.rotate_degrees.z += args.spin.unwrap_or(0.0);
            close.translate += args.move_by.unwrap_or(Vec3::ZERO);
            object.transform_close = Some(close);
        }
    }
    if let Some(shutter) = args.shutter {
        scene.shutter = shutter;
    }
    if let Some(aperture) = args.aperture {
        scene.lens.aperture = aperture;
    }
    if let Some(focus) = args.focus {
        scene.lens.focus_distance = Some(focus);
    }
    let camera_override =
        args.eye.is_some() || args.target.is_some() || args.up.is_some() || args.fov.is_some();
    // A bare model or the teapot was framed for 800x600: frame it again for
    // the requested aspect ratio (through the same helper), unless the user
    // places the camera. Scene files (TOML, RIB) keep their own camera.
    let is_model = args
        .scene
        .as_deref()
        .and_then(|p| p.extension())
        .is_none_or(|e| !(e.eq_ignore_ascii_case("toml") || e.eq_ignore_ascii_case("rib")));
    let moved = args.spin.is_some() || args.move_by.is_some();
    if is_model && (resized || moved) && scene.camera.is_some() {
        let models = scene.load_models()?;
        if resized {
            let (lo, hi) = models[0].bounds();
            let aspect = scene.resolution.width as f32 / scene.resolution.height.max(1) as f32;
            scene.camera = Some(CameraDesc::framing(lo, hi, aspect));
        }
        // The framing sees the model at open: its far plane must also
        // cover where `--move` and `--spin` take it.
        if let Some(mut camera) = scene.camera.filter(|_| moved && !camera_override) {
            camera.far = far_plane_covering_motion(&camera, &scene, &models);
            scene.camera = Some(camera);
        }
    }
    let camera_moves = args.camera_move.is_some() || args.camera_pan.is_some();
    if camera_override || camera_moves {
        // Start from the camera the scene would use (framed if absent).
        let camera = match scene.camera {
            Some(desc) => desc,
            None => {
                let framed = prepared(&scene)?.camera;
                CameraDesc {
                    eye: framed.eye,
                    target: framed.target,
                    up: framed.up,
                    fov_y_degrees: framed.fov_y_radians.to_degrees(),
                    near: framed.near,
                    far: framed.far,
                    projection: framed.projection,
                    ortho_height: (!framed.projection.is_perspective())
                        .then_some(framed.ortho_height),
                }
            }
        };
        let camera = CameraDesc {
            eye: args.eye.unwrap_or(camera.eye),
            target: args.target.unwrap_or(camera.target),
            up: args.up.unwrap_or(camera.up),
            fov_y_degrees: args.fov.unwrap_or(camera.fov_y_degrees),
            ..camera
        };
        scene.camera = Some(camera);
        if camera_moves {
            let by = args.camera_move.unwrap_or(Vec3::ZERO);
            scene.camera_close = Some(camera.moved(by, args.camera_pan.unwrap_or(0.0)));
        }
    }
    Ok(prepared(&scene)?)
}

fn print_stats(stats: &RenderStats, backend: &str, scene: &PreparedScene) {
    let dicing = match scene.dicing {
        Dicing::Rate => format!(
            "rate, shading rate {}",
            scene.micropolygon_side * scene.micropolygon_side
        ),
        Dicing::Fixed => format!("fixed, threshold {} px", scene.dice_threshold),
    };
    let dicing = format!("{dicing}, {} shading", scene.shading_interpolation.name());
    let rows: [(&str, String); 19] = [
        ("input patches", stats.input_patches.to_string()),
        ("splits", stats.splits.to_string()),
        ("culled patches", stats.culled_patches.to_string()),
        ("depth-guard drops", stats.depth_guard_drops.to_string()),
        ("grids diced", stats.grids_diced.to_string()),
        ("micropolygons", stats.micropolygons.to_string()),
        (
            "grids small/med/large",
            format!(
                "{}/{}/{}",
                stats.grids_by_class[0], stats.grids_by_class[1], stats.grids_by_class[2]
            ),
        ),
        (
            "dice thread util.",
            format!("{:.3}", stats.thread_utilization()),
        ),
        (
            "micropolys per hit",
            format!("{:.3}", stats.micropolygons_per_hit()),
        ),
        ("samples tested", stats.samples_tested.to_string()),
        ("samples hit", stats.samples_hit.to_string()),
        ("samples skipped", stats.samples_skipped.to_string()),
        ("dicing", dicing),
        (
            "sample test effic.",
            format!("{:.4}", stats.sample_test_efficiency()),
        ),
        ("interleave grids", stats.interleave_grids.to_string()),
        (
            "largest micropolygon",
            format!("{:.3} px", stats.largest_micropolygon_px),
        ),
        (
            "beyond displ. bound",
            stats.displacement_bound_exceeded.to_string(),
        ),
        (
            "non-finite dsp/tf/cam",
            format!(
                "{}/{}/{}",
                stats.non_finite_displacement, stats.non_finite_transform, stats.non_finite_camera
            ),
        ),
        (
            "frame time",
            stats
                .frame_time_ms
                .map(|t| format!("{t:.3} ms ({backend})"))
                .unwrap_or_else(|| "-".into()),
        ),
    ];
    println!("{:<22}{:>24}", "statistic", "value");
    for (name, value) in rows {
        println!("{name:<22}{value:>24}");
    }
}

fn render(args: &RenderArgs) -> Result<(), BoxError> {
    if let Some(bytes) = args.max_input_bytes {
        reyes::input::set_limits(Limits::all(bytes));
    }
    let output = output_path(args)?;
    let outputs = check_outputs(args, &output)?;
    let scene = prepare(args)?;
    let (image, stats, backend) = if args.cpu {
        // The reference's frame, work and time bounds; --timeout as on the GPU.
        let mut options = reyes::reference::ReferenceOptions::default();
        if let Some(seconds) = args.timeout {
            options.timeout = Some(std::time::Duration::from_secs(seconds.max(1)));
        }
        let rendered = reyes::reference::try_render_with(&scene, &options)?;
        (rendered.image, rendered.stats, "CPU wall".to_owned())
    } else {
        let gpu = reyes::gpu::create_gpu()?;
        let mut options = GpuOptions::default();
        if let Some(seconds) = args.timeout {
            options.timeout = std::time::Duration::from_secs(seconds.max(1));
        }
        options.chunks_per_batch = args.chunks;
        let mut renderer = GpuRenderer::new(&gpu, options)?;
        // Retries are reported as they happen, through the log.
        let rendered = renderer.render(&scene)?;
        let backend = if rendered.timings.megakernel_gpu_ms.is_some() {
            "GPU megakernel"
        } else {
            "wall"
        };
        (
            rendered.image,
            rendered.stats,
            format!("{backend}, {}", gpu.describe()),
        )
    };
    // The image and the statistics are renamed into place together, or
    // neither is.
    outputs.write(&image, &stats)?;
    println!(
        "wrote {} ({}x{}, {} spp)",
        output.display(),
        scene.camera.width,
        scene.camera.height,
        scene.spp
    );
    if args.stats {
        print_stats(&stats, &backend, &scene);
    }
    let warnings =
        reyes::output::frame_warnings(&stats, scene.objects.len(), scene.max_split_depth);
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
    Ok(())
}

/// The image's path: `-o`, else a RIB scene's `Display` file (read up to
/// `WorldBegin`; a relative name is relative to the current directory, as in
/// RenderMan), else `reyes.png`.
fn output_path(args: &RenderArgs) -> Result<PathBuf, BoxError> {
    if let Some(output) = &args.output {
        return Ok(output.clone());
    }
    let rib = args
        .scene
        .as_deref()
        .filter(|s| s.extension().is_some_and(|e| e.eq_ignore_ascii_case("rib")));
    if let Some(scene) = rib
        && let Some(display) = reyes::rib::RibScene::display_of(scene)?
    {
        return Ok(PathBuf::from(display));
    }
    Ok(PathBuf::from("reyes.png"))
}

/// Checks the output paths before any work (see
/// [`reyes::output::OutputPlan::check`]): a render must not run for minutes
/// towards an output it cannot write, or overwrite its own inputs.
fn check_outputs(args: &RenderArgs, output: &Path) -> Result<reyes::output::OutputPlan, BoxError> {
    let mut inputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(scene) = &args.scene {
        inputs.push(("scene", scene));
    }
    // A height map or .wgsl function; the built-in sources are no file.
    if let Some(source) = args.displace.as_deref()
        && source != SOURCE_BUMPS
        && source != SOURCE_SINES
        && source != SOURCE_WGSL
    {
        inputs.push(("displacement", Path::new(source)));
    }
    Ok(reyes::output::OutputPlan::check(
        output,
        args.stats_json.as_deref(),
        &inputs,
    )?)
}

fn main() -> ExitCode {
    // The renderer reports retries (warn) and tile progress (info) through
    // `log`; show them unless RUST_LOG says otherwise.
    env_logger::Builder::from_env(
        env_logger::Env::default().default_filter_or("reyes=info,scheduler=warn"),
    )
    .init();
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Render(args) => render(args),
        Command::Convert(args) => convert(args),
        #[cfg(feature = "viewer")]
        Command::View(args) => view(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            // Print causes the message does not already include.
            let mut shown = error.to_string();
            let mut source = error.source();
            while let Some(cause) = source {
                let text = cause.to_string();
                if !shown.contains(&text) {
                    eprintln!("  caused by: {text}");
                    shown.push_str(&text);
                }
                source = cause.source();
            }
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::parse_bytes;

    #[cfg(feature = "viewer")]
    #[test]
    fn the_printed_render_command_drops_what_the_viewer_sets() {
        let argv = "reyes view scene.toml --eye 1,2,3 --spp=16 --chunks 2 --frames 3 --screenshot a.png --hide-overlay -o x.png --spin 10";
        let prefix = super::render_prefix(argv.split(' ').map(str::to_owned).collect());
        assert_eq!(
            prefix,
            [
                "reyes",
                "render",
                "scene.toml",
                "--chunks",
                "2",
                "--spin",
                "10"
            ]
        );
    }

    #[test]
    fn byte_counts_parse_with_binary_suffixes() {
        assert_eq!(parse_bytes("1048576"), Ok(1 << 20));
        assert_eq!(parse_bytes("512K"), Ok(512 << 10));
        assert_eq!(parse_bytes("16m"), Ok(16 << 20));
        assert_eq!(parse_bytes("2GiB"), Ok(2 << 30));
        assert_eq!(parse_bytes("1TB"), Ok(1 << 40));
        assert!(parse_bytes("lots").is_err());
        assert!(parse_bytes("-1").is_err());
        assert!(parse_bytes("99999999999T").is_err());
    }
}
