//! `reyes view`: the interactive viewer on the scene `reyes render` would
//! draw.

use std::path::PathBuf;

use super::BoxError;
use super::args::RenderArgs;
use super::prepare::{Prepared, prepare};
use crate::gpu::GpuOptions;
use crate::input::Limits;
use crate::output::{OutputGuard, OutputKind};

/// The arguments of `reyes view`: those of `reyes render` and the viewer's own.
#[derive(Debug, clap::Args)]
pub(crate) struct ViewArgs {
    #[command(flatten)]
    pub(crate) render: RenderArgs,
    /// Close after N frames have been presented and the view is refined
    /// (for headless use under `xvfb-run`); when the view is refined with
    /// fewer (no further frame comes without input), close there with a
    /// note.
    #[arg(long, value_name = "N")]
    pub(crate) frames: Option<u64>,
    /// With --frames: save the last presented image here (`.png`, or
    /// `.exr` for float linear RGBA, as `render -o`).
    #[arg(long, value_name = "IMAGE", requires = "frames")]
    pub(crate) screenshot: Option<PathBuf>,
    /// Start with the overlay hidden (`H` shows it).
    #[arg(long)]
    pub(crate) hide_overlay: bool,
    /// Scripted input steps (see `reyes::view::script`), for tests.
    #[arg(long, value_name = "STEPS", hide = true)]
    pub(crate) script: Option<String>,
    /// Write what was rendered (cameras, frame times) as JSON, for tests.
    #[arg(long, value_name = "FILE", hide = true)]
    pub(crate) log_json: Option<PathBuf>,
}

/// `reyes view`: the viewer on the scene `render` would draw.
pub(crate) fn view(args: &ViewArgs) -> Result<(), BoxError> {
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
    if render.keep_going {
        return Err(
            "reyes view shows one frame: --keep-going (for reyes render's frames) does not apply"
                .into(),
        );
    }
    super::args::set_patch_budget(render.max_patches);
    if let Some(bytes) = render.max_input_bytes {
        crate::input::set_limits(Limits::all(bytes));
    }
    let script = match &args.script {
        Some(text) => crate::view::script::parse(text)?,
        None => Vec::new(),
    };
    // Every output is checked before the window opens, against every file
    // the scene read: the save path (`-o`), the screenshot and the log.
    let save_path = render
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("reyes-view.png"));
    let mut guard = OutputGuard::new();
    if let Some(scene) = &render.scene {
        guard.add_input("scene", scene)?;
    }
    guard.add_output(OutputKind::Image, "-o image", &save_path)?;
    if let Some(path) = &args.screenshot {
        guard.add_output(OutputKind::Image, "screenshot", path)?;
    }
    if let Some(path) = &args.log_json {
        guard.add_output(OutputKind::Json, "log", path)?;
    }
    let Prepared { scene, read, .. } = prepare(render)?;
    guard.add_inputs(read)?;
    let mut gpu_options = GpuOptions::default();
    if let Some(seconds) = render.timeout {
        gpu_options.timeout = std::time::Duration::from_secs(seconds);
    }
    gpu_options.chunks_per_batch = render.chunks;
    gpu_options.pipeline_cache_dir = render.pipeline_cache_dir();
    let command = crate::view::save::CommandBase {
        // `args_os`: `args` panics on an argument that is not UTF-8 (a
        // file name); the printed command shows it as `to_string_lossy`.
        prefix: render_prefix(
            std::env::args_os()
                .map(|a| a.to_string_lossy().into_owned())
                .collect(),
        ),
        shutter: render.shutter,
        dice_threshold: scene.dicing.fixed_threshold(),
    };
    let config = crate::view::ViewConfig {
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        script,
        overlay: !args.hide_overlay,
        save_path,
        command,
        gpu_options,
        ..Default::default()
    };
    let log = crate::view::run(scene, config)?;
    if let Some(path) = &args.log_json {
        crate::output::write_json(path, &serde_json::to_string_pretty(&log)?)?;
    }
    Ok(())
}

/// `reyes render` and the `reyes view` arguments it shares, without those
/// the viewer sets itself (the camera, the resolution, the settings it can
/// change, the output) or that only the viewer has.
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

#[cfg(test)]
mod tests {
    use super::render_prefix;

    #[test]
    fn the_printed_render_command_drops_what_the_viewer_sets() {
        let argv = "reyes view scene.toml --eye 1,2,3 --spp=16 --chunks 2 --frames 3 --screenshot a.png --hide-overlay -o x.png --spin 10";
        let prefix = render_prefix(argv.split(' ').map(str::to_owned).collect());
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
}
