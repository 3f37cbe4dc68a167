//! `reyes render`: frames on the GPU or with the CPU reference, each
//! written as an image with optional statistics.

use std::cell::OnceCell;
use std::path::Path;

use scheduler::Gpu;

use super::BoxError;
use super::args::RenderArgs;
use super::progress::{Ticker, print_software_notice};
use super::sequence::SequenceArgs;
use super::stats::print_stats;
use crate::gpu::{GpuOptions, GpuRenderer};
use crate::input::Limits;
use crate::output::console::{errln, outln};
use crate::prepare::PreparedScene;
use crate::progress::AdapterSummary;
use crate::shadow::ShadowMap;
use crate::stats::RenderStats;

/// The arguments of `reyes render`: those `reyes view` shares, and those
/// of sequences.
#[derive(Debug, clap::Args)]
pub(crate) struct RenderCommand {
    #[command(flatten)]
    pub(crate) args: RenderArgs,
    #[command(flatten)]
    pub(crate) sequence: SequenceArgs,
}

/// `reyes render`: prepares the scene, renders it on the GPU or with the CPU
/// reference, and writes the image (and the statistics); for a RIB file or
/// a TOML sequence, each selected frame in turn ([`super::jobs`]).
pub(crate) fn render(command: &RenderCommand) -> Result<(), BoxError> {
    let RenderCommand { args, sequence } = command;
    args.check_backend()?;
    super::args::set_patch_budget(args.max_patches);
    if let Some(bytes) = args.max_input_bytes {
        crate::input::set_limits(Limits::all(bytes));
    }
    let selection = args.frame.as_ref().or(sequence.frames.as_ref());
    let plan = super::jobs::plan(args, selection)?;
    super::jobs::run(args, sequence, plan)
}

/// The renderer of a run: the CPU reference, or one GPU renderer that every
/// frame of the run shares (created at the first frame), so that frames of
/// one kernel variant compile its megakernel and create its pipeline once.
pub(crate) struct Backend<'g> {
    gpu: &'g OnceCell<Gpu>,
    /// Declared before the renderer, dropped after it: the line is blanked
    /// before anything else is printed, error or not.
    ticker: Option<Ticker<std::io::Stderr>>,
    renderer: Option<GpuRenderer<'g>>,
}

impl<'g> Backend<'g> {
    /// A backend for `args` (`--cpu` or the GPU), its GPU in `gpu`.
    pub(crate) fn new(args: &RenderArgs, gpu: &'g OnceCell<Gpu>) -> Backend<'g> {
        Backend {
            gpu,
            ticker: (!args.cpu)
                .then(|| Ticker::on_terminal(args.quiet))
                .flatten(),
            renderer: None,
        }
    }

    /// Renders `scene` and writes it to `outputs`, then prints the `wrote`
    /// line, the statistics (headed by `label`, when the file has frames)
    /// and the frame's warnings.
    pub(crate) fn render_and_write(
        &mut self,
        args: &RenderArgs,
        scene: &PreparedScene,
        outputs: &crate::output::OutputPlan,
        paths: (&Path, Option<&Path>),
        label: Option<&str>,
    ) -> Result<RenderStats, BoxError> {
        let (output, trace) = paths;
        let depth = scene.aov == crate::Aov::Z;
        if depth {
            outputs.check_depth()?;
        }
        let Frame {
            image,
            linear,
            stats,
            backend,
        } = if args.cpu {
            render_cpu(args, scene)?
        } else {
            self.render_gpu(args, scene, trace)?
        };
        // The image and the statistics are renamed into place together, or
        // neither is.
        if depth {
            // Relative to the maps' space (a RIB frame's: the file's world,
            // which the file's other frames share).
            let mut map = ShadowMap::from_camera(&scene.camera, crate::depth::depths(&linear));
            if let Some(space) = scene.shadow_map_space {
                map.world_to_camera *= space;
                map.world_to_clip *= space;
            }
            outputs.write_depth_map(&map, &stats)?;
        } else {
            outputs.write(&image, &linear, &stats)?;
        }
        outln!(
            "wrote {} ({}x{}, {} spp)",
            output.display(),
            scene.camera.width,
            scene.camera.height,
            scene.spp
        )?;
        if args.stats {
            if let Some(label) = label {
                outln!("statistics of {label}")?;
            }
            print_stats(&stats, &backend, scene)?;
        }
        // Only an empty frame's advice looks at where the geometry lies.
        let extent = (stats.samples_hit == 0)
            .then(|| depth_extent(scene))
            .flatten();
        let warnings = crate::output::frame_warnings(
            &stats,
            scene.objects.len(),
            scene.max_split_depth,
            extent,
        );
        let prefix = label.map(|l| format!("{l}: ")).unwrap_or_default();
        for warning in warnings {
            errln!("warning: {prefix}{warning}")?;
        }
        Ok(stats)
    }

    /// The GPU renderer, created (with the GPU) at the first frame. Unless
    /// `--quiet`, a software adapter is named once, and on a terminal a
    /// progress line follows the compile and the frames.
    fn renderer(&mut self, args: &RenderArgs) -> Result<&mut GpuRenderer<'g>, BoxError> {
        if self.renderer.is_none() {
            if self.gpu.get().is_none() {
                let _ = self.gpu.set(crate::gpu::create_gpu()?);
            }
            let gpu = self.gpu.get().expect("created above");
            if !args.quiet {
                print_software_notice(&AdapterSummary::of(&gpu.adapter.get_info()))?;
            }
            let mut options = GpuOptions::default();
            if let Some(ticker) = &self.ticker {
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
            self.renderer = Some(GpuRenderer::new(gpu, options)?);
        }
        Ok(self.renderer.as_mut().expect("created above"))
    }

    /// The frame of the GPU renderer; retries are reported as they happen,
    /// through the log, and so is the pipeline: created for this frame
    /// (with the driver's compile times), or reused from an earlier one.
    fn render_gpu(
        &mut self,
        args: &RenderArgs,
        scene: &PreparedScene,
        trace: Option<&Path>,
    ) -> Result<Frame, BoxError> {
        let renderer = self.renderer(args)?;
        let created = renderer.pipelines_created();
        let rendered = renderer.render(scene)?;
        if let Some(path) = trace {
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
        if renderer.pipelines_created() == created {
            log::info!(
                "GPU program `{}`: the pipeline of an earlier frame is reused (no compile)",
                renderer.variant()
            );
        } else if let Some(pipeline) = renderer.last_pipeline() {
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
        let gpu = self.gpu.get().expect("the renderer's GPU");
        Ok(Frame {
            image: rendered.image,
            linear: rendered.linear,
            stats: rendered.stats,
            backend: format!("{timer}, {}", gpu.describe()),
        })
    }
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

/// Where `scene`'s input control points lie along the camera's view
/// direction, against its clipping planes (`None` without patches).
fn depth_extent(scene: &PreparedScene) -> Option<crate::output::DepthExtent> {
    let view = scene.camera.view;
    let (nearest, farthest) = scene
        .patches
        .iter()
        .flat_map(|patch| patch.points)
        .map(|point| -view.transform_point3(point).z)
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), depth| {
            (lo.min(depth), hi.max(depth))
        });
    (nearest <= farthest).then_some(crate::output::DepthExtent {
        nearest,
        farthest,
        near: scene.camera.near,
        far: scene.camera.far,
    })
}
