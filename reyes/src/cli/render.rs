//! `reyes render`: one frame on the GPU or with the CPU reference, written
//! as an image with optional statistics.

use std::path::{Path, PathBuf};

use super::BoxError;
use super::args::RenderArgs;
use super::prepare::{Prepared, prepare};
use super::progress::{Ticker, print_software_notice};
use super::stats::print_stats;
use crate::displacement::desc::{SOURCE_BUMPS, SOURCE_SINES, SOURCE_WGSL};
use crate::gpu::{GpuOptions, GpuRenderer};
use crate::input::Limits;
use crate::output::console::{errln, outln};
use crate::output::{OutputGuard, OutputKind};
use crate::prepare::PreparedScene;
use crate::progress::AdapterSummary;
use crate::stats::RenderStats;

/// `reyes render`: prepares the scene, renders it on the GPU or with the CPU
/// reference, and writes the image (and the statistics).
pub(crate) fn render(args: &RenderArgs) -> Result<(), BoxError> {
    args.check_backend()?;
    super::args::set_patch_budget(args.max_patches);
    if let Some(bytes) = args.max_input_bytes {
        crate::input::set_limits(Limits::all(bytes));
    }
    let output = output_path(args)?;
    let (mut guard, outputs) = check_outputs(args, &output)?;
    let Prepared { scene, read } = prepare(args)?;
    // Every file the scene read (archives, models, height maps) is no
    // output either; then the directories are made, before any rendering.
    guard.add_inputs(read)?;
    guard.prepare_dirs()?;
    let Frame {
        image,
        linear,
        stats,
        backend,
    } = if args.cpu {
        render_cpu(args, &scene)?
    } else {
        render_gpu(args, &scene)?
    };
    // The image and the statistics are renamed into place together, or
    // neither is.
    outputs.write(&image, &linear, &stats)?;
    outln!(
        "wrote {} ({}x{}, {} spp)",
        output.display(),
        scene.camera.width,
        scene.camera.height,
        scene.spp
    )?;
    if args.stats {
        print_stats(&stats, &backend, &scene)?;
    }
    let warnings =
        crate::output::frame_warnings(&stats, scene.objects.len(), scene.max_split_depth);
    for warning in warnings {
        errln!("warning: {warning}")?;
    }
    Ok(())
}

/// A rendered frame and the renderer that timed it.
struct Frame {
    image: image::RgbaImage,
    /// The resolve's linear floats (what an EXR holds).
    linear: image::Rgba32FImage,
    stats: RenderStats,
    /// What the frame time measures, for the statistics table.
    backend: String,
}

/// The frame of the CPU reference, within its frame, work and time bounds
/// (`--timeout` as on the GPU).
fn render_cpu(args: &RenderArgs, scene: &PreparedScene) -> Result<Frame, BoxError> {
    let mut options = crate::reference::ReferenceOptions::default();
    if let Some(seconds) = args.timeout {
        options.timeout = Some(std::time::Duration::from_secs(seconds));
    }
    let rendered = crate::reference::try_render_with(scene, &options)?;
    Ok(Frame {
        image: rendered.image,
        linear: rendered.linear,
        stats: rendered.stats,
        backend: "CPU wall".to_owned(),
    })
}

/// The frame of the GPU renderer; retries are reported as they happen,
/// through the log. Unless `--quiet`, a software adapter is named once, and
/// on a terminal a progress line follows the compile and the frame.
fn render_gpu(args: &RenderArgs, scene: &PreparedScene) -> Result<Frame, BoxError> {
    let gpu = crate::gpu::create_gpu()?;
    if !args.quiet {
        print_software_notice(&AdapterSummary::of(&gpu.adapter.get_info()))?;
    }
    // Declared before the renderer, dropped after it: the line is blanked
    // before anything else is printed, error or not.
    let ticker = Ticker::on_terminal(args.quiet);
    let mut options = GpuOptions::default();
    if let Some(ticker) = &ticker {
        options.progress = ticker.progress();
    }
    if let Some(seconds) = args.timeout {
        options.timeout = std::time::Duration::from_secs(seconds);
    }
    options.chunks_per_batch = args.chunks;
    options.pipeline_cache_dir = args.pipeline_cache_dir();
    options.trace = args
        .trace
        .as_ref()
        .map(|_| scheduler::TraceOptions::default());
    let mut renderer = GpuRenderer::new(&gpu, options)?;
    let rendered = renderer.render(scene)?;
    if let Some(path) = &args.trace {
        let trace = rendered.report.as_ref().and_then(|r| r.trace());
        let trace = trace.ok_or("the frame ran no traced megakernel")?;
        crate::output::write_json(path, &trace.to_chrome_json())?;
        log::info!(
            "trace: {} batches, {} recorded, written to {}",
            trace.batches,
            trace.records.len(),
            path.display()
        );
    }
    if let Some(pipeline) = renderer.last_pipeline() {
        let (lines, functions) = renderer.compiled().module_size();
        let first_dispatch = pipeline.timings.first_dispatch.unwrap_or_default();
        log::info!(
            "GPU program `{}` ({lines} lines, {functions} functions): pipeline creation {:.3} s, first dispatch {:.3} s, driver compile {:.3} s, pipeline cache {:?}",
            renderer.variant(),
            pipeline.timings.pipeline_creation.as_secs_f64(),
            first_dispatch.as_secs_f64(),
            (pipeline.timings.pipeline_creation + first_dispatch).as_secs_f64(),
            pipeline.cache
        );
    }
    let timer = if rendered.timings.megakernel_gpu_ms.is_some() {
        "GPU megakernel"
    } else {
        "wall"
    };
    Ok(Frame {
        image: rendered.image,
        linear: rendered.linear,
        stats: rendered.stats,
        backend: format!("{timer}, {}", gpu.describe()),
    })
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
        && let Some(display) = crate::rib::RibScene::display_of(scene)?
    {
        return Ok(PathBuf::from(display));
    }
    Ok(PathBuf::from("reyes.png"))
}

/// Checks the output paths before any work, in the run's guard (see
/// [`crate::output::OutputGuard::add_output`]): a render must not run for
/// minutes towards an output it cannot write, or overwrite its own inputs.
/// The files named on the command line are recorded as inputs here; those
/// the scene reads are added once it is loaded.
fn check_outputs(
    args: &RenderArgs,
    output: &Path,
) -> Result<(OutputGuard, crate::output::OutputPlan), BoxError> {
    let mut guard = OutputGuard::new();
    if let Some(scene) = &args.scene {
        guard.add_input("scene", scene)?;
    }
    // A height map or .wgsl function; the built-in sources are no file.
    if let Some(source) = args.displace.as_deref()
        && source != SOURCE_BUMPS
        && source != SOURCE_SINES
        && source != SOURCE_WGSL
    {
        guard.add_input("displacement", source)?;
    }
    let plan = crate::output::OutputPlan::new(&mut guard, output, args.stats_json.as_deref())?;
    if let Some(trace) = &args.trace {
        guard.add_output(OutputKind::Json, "trace", trace)?;
    }
    Ok((guard, plan))
}
