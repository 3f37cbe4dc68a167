//! How the renderer runs the megakernel ([`GpuOptions`]) and what a frame
//! gives back ([`GpuRendered`], [`FrameTimings`]).

use std::path::PathBuf;
use std::time::Duration;

use image::{Rgba32FImage, RgbaImage};
use scheduler::{Policy, RunReport, Strategy};

use crate::progress::Progress;
use crate::stats::RenderStats;

/// Default capacity (items) of the split and dice queues. With the
/// depth-first priorities the queues hold roughly one wave of pieces per
/// running workgroup; 2^16 items (14 MiB per queue) leaves ample room for
/// the teapot and the Killeroo, and an overflow is retried with the queues
/// grown to the need the run measured, never ignored.
pub const DEFAULT_WORK_CAPACITY: u32 = 1 << 16;

/// How the renderer runs the megakernel.
#[derive(Clone, Debug)]
pub struct GpuOptions {
    /// Persistent workgroups (`None`: what the driver's quirks ask for,
    /// [`scheduler::Quirks::megakernel_workgroups`], one per CPU thread on
    /// llvmpipe; else the scheduler's default).
    pub workgroups: Option<u32>,
    /// Iteration budget per dispatch of a first attempt (`None`: the
    /// driver's budget for long-looping bodies,
    /// [`scheduler::Quirks::long_body_iteration_budget`], 16 on llvmpipe;
    /// else the scheduler's default). A loop limit halves it for the retry.
    pub iteration_budget: Option<u32>,
    /// Chunks per batch the megakernel is compiled with (`None`:
    /// [`scheduler::Quirks::chunks_per_batch`], 4 on llvmpipe, for frames
    /// without motion blur or depth of field, else 1). The image is the
    /// same for any value.
    pub chunks_per_batch: Option<u32>,
    /// Capacity of the split and dice queues in items, to start with: an
    /// overflow grows them (and the grown queues stay for later frames).
    pub work_capacity: u32,
    /// Host-side limit of one run.
    pub timeout: Duration,
    /// How the scheduler runs the graph: the persistent megakernel (default)
    /// or kernel-by-kernel rounds. The image is the same either way.
    pub strategy: Strategy,
    /// Queue policy the graph is compiled for (default: priority, which
    /// works the patches depth-first).
    pub policy: Policy,
    /// Most samples the framebuffer of one screen tile may hold (`None`: as
    /// many as the device's buffers and the shaders' u32 sample index
    /// allow). A frame with more samples is rendered in tiles (see
    /// `plan_tiles`); a small cap forces
    /// tiling on small frames.
    pub max_tile_samples: Option<u64>,
    /// Most input patches seeded into one run of the megakernel (`None`: as
    /// many as the Bound queue holds next to the work queues in one device
    /// buffer). A scene with more patches is rendered in batches, each run
    /// into the same framebuffer and statistics, which compose (see
    /// [`GpuRenderer::render`](super::renderer::GpuRenderer::render)); a
    /// small value forces batches on small scenes.
    pub max_batch_patches: Option<u32>,
    /// Who hears what the renderer is doing ([`crate::progress`]): the
    /// frames, the driver's compile of the megakernel, tiles and batches.
    /// Default: nobody, at no cost.
    pub progress: Progress,
    /// A directory for the compiled megakernel pipelines, kept across runs
    /// of the program (`None`, the default: nothing is written). See
    /// [`scheduler::ExecutorConfig::pipeline_cache_dir`]; the command line
    /// uses [`default_pipeline_cache_dir`](crate::gpu::default_pipeline_cache_dir).
    pub pipeline_cache_dir: Option<PathBuf>,
    /// Trace the megakernel's runs ([`scheduler::CompileOptions::trace`]):
    /// [`GpuRendered::report`] then holds the trace of the frame's last run
    /// (`None`, the default: untraced, nothing recorded).
    pub trace: Option<scheduler::TraceOptions>,
    /// Keep each sample's nearest surface with 32-bit atomics over two runs
    /// of the megakernel ([`DepthTest::TwoPass32`](crate::gpu::DepthTest::TwoPass32))
    /// even where the device has 64-bit ones (`false`, the default: only
    /// devices without them do). The two tests give the same framebuffer;
    /// this compares them.
    pub two_pass_depth_test: bool,
}

pub use crate::params::DEFAULT_RENDER_TIMEOUT;

impl Default for GpuOptions {
    fn default() -> Self {
        Self {
            workgroups: None,
            iteration_budget: None,
            chunks_per_batch: None,
            work_capacity: DEFAULT_WORK_CAPACITY,
            timeout: DEFAULT_RENDER_TIMEOUT,
            strategy: Strategy::Megakernel,
            policy: Policy::Priority,
            max_tile_samples: None,
            max_batch_patches: None,
            progress: Progress::none(),
            pipeline_cache_dir: None,
            trace: None,
            two_pass_depth_test: false,
        }
    }
}

/// Where the time of a frame went.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct FrameTimings {
    /// GPU time of the megakernel (timestamp queries), when the device has them.
    pub megakernel_gpu_ms: Option<f64>,
    /// Host wall time of the megakernel run (seeding to counter read-back).
    pub megakernel_wall_ms: f64,
    /// Host wall time of the whole frame: clear, megakernel, resolve, read-back.
    pub total_wall_ms: f64,
}

/// A frame rendered on the GPU.
#[derive(Debug, Clone)]
pub struct GpuRendered {
    /// The 8-bit image: [`GpuRendered::linear`] exposed, encoded as sRGB
    /// and quantized on the host
    /// ([`PreparedScene::encoding`](crate::prepare::PreparedScene::encoding),
    /// see [`crate::quantize`]), as the CPU reference does.
    pub image: RgbaImage,
    /// The resolve's filtered linear RGB, alpha 1, read back as floats:
    /// not clamped, not exposed, not quantized (what the EXR output holds).
    pub linear: Rgba32FImage,
    /// Per pixel (row-major): whether any sample was covered.
    pub coverage: Vec<bool>,
    /// Per pixel (row-major): how many of its samples were covered (up to
    /// 256, so not a byte).
    pub covered_samples: Vec<u16>,
    /// The frame's counters. `frame_time_ms` is the megakernel's GPU time
    /// when the device has timestamp queries, else the frame's wall time.
    pub stats: RenderStats,
    /// The scheduler's report of the (last) megakernel run; `None` for a
    /// scene without patches, where nothing runs.
    pub report: Option<RunReport>,
    /// Runs repeated because a queue overflowed, summed over the batches and
    /// tiles (the scheduler's [`scheduler::RetryCauses`]).
    pub overflow_retries: u32,
    /// Runs repeated because llvmpipe cut loops short (the scheduler's
    /// waits or the rasterization loops), summed over the batches and tiles.
    pub loop_retries: u32,
    /// Timings of the frame (summed over the tiles).
    pub timings: FrameTimings,
    /// Screen tiles the frame was rendered in (1 unless its sample
    /// framebuffer exceeds the device's limits or
    /// [`GpuOptions::max_tile_samples`]).
    pub tiles: u32,
    /// Runs of the megakernel, one per batch of input patches, of the
    /// successful attempt, summed over the tiles (1 per tile unless the
    /// patches exceed the Bound queue or [`GpuOptions::max_batch_patches`];
    /// 0 for a scene without patches).
    pub batches: u32,
}

impl crate::prepare::RenderedPass for GpuRendered {
    fn linear(&self) -> &image::Rgba32FImage {
        &self.linear
    }
    fn stats_mut(&mut self) -> &mut crate::stats::RenderStats {
        &mut self.stats
    }
}
