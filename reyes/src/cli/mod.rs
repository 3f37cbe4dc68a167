//! The `reyes` command line (feature `cli`): render a scene or a Bezier
//! patch model on the GPU, convert a RIB scene, or view one.
//!
//! ```text
//! reyes render [SCENE] -o out.png [--width W] [--height H] [--spp N]
//!              [--sampling bbox|simple|interleave|interval|adaptive|nearest] [--interleave-tile 2|3|4]
//!              [--interleave-permutations P]
//!              [--stats] [--stats-json FILE] [--quiet]
//!              [--spin DEG] [--move x,y,z] [--camera-move x,y,z] [--camera-pan DEG]
//!              [--shutter F] [--aperture R] [--focus D]
//!              [--eye x,y,z] [--target x,y,z] [--up x,y,z] [--fov DEG] [--cpu]
//!              [--displace bumps|sines|FILE.png|FILE.wgsl --displace-scale S
//!               [--displace-bound B] [--displace-tiling T]] [--timeout SECONDS]
//!              [--chunks N] [--dicing rate|fixed] [--shading-rate R] [--shading-interpolation smooth|constant] [--flat-shading]
//!              [--aov shaded|grids|depth|normal|z] [--depth-filter min|midpoint|max|average]
//!              [--sides 1|2] [--reverse-orientation]
//!              [--max-input-bytes BYTES] [--max-patches N] [--no-pipeline-cache] [--lenient]
//!              [--frame N|N..M|LIST] [--keep-going]
//!              [--frames N|A-B|A-BxS|LIST] [--skip-existing]
//! reyes farm frames SCENE --frames LIST -o PATTERN [--chunk N] [--format text|json]
//! reyes farm slurm SCENE --frames LIST -o PATTERN [--chunk N] [--gpus-per-task N]
//!                  [--partition P] [--time LIMIT] [--logs DIR] [--script FILE] [--submit]
//! reyes farm status SCENE --frames LIST -o PATTERN [--chunk N]
//! reyes cache info|clear
//! reyes view [SCENE] [the options of render] [--frames N --screenshot IMAGE] [--hide-overlay]
//! ```
//!
//! The binary parses [`Cli`], hands it to [`run`] and reports the error
//! [`run`] returns with [`print_error`].

mod args;
mod cache;
mod convert;
mod failures;
mod farm;
mod frames;
mod input;
mod jobs;
mod parse;
mod prepare;
mod progress;
mod render;
mod requests;
mod rib_plan;
mod sequence;
mod stats;
#[cfg(feature = "viewer")]
mod view;

use clap::{Parser, Subcommand};

/// Any error of a command, with its causes.
pub type BoxError = Box<dyn std::error::Error>;

/// The parsed command line.
#[derive(Debug, Parser)]
#[command(
    name = "reyes",
    version,
    about = "A Reyes renderer for bicubic Bezier patches on the GPU"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
// Without `viewer`, the view command's arguments are small and the render
// command's are large by comparison.
#[cfg_attr(
    not(feature = "viewer"),
    expect(
        clippy::large_enum_variant,
        reason = "one command is parsed once per process"
    )
)]
enum Command {
    /// Render a scene (.toml or RenderMan .rib), a model (.bpt/.bez/.obj) or,
    /// without SCENE, the teapot. A RIB file's frames (`FrameBegin n` …
    /// `FrameEnd`) are rendered in order, each to its own image (`--frame`,
    /// `-o out.####.png`).
    Render(render::RenderCommand),
    /// Convert a RenderMan RIB scene to a TOML scene plus `.bpt` models
    /// (written beside the TOML as `<stem>-<i>.bpt`); of a RIB file of
    /// several frames, the one `--frame N` names.
    Convert(convert::ConvertArgs),
    /// Hand a sequence's frames to a render farm or a cluster: print its
    /// chunks with their commands (`frames`), write a Slurm job array
    /// (`slurm`), or list the missing frames (`status`).
    Farm(farm::FarmArgs),
    /// Show (`info`) or empty (`clear`) the directory of compiled pipelines
    /// (`$REYES_CACHE_DIR`, else the platform's cache directory). Only its
    /// pipeline files are touched, never the driver's shader cache.
    Cache(cache::CacheArgs),
    /// Open a window on a scene (the inputs and options of `render`), orbit
    /// it with the mouse and re-render as the view changes. `-o` names the
    /// image that `P` saves (default `reyes-view.png`; `.png` or `.exr`).
    #[cfg(feature = "viewer")]
    View(view::ViewArgs),
}

/// Runs the command `cli` names.
pub fn run(cli: &Cli) -> Result<(), BoxError> {
    // Before any thread starts: a file-size limit fails a write with an
    // error naming the file instead of killing the process mid-write.
    crate::output::ignore_file_size_signal();
    match &cli.command {
        Command::Render(args) => render::render(args),
        Command::Convert(args) => convert::convert(args),
        Command::Farm(args) => farm::farm(args),
        Command::Cache(args) => cache::cache(args),
        #[cfg(feature = "viewer")]
        Command::View(args) => view::view(args),
    }
}

/// Prints `error` to stderr, followed by the causes its message does not
/// already include. A failed write is ignored: standard error is where it
/// would be reported, and the exit status says the run failed anyway.
pub fn print_error(error: &dyn std::error::Error) {
    let mut lines = vec![format!("error: {error}")];
    let mut shown = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        let text = cause.to_string();
        if !shown.contains(&text) {
            lines.push(format!("  caused by: {text}"));
            shown.push_str(&text);
        }
        source = cause.source();
    }
    for line in lines {
        if crate::output::console::errln!("{line}").is_err() {
            return;
        }
    }
}
