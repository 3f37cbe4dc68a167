//! [`GpuRenderer`]: runs one frame of the Reyes megakernel and returns the
//! image, the coverage and the [`RenderStats`].

use std::time::{Duration, Instant};

use image::RgbaImage;
use scheduler::readback::read_buffer;
use scheduler::{
    Capacities, CompileError, CompiledGraph, DEFAULT_WORKGROUPS, DeviceError, Executor,
    ExecutorConfig, Gpu, Policy, RunError, RunReport, Seeds, Strategy,
};

use super::buffers::{FrameBuffers, GpuCounters, texel_buffer_bytes};
use super::graph::{self, BOUND, DICE, PatchItem, REQUIRED_FEATURES, SPLIT_U, SPLIT_V};
use super::loop_limit::{LoopLimitContext, LoopLimitError};
use super::resolve::{ResolveTarget, Resolver};
use crate::prepare::PreparedScene;
use crate::stats::RenderStats;

/// Screen tiles start at multiples of this many pixels. The renderer's
/// per-pixel 5D sample table repeats every [`crate::uvt::TABLE_SIDE`] (64)
/// pixels and its interleaved sampling works on
/// [`crate::uvt::INTERLEAVE_TILE`] (2) pixel squares, both indexed by the
/// pixel coordinates of the frame being rendered; a tile whose origin is a
/// multiple of both gives every pixel the samples it has in the untiled
/// frame, so tiling changes the image only through float rounding. The
/// jitter and Interleave UVT's permutation per 2 x 2 square are hashed from
/// absolute pixel coordinates ([`crate::camera::Camera::origin`]).
pub const TILE_ALIGN: u32 = 64;
const _: () = assert!(
    TILE_ALIGN.is_multiple_of(crate::uvt::TABLE_SIDE)
        && TILE_ALIGN.is_multiple_of(crate::uvt::INTERLEAVE_TILE),
    "tile origins must keep the sample tables' period"
);

/// Default capacity (items) of the split and dice queues. With the
/// depth-first priorities the queues hold roughly one wave of pieces per
/// running workgroup; 2^16 items (14 MiB per queue) leaves ample room for
/// the teapot and the Killeroo, and an overflow is retried with double the
/// capacity, never ignored.
pub const DEFAULT_WORK_CAPACITY: u32 = 1 << 16;
/// Iteration budget on CPU adapters (llvmpipe). llvmpipe ends loops once an
/// invocation has run 65535 loop iterations, counted across all loops and
/// all their runs (the scheduler's queue waits included). With the
/// scheduler's CPU default of 64 batches per dispatch the rasterization
/// loops of DiceShadeSample were cut in a 256-workgroup teapot run (detected
/// through `STAT_LOOPS_CUT`); 16 batches per dispatch left room in every
/// uncontended run, at the cost of a few more dispatches.
pub const CPU_ITERATION_BUDGET: u32 = 16;
/// Persistent workgroups on CPU adapters: one per CPU thread, so that all
/// of them run at once. llvmpipe runs only as many workgroups at a time as it
/// has threads; a workgroup polling for work that a descheduled workgroup is
/// producing spends llvmpipe's shared loop budget (see
/// [`CPU_ITERATION_BUDGET`]) until the body's own loops get cut. With 256 or
/// 16 workgroups that happened in 800x600 and 1920x1080 teapot frames even at
/// 4 batches per dispatch.
pub fn cpu_workgroups() -> u32 {
    std::thread::available_parallelism().map_or(2, |n| n.get().min(64) as u32)
}
/// Chunks per batch on CPU adapters ([`scheduler::CompileOptions::chunks_per_batch`])
/// for frames without motion blur or depth of field. llvmpipe runs every part
/// of the megakernel for every group of 8 lanes, whichever procedure the batch
/// belongs to, so larger batches share that cost among more items: the
/// default teapot frame takes about 1.5 s with 4 chunks against 2.4 s with 1
/// (docs/performance.md, "Chunks per batch"). Frames that sample time or
/// lens keep 1: their rasterization loops are long enough that 4 chunks per
/// batch ran into llvmpipe's loop limit (see [`CPU_ITERATION_BUDGET`]), and
/// the bookkeeping is a small share of their time.
pub const CPU_CHUNKS_PER_BATCH: u32 = 4;
/// Iteration budget of the one retry after llvmpipe cut loops short. The
/// loop counter llvmpipe keeps is shared by all loops of an invocation,
/// including the scheduler's queue waits, which grow when other work
/// competes for the CPU; fewer batches per dispatch leave more headroom.
pub const CPU_RETRY_ITERATION_BUDGET: u32 = 1;
/// Retries after llvmpipe cut loops short (each from scratch).
const MAX_LOOP_RETRIES: u32 = 2;
/// The split and dice queues are never shrunk below this to fit a device.
const MIN_WORK_CAPACITY: u32 = 1 << 12;
/// The work queues are shrunk (down to [`MIN_WORK_CAPACITY`]) to fit the
/// device only while batches of input patches would be smaller than this:
/// more runs cost less than overflowing work queues.
const MIN_BATCH_PATCHES: u32 = 1 << 12;
/// Bytes of one input patch in the height-map buffer (48 floats).
const PATCH_BYTES: u64 = 4 * 48;

/// Why a frame could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No device with the features the renderer needs could be created.
    #[error(
        "could not create a GPU device with 64-bit integer atomics (SHADER_INT64 and SHADER_INT64_ATOMIC_MIN_MAX, needed for the depth test): {0}"
    )]
    Device(#[source] DeviceError),
    /// The device lacks features the renderer needs.
    #[error(
        "the GPU device lacks {missing:?}; the Reyes renderer needs 64-bit integers and 64-bit atomicMin for its depth test (create the device with reyes::gpu::create_gpu)"
    )]
    MissingFeatures {
        /// The features that are missing.
        missing: wgpu::Features,
    },
    /// The image is too large for the device's buffers.
    #[error(
        "{width}x{height} at {spp} spp needs a {needed}-byte {what} but the device allows at most {limit} bytes per buffer; lower the resolution or spp"
    )]
    TooLarge {
        /// Which buffer.
        what: &'static str,
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Samples per pixel.
        spp: u32,
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
    /// The scene's height maps do not fit into one device buffer.
    #[error(
        "the scene's height maps, time/lens tables and patches need {needed} bytes but the device allows at most {limit} bytes per buffer; use fewer or smaller height maps, or fewer patches"
    )]
    HeightMapsTooLarge {
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
    /// The megakernel did not compile (a bug in the renderer's WGSL).
    #[error("the Reyes megakernel did not compile: {0}")]
    Compile(#[from] CompileError),
    /// The megakernel did not compile with the scene's user displacement
    /// function (most likely an error in that function).
    #[error(
        "the user displacement function (WGSL defining `fn displacement_user(u: f32, v: f32) -> f32`) does not compile into the megakernel: {0}"
    )]
    UserDisplacement(#[source] CompileError),
    /// The scene's user displacement function fails the checks made on its
    /// own source (syntax, a name of the renderer's, module variables,
    /// barriers), at its own line.
    #[error("the user displacement function is refused: {0}")]
    UserFunction(#[from] crate::displacement::user_wgsl::UserWgslError),
    /// Objects use different user displacement functions; the megakernel
    /// holds one.
    #[error(
        "objects {first} and {other} use different user displacement functions; a scene may use one (it is compiled into the megakernel)"
    )]
    ConflictingUserDisplacement {
        /// The first object with a user function.
        first: usize,
        /// An object whose function differs.
        other: usize,
    },
    /// The scheduler could not run the megakernel (after one retry with
    /// doubled capacities when a queue overflowed).
    #[error("the Reyes megakernel failed: {0}")]
    Run(#[from] RunError),
    /// llvmpipe's loop limit still cut loops short after the retries with
    /// smaller iteration budgets, so samples would be missing. The error
    /// gives the facts (workgroups, iteration budget, attempts) and advice
    /// that follows from the frame's configuration ([`LoopLimitError`]).
    #[error(transparent)]
    LoopLimit(Box<LoopLimitError>),
    /// Not even one input patch fits the Bound queue next to the smallest
    /// work queues in one device buffer.
    #[error(
        "the scheduler's queues need {needed} bytes for one input patch next to the split and dice queues at their smallest ({work_capacity} items each), but the device allows at most {limit} bytes per buffer: 0 of the {patches} patches fit per batch"
    )]
    NoBatchFits {
        /// Input patches of the scene.
        patches: usize,
        /// Capacity of each work queue, in items.
        work_capacity: u32,
        /// Bytes of the queues for one input patch.
        needed: u64,
        /// Bytes allowed per buffer.
        limit: u64,
    },
    /// The input patches (which the megakernel reads from one device buffer
    /// whatever the batches) do not fit the device next to the height maps.
    #[error(
        "the scene's {patches} input patches need {needed} bytes next to the height maps and time/lens tables, but the device allows at most {limit} bytes per buffer: {fit} patches fit; use a model with fewer patches"
    )]
    TooManyPatches {
        /// Input patches of the scene.
        patches: usize,
        /// Patches that would fit.
        fit: u64,
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
}

/// How the renderer runs the megakernel.
#[derive(Clone, Debug)]
pub struct GpuOptions {
    /// Persistent workgroups (`None`: [`cpu_workgroups`] on CPU adapters,
    /// else the scheduler's default).
    pub workgroups: Option<u32>,
    /// Iteration budget per dispatch (`None`: [`CPU_ITERATION_BUDGET`] on
    /// CPU adapters, else the scheduler's default).
    pub iteration_budget: Option<u32>,
    /// Chunks per batch the megakernel is compiled with (`None`:
    /// [`CPU_CHUNKS_PER_BATCH`] on CPU adapters for frames without motion
    /// blur or depth of field, else 1). The image is the same for any value.
    pub chunks_per_batch: Option<u32>,
    /// Capacity of the split and dice queues in items.
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
    /// [`plan_tiles`]); a small cap forces tiling on small frames.
    pub max_tile_samples: Option<u64>,
    /// Most input patches seeded into one run of the megakernel (`None`: as
    /// many as the Bound queue holds next to the work queues in one device
    /// buffer). A scene with more patches is rendered in batches, each run
    /// into the same framebuffer and statistics, which compose (see
    /// [`GpuRenderer::render`]); a small value forces batches on small scenes.
    pub max_batch_patches: Option<u32>,
}

/// Default host-side limit of one megakernel run. It includes the driver's
/// compilation of the pipeline on its first dispatch, which lavapipe does
/// lazily: over a minute for the Reyes megakernel on a cold shader cache.
pub const DEFAULT_RENDER_TIMEOUT: Duration = Duration::from_secs(600);

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
    /// The resolved image, 8-bit sRGB, alpha 255.
    pub image: RgbaImage,
    /// Per pixel (row-major): whether any sample was covered.
    pub coverage: Vec<bool>,
    /// Per pixel (row-major): how many of its samples were covered.
    pub covered_samples: Vec<u8>,
    /// The frame's counters. `frame_time_ms` is the megakernel's GPU time
    /// when the device has timestamp queries, else the frame's wall time.
    pub stats: RenderStats,
    /// The scheduler's report of the (last) megakernel run; `None` for a
    /// scene without patches, where nothing runs.
    pub report: Option<RunReport>,
    /// Runs repeated because a queue overflowed (0 or 1 per tile, summed
    /// over the tiles).
    pub overflow_retries: u32,
    /// Runs repeated because llvmpipe cut loops short (0 to 2 per tile,
    /// summed over the tiles).
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

/// A screen tile: the pixels `[x0, x0 + width) x [y0, y0 + height)` of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Left column.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// Columns.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

/// Splits a `width x height` image into screen tiles of at most
/// `max_pixels` pixels each, row by row from the top left.
///
/// One tile covers the whole image when it fits. Otherwise tile origins are
/// multiples of [`TILE_ALIGN`] and the tiles are full-width bands of rows
/// when a band of [`TILE_ALIGN`] rows fits (one band spans every column, so
/// patches are bound and culled against fewer tiles), else tiles about as
/// wide as they are high; either way the tile size is then evened out so
/// that the last row or column of tiles is not much smaller than the others.
/// Tiles at the right and bottom edges are clipped to the image.
///
/// `None` when even the smallest aligned tile, `min(width, 64) x
/// min(height, 64)` pixels, exceeds `max_pixels`.
pub fn plan_tiles(width: u32, height: u32, max_pixels: u64) -> Option<Vec<Tile>> {
    let (w, h) = (u64::from(width), u64::from(height));
    if w * h <= max_pixels {
        return Some(vec![Tile {
            x0: 0,
            y0: 0,
            width,
            height,
        }]);
    }
    let align = u64::from(TILE_ALIGN);
    if w.min(align) * h.min(align) > max_pixels {
        return None;
    }
    let down = |n: u64| n / align * align;
    // In every branch the side that is smaller than its extent is a
    // positive multiple of `align` (see the checks above), so evening out
    // below keeps the tiles within `max_pixels`.
    let rows = down(max_pixels / w);
    let (tile_w, tile_h) = if rows >= align {
        (w, rows)
    } else if h <= align {
        // Too few rows for aligned bands: columns of the full height.
        (down(max_pixels / h), h)
    } else {
        // The largest aligned square that fits, widened to use the budget.
        let side = down(max_pixels.isqrt()).max(align);
        (down(max_pixels / side), side)
    };
    // The smallest aligned size that needs no more tiles than `tile`.
    let even = |extent: u64, tile: u64| {
        if tile >= extent {
            extent
        } else {
            let count = extent.div_ceil(tile);
            extent.div_ceil(count).div_ceil(align) * align
        }
    };
    let (tile_w, tile_h) = (even(w, tile_w), even(h, tile_h));
    let mut tiles = Vec::new();
    for y0 in (0..h).step_by(tile_h as usize) {
        for x0 in (0..w).step_by(tile_w as usize) {
            // Every value is at most `width` or `height`, so these fit u32.
            tiles.push(Tile {
                x0: x0 as u32,
                y0: y0 as u32,
                width: tile_w.min(w - x0) as u32,
                height: tile_h.min(h - y0) as u32,
            });
        }
    }
    Some(tiles)
}

/// Adds a tile's counters to a frame's: counts are summed, the largest
/// micropolygon is the largest of any tile. `input_patches` (the scene's,
/// not the tile's) and the frame time are set by the caller.
fn add_tile_stats(total: &mut RenderStats, tile: &RenderStats) {
    // Destructured without `..` so that a new counter has to be placed here.
    let RenderStats {
        input_patches: _,
        splits,
        culled_patches,
        depth_guard_drops,
        grids_diced,
        micropolygons,
        samples_tested,
        samples_hit,
        largest_micropolygon_px,
        displacement_bound_exceeded,
        interleave_grids,
        grids_by_class,
        dice_threads,
        frame_time_ms: _,
    } = tile;
    for (sum, n) in total.grids_by_class.iter_mut().zip(grids_by_class) {
        *sum += n;
    }
    total.dice_threads += dice_threads;
    total.splits += splits;
    total.culled_patches += culled_patches;
    total.depth_guard_drops += depth_guard_drops;
    total.grids_diced += grids_diced;
    total.micropolygons += micropolygons;
    total.samples_tested += samples_tested;
    total.samples_hit += samples_hit;
    total.largest_micropolygon_px = total.largest_micropolygon_px.max(*largest_micropolygon_px);
    total.displacement_bound_exceeded += displacement_bound_exceeded;
    total.interleave_grids += interleave_grids;
}

/// Renders prepared scenes with the Reyes megakernel. Pipelines, the
/// executor (for a given queue sizing) and the frame buffers (for a given
/// resolution) are created on first use and reused by later frames.
#[derive(Debug)]
pub struct GpuRenderer<'a> {
    gpu: &'a Gpu,
    options: GpuOptions,
    compiled: CompiledGraph,
    /// The user displacement function compiled into `compiled`, if any.
    compiled_user: Option<String>,
    /// The chunks per batch `compiled` was compiled with.
    compiled_chunks: u32,
    resolver: Resolver,
    executor: Option<(Capacities, Option<u32>, Executor)>,
    frame: Option<(FrameBuffers, ResolveTarget)>,
}

impl<'a> GpuRenderer<'a> {
    /// Compiles the megakernel for `gpu`'s device, which must have
    /// [`REQUIRED_FEATURES`] (see [`super::create_gpu`]).
    pub fn new(gpu: &'a Gpu, options: GpuOptions) -> Result<Self, RenderError> {
        let missing = REQUIRED_FEATURES - gpu.device.features();
        if !missing.is_empty() {
            return Err(RenderError::MissingFeatures { missing });
        }
        let chunks = chunks_per_batch(gpu, &options, false);
        let compiled = graph::compile_for(
            scheduler::recommended_features(&gpu.device),
            None,
            options.policy,
            chunks,
        )?;
        Ok(Self {
            gpu,
            options,
            compiled,
            compiled_user: None,
            compiled_chunks: chunks,
            resolver: Resolver::new(&gpu.device),
            executor: None,
            frame: None,
        })
    }

    /// The compiled megakernel (of the last scene's user displacement
    /// function, if it had one).
    pub fn compiled(&self) -> &CompiledGraph {
        &self.compiled
    }

    /// Compiles the megakernel again when `scene` needs a different user
    /// displacement function, or chunks per batch, than the one compiled in
    /// (the executor, which holds the pipeline, is then rebuilt).
    fn prepare_megakernel(&mut self, scene: &PreparedScene) -> Result<(), RenderError> {
        let mut users = scene.objects.iter().enumerate().filter_map(|(i, o)| {
            o.displacement
                .as_ref()
                .and_then(|d| d.user_wgsl())
                .map(|w| (i, w))
        });
        let user = users.next();
        if let Some((first, wgsl)) = user {
            if let Some((other, _)) = users.find(|(_, w)| *w != wgsl) {
                return Err(RenderError::ConflictingUserDisplacement { first, other });
            }
        }
        let user = user.map(|(_, w)| w);
        let chunks = chunks_per_batch(self.gpu, &self.options, scene.samples_time_and_lens());
        if user == self.compiled_user.as_deref() && chunks == self.compiled_chunks {
            return Ok(());
        }
        if let Some(wgsl) = user {
            crate::displacement::user_wgsl::check(wgsl)?;
        }
        let features = scheduler::recommended_features(&self.gpu.device);
        let compiled = graph::compile_for(features, user, self.options.policy, chunks).map_err(
            |e| match user {
                Some(_) => RenderError::UserDisplacement(e),
                None => RenderError::Compile(e),
            },
        )?;
        self.executor = None;
        self.compiled = compiled;
        self.compiled_user = user.map(str::to_owned);
        self.compiled_chunks = chunks;
        Ok(())
    }

    /// Largest buffer the device binds as storage.
    fn buffer_limit(&self) -> u64 {
        let limits = self.gpu.device.limits();
        limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size)
    }

    /// Checks the frame against the device limits and splits it into screen
    /// tiles whose sample framebuffers fit one device buffer, the shaders'
    /// u32 sample index and [`GpuOptions::max_tile_samples`].
    fn plan(&self, scene: &PreparedScene) -> Result<Vec<Tile>, RenderError> {
        let (width, height, spp) = (scene.camera.width, scene.camera.height, scene.spp);
        let limit = self.buffer_limit();
        let too_large = |what, needed, limit| RenderError::TooLarge {
            what,
            width,
            height,
            spp,
            needed,
            limit,
        };
        // Only tiles are resolved on the device, but a frame whose whole RGBA
        // image exceeds one device buffer is still refused: it would need
        // thousands of tiles and gigabytes of host memory for the image.
        let pixels = u64::from(width) * u64::from(height);
        if 4 * pixels > limit {
            return Err(too_large("image", 4 * pixels, limit));
        }
        // The height maps, and the time/lens tables behind them.
        let needed = texel_buffer_bytes(scene);
        // The shaders index texels with u32.
        let texel_limit = limit.min(4 * u64::from(u32::MAX));
        if needed > texel_limit {
            // The megakernel reads every input patch from this buffer
            // whatever the batches: say how many patches would fit.
            let without_patches = texel_buffer_bytes(&PreparedScene {
                patches: Vec::new(),
                ..scene.clone()
            });
            if without_patches <= texel_limit {
                return Err(RenderError::TooManyPatches {
                    patches: scene.patches.len(),
                    fit: (texel_limit - without_patches) / PATCH_BYTES,
                    needed,
                    limit: texel_limit,
                });
            }
            return Err(RenderError::HeightMapsTooLarge {
                needed,
                limit: texel_limit,
            });
        }
        // 8 bytes per sample in one buffer; the shaders index samples with u32.
        let device_samples = (limit / 8).min(u64::from(u32::MAX));
        let (max_samples, what) = match self.options.max_tile_samples {
            Some(cap) if cap < device_samples => (
                cap,
                "sample framebuffer of the smallest screen tile (capped by GpuOptions::max_tile_samples)",
            ),
            _ => (
                device_samples,
                "sample framebuffer of the smallest screen tile",
            ),
        };
        let spp64 = u64::from(spp.max(1));
        plan_tiles(width, height, max_samples / spp64).ok_or_else(|| {
            let align = u64::from(TILE_ALIGN);
            let smallest = u64::from(width).min(align) * u64::from(height).min(align) * spp64;
            too_large(what, 8 * smallest, 8 * max_samples)
        })
    }

    /// Queue capacities, and the input patches per batch, for a scene of
    /// `patches` input patches: the Bound queue holds one batch of seeds,
    /// the work queues get `work` items. The batch is every patch (or
    /// [`GpuOptions::max_batch_patches`]) unless the queues would then not
    /// fit into one device buffer (`memory_plan`); then it is the largest
    /// power of two that fits next to `work`, and `work` is halved (down to
    /// [`MIN_WORK_CAPACITY`]) only while a batch would be smaller than
    /// [`MIN_BATCH_PATCHES`].
    fn capacities(&self, patches: usize, work: u32) -> Result<(Capacities, u32), RenderError> {
        let limit = self.buffer_limit();
        let all = u32::try_from(patches.max(1))
            .unwrap_or(u32::MAX)
            .min(1 << 31);
        let wanted = self
            .options
            .max_batch_patches
            .map_or(all, |cap| all.min(cap.max(1)));
        let with = |bound: u32, work: u32| {
            DICE.into_iter().fold(
                Capacities::uniform(work)
                    .with(BOUND, bound)
                    .with(SPLIT_U, work)
                    .with(SPLIT_V, work),
                |capacities, dice| capacities.with(dice, work),
            )
        };
        let queue_bytes = |capacities: &Capacities| {
            let plan = self
                .compiled
                .memory_plan(&self.config(capacities.clone(), None));
            plan.queue_bytes.max(plan.control_bytes)
        };
        match plan_batch(wanted, work, limit, |bound, work| {
            queue_bytes(&with(bound, work))
        }) {
            Ok(plan) => Ok((with(plan.bound, plan.work), plan.batch)),
            Err(needed) => Err(RenderError::NoBatchFits {
                patches,
                work_capacity: MIN_WORK_CAPACITY,
                needed,
                limit,
            }),
        }
    }

    /// The iteration budget of a first attempt (see [`GpuOptions::iteration_budget`]).
    fn iteration_budget(&self) -> Option<u32> {
        self.options
            .iteration_budget
            .or_else(|| self.is_cpu().then_some(CPU_ITERATION_BUDGET))
    }

    /// Whether the adapter is a CPU (llvmpipe behind lavapipe).
    fn is_cpu(&self) -> bool {
        is_cpu(self.gpu)
    }

    fn config(&self, capacities: Capacities, iteration_budget: Option<u32>) -> ExecutorConfig {
        let mut config = ExecutorConfig {
            capacities,
            // Rounds launch as many workgroups as a round has batches, up to
            // this count; on llvmpipe each workgroup's loops share one budget
            // for all the batches it strides over, so Rounds keep the
            // scheduler's default there instead of one per core.
            workgroups: self.options.workgroups.or_else(|| {
                (self.is_cpu() && self.options.strategy == Strategy::Megakernel)
                    .then(cpu_workgroups)
            }),
            iteration_budget,
            timeout: self.options.timeout,
        };
        // Every workgroup stages up to a batch's children for each of the
        // six queues; fewer workgroups (Rounds launch up to 1,024) keep that
        // within one device buffer.
        let staging = self.compiled.memory_plan(&config).staging_bytes;
        let limit = self.buffer_limit();
        if staging > limit {
            let workgroups = u64::from(config.workgroups.unwrap_or(DEFAULT_WORKGROUPS));
            let per_workgroup = staging.div_ceil(workgroups);
            config.workgroups = Some(u32::try_from((limit / per_workgroup).max(1)).unwrap_or(1));
        }
        config
    }

    /// Creates the executor unless the cached one has these capacities.
    fn executor(
        &mut self,
        capacities: &Capacities,
        budget: Option<u32>,
    ) -> Result<&mut Executor, RenderError> {
        let stale = self
            .executor
            .as_ref()
            .is_none_or(|(c, b, _)| c != capacities || *b != budget);
        if stale {
            // Drop the old queues before allocating new ones.
            self.executor = None;
            let executor = Executor::new(
                &self.gpu.device,
                &self.gpu.queue,
                &self.compiled,
                &self.config(capacities.clone(), budget),
            )?;
            self.executor = Some((capacities.clone(), budget, executor));
        }
        Ok(&mut self.executor.as_mut().expect("just created").2)
    }

    /// Prepares the frame buffers for `scene` (reused when the sizes match).
    fn frame_buffers(&mut self, scene: &PreparedScene) {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let camera = &scene.camera;
        match &mut self.frame {
            Some((buffers, target))
                if buffers.fits(scene)
                    && target.width == camera.width
                    && target.height == camera.height =>
            {
                buffers.write(queue, scene);
                target.write_params(queue, scene.spp, scene.background);
            }
            _ => {
                self.frame = None;
                self.frame = Some((
                    FrameBuffers::new(device, queue, scene),
                    ResolveTarget::new(
                        device,
                        camera.width,
                        camera.height,
                        scene.spp,
                        scene.background,
                    ),
                ));
            }
        }
    }

    /// Renders one frame.
    ///
    /// A frame whose sample framebuffer exceeds the device's limits (or
    /// [`GpuOptions::max_tile_samples`]) is rendered as screen tiles (see
    /// [`plan_tiles`]), one after another, each through a camera cropped to
    /// the tile ([`crate::camera::Camera::crop`]); their pixels are pasted
    /// into the frame and their counters added up. A frame that fits is one
    /// tile and is rendered exactly as without tiling.
    ///
    /// Within a tile, input patches beyond what the Bound queue holds next
    /// to the work queues in one device buffer (or beyond
    /// [`GpuOptions::max_batch_patches`]) are seeded in batches, one run of
    /// the megakernel each, into the same framebuffer and statistics; the
    /// image and the counters are those of one run of all patches (see
    /// [`GpuRendered::batches`]).
    ///
    /// Within a tile, a queue overflow is retried once from scratch (cleared
    /// framebuffer and statistics) with the work queues' capacities doubled,
    /// and a run whose loops llvmpipe cut short is retried once with
    /// [`CPU_RETRY_ITERATION_BUDGET`]; the result reports both retries.
    pub fn render(&mut self, scene: &PreparedScene) -> Result<GpuRendered, RenderError> {
        let tiles = self.plan(scene)?;
        self.prepare_megakernel(scene)?;
        if let [_] = tiles[..] {
            return self.render_tile(scene);
        }
        self.render_tiles(scene, &tiles)
    }

    /// Renders `scene` tile by tile and pastes the tiles together.
    fn render_tiles(
        &mut self,
        scene: &PreparedScene,
        tiles: &[Tile],
    ) -> Result<GpuRendered, RenderError> {
        let start = Instant::now();
        let (width, height) = (scene.camera.width, scene.camera.height);
        log::info!(
            "{width}x{height} at {} spp exceeds one framebuffer: rendering {} screen tiles",
            scene.spp,
            tiles.len()
        );
        // Only the camera differs between tiles: everything else the frame
        // uniform and the tables derive from the scene stays the frame's.
        let mut tile_scene = scene.clone();
        let mut image = RgbaImage::new(width, height);
        let mut coverage = vec![false; width as usize * height as usize];
        let mut covered_samples = vec![0u8; width as usize * height as usize];
        let mut stats = RenderStats {
            input_patches: scene.patches.len() as u64,
            ..RenderStats::default()
        };
        let (mut report, mut overflow_retries, mut loop_retries, mut batches) = (None, 0, 0, 0);
        let mut megakernel_gpu_ms = Some(0.0);
        let mut megakernel_wall_ms = 0.0;
        for (index, tile) in tiles.iter().enumerate() {
            tile_scene.camera = scene.camera.crop(tile.x0, tile.y0, tile.width, tile.height);
            let rendered = self.render_tile(&tile_scene)?;
            // Progress: a tiled frame is the longest work the renderer does.
            log::info!(
                "tile {}/{} (x {}..{}, y {}..{}): {:.1} s, {} grids",
                index + 1,
                tiles.len(),
                tile.x0,
                tile.x0 + tile.width,
                tile.y0,
                tile.y0 + tile.height,
                rendered.timings.total_wall_ms / 1e3,
                rendered.stats.grids_diced
            );
            let (tw, x0) = (tile.width as usize, tile.x0 as usize);
            for row in 0..tile.height as usize {
                let y = tile.y0 as usize + row;
                let source = row * tw..(row + 1) * tw;
                let target = y * width as usize + x0..y * width as usize + x0 + tw;
                coverage[target.clone()].copy_from_slice(&rendered.coverage[source.clone()]);
                covered_samples[target.clone()]
                    .copy_from_slice(&rendered.covered_samples[source.clone()]);
                image.as_mut()[4 * target.start..4 * target.end]
                    .copy_from_slice(&rendered.image.as_raw()[4 * source.start..4 * source.end]);
            }
            add_tile_stats(&mut stats, &rendered.stats);
            megakernel_gpu_ms = megakernel_gpu_ms
                .zip(rendered.timings.megakernel_gpu_ms)
                .map(|(a, b)| a + b);
            megakernel_wall_ms += rendered.timings.megakernel_wall_ms;
            overflow_retries += rendered.overflow_retries;
            loop_retries += rendered.loop_retries;
            batches += rendered.batches;
            report = rendered.report.or(report);
        }
        // The tiles' frame times plus the pasting.
        let total_wall_ms = start.elapsed().as_secs_f64() * 1e3;
        stats.frame_time_ms = Some(megakernel_gpu_ms.unwrap_or(total_wall_ms));
        Ok(GpuRendered {
            image,
            coverage,
            covered_samples,
            stats,
            report,
            overflow_retries,
            loop_retries,
            timings: FrameTimings {
                megakernel_gpu_ms,
                megakernel_wall_ms,
                total_wall_ms,
            },
            tiles: tiles.len() as u32,
            batches,
        })
    }

    /// Renders `scene`, whose buffers fit the device, in one piece: one run
    /// of the megakernel per batch of input patches (see
    /// [`Self::capacities`]), all into the same framebuffer and statistics.
    /// The framebuffer keeps the nearest sample (a depth-tested atomicMin)
    /// and the counters are sums and maxima, so the batches compose into the
    /// frame one run of every patch would give. A retry starts the whole
    /// attempt again from a cleared frame.
    fn render_tile(&mut self, scene: &PreparedScene) -> Result<GpuRendered, RenderError> {
        let start = Instant::now();
        self.frame_buffers(scene);
        let mut work = self.options.work_capacity;
        let mut budget = self.iteration_budget();
        let mut overflow_retries = 0;
        let mut loop_retries = 0;
        let mut attempt;
        let counters = loop {
            self.clear_frame();
            if scene.patches.is_empty() {
                attempt = Attempt::default();
                break self.read_counters()?;
            }
            let (capacities, batch) = self.capacities(scene.patches.len(), work)?;
            let (outcome, done) = self.run_batches(scene, &capacities, budget, batch);
            attempt = done;
            match outcome {
                Ok(counters) if counters.loops_cut() == 0 => break counters,
                Ok(counters) if loop_retries < MAX_LOOP_RETRIES => {
                    log::warn!(
                        "llvmpipe cut {} rasterization loop(s); rendering again with a smaller iteration budget",
                        counters.loops_cut()
                    );
                    loop_retries += 1;
                    budget = Some(CPU_RETRY_ITERATION_BUDGET);
                }
                Ok(counters) => {
                    return Err(self.loop_limit_error(
                        scene,
                        &counters,
                        0,
                        loop_retries + 1,
                        &capacities,
                        budget,
                        attempt.batch_of(scene.patches.len(), batch),
                    ));
                }
                Err(RenderError::Run(RunError::QueueOverflow {
                    procedure,
                    needed_at_least,
                    ..
                })) if overflow_retries == 0 => {
                    log::warn!(
                        "queue {procedure} overflowed (needed at least {needed_at_least}); rendering again with doubled capacities"
                    );
                    overflow_retries += 1;
                    work = work.saturating_mul(2);
                }
                Err(RenderError::Run(RunError::LoopLimit { waits, .. }))
                    if loop_retries < MAX_LOOP_RETRIES =>
                {
                    log::warn!(
                        "llvmpipe cut {waits} queue wait(s); rendering again with a smaller iteration budget"
                    );
                    loop_retries += 1;
                    budget = Some(CPU_RETRY_ITERATION_BUDGET);
                }
                Err(RenderError::Run(RunError::LoopLimit { waits, .. })) => {
                    // The scheduler's own advice (retry with a smaller
                    // budget) is spent: say what is too long instead.
                    let counters = self.read_counters()?;
                    return Err(self.loop_limit_error(
                        scene,
                        &counters,
                        waits,
                        loop_retries + 1,
                        &capacities,
                        budget,
                        attempt.batch_of(scene.patches.len(), batch),
                    ));
                }
                Err(e) => return Err(e),
            }
        };
        let (buffers, target) = self.frame.as_ref().expect("prepared above");
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let resolved = self.resolver.resolve(
            device,
            queue,
            target,
            &buffers.framebuffer,
            self.options.timeout,
        )?;
        let image = RgbaImage::from_raw(target.width, target.height, resolved.rgba)
            .expect("the image buffer holds width * height RGBA8 pixels");
        let total_wall = start.elapsed();
        let mut stats = counters.to_stats();
        // Bound counts the patches it ran; a scene without patches runs nothing.
        stats.input_patches = scene.patches.len() as u64;
        let megakernel_gpu_ms = attempt.gpu_time.map(|d| d.as_secs_f64() * 1e3);
        stats.frame_time_ms = Some(megakernel_gpu_ms.unwrap_or(total_wall.as_secs_f64() * 1e3));
        Ok(GpuRendered {
            image,
            coverage: resolved.coverage,
            covered_samples: resolved.covered_samples,
            stats,
            report: attempt.report,
            overflow_retries,
            loop_retries,
            timings: FrameTimings {
                megakernel_gpu_ms,
                megakernel_wall_ms: attempt.wall.as_secs_f64() * 1e3,
                total_wall_ms: total_wall.as_secs_f64() * 1e3,
            },
            tiles: 1,
            batches: attempt.batches,
        })
    }

    /// Runs the megakernel once per batch of `batch` input patches of
    /// `scene` into the cleared frame. Stops at the first failed run, or at
    /// the first run after which llvmpipe had cut rasterization loops (the
    /// frame is then rendered again anyway); otherwise returns the counters
    /// of all batches together.
    fn run_batches(
        &mut self,
        scene: &PreparedScene,
        capacities: &Capacities,
        budget: Option<u32>,
        batch: u32,
    ) -> (Result<GpuCounters, RenderError>, Attempt) {
        let mut attempt = Attempt {
            gpu_time: Some(Duration::ZERO),
            ..Attempt::default()
        };
        let ranges = batch_ranges(scene.patches.len(), batch);
        let count = ranges.len();
        for (index, range) in ranges.into_iter().enumerate() {
            // Seeds keep the scene's patch indices: every run reads its
            // patches from the same scene buffers.
            let seeds: Vec<PatchItem> = scene.patches[range.clone()]
                .iter()
                .zip(range.start..)
                .map(|(patch, index)| PatchItem::input(patch, index as u32))
                .collect();
            let run_start = Instant::now();
            // The executor borrows `self` mutably; take the buffers out meanwhile.
            let frame = self.frame.take().expect("prepared above");
            let strategy = self.options.strategy;
            let result = self.executor(capacities, budget).and_then(|executor| {
                executor
                    .run_with(
                        strategy,
                        &Seeds::new().add_untyped(&scheduler::ProcedureId::named(BOUND), &seeds),
                        &frame.0.bindings(),
                    )
                    .map_err(RenderError::Run)
            });
            self.frame = Some(frame);
            attempt.wall += run_start.elapsed();
            attempt.batches += 1;
            match result {
                Ok(report) => {
                    attempt.gpu_time = attempt.gpu_time.zip(report.gpu_time).map(|(a, b)| a + b);
                    attempt.report = Some(report);
                }
                Err(e) => return (Err(e), attempt),
            }
            if count > 1 && index + 1 < count {
                match self.read_counters() {
                    Ok(counters) if counters.loops_cut() > 0 => return (Ok(counters), attempt),
                    Ok(_) => {}
                    Err(e) => return (Err(e), attempt),
                }
                log::info!(
                    "batch {}/{count} of input patches ({}..{}) done",
                    index + 1,
                    range.start,
                    range.end
                );
            }
        }
        (self.read_counters(), attempt)
    }

    /// The error after the last retry still cut loops: the facts of the
    /// last run and advice from the scene's configuration.
    #[allow(clippy::too_many_arguments)]
    fn loop_limit_error(
        &self,
        scene: &PreparedScene,
        counters: &GpuCounters,
        waits: u32,
        runs: u32,
        capacities: &Capacities,
        budget: Option<u32>,
        batch: (u32, u32),
    ) -> RenderError {
        let stats = counters.to_stats();
        let context = LoopLimitContext::new(
            scene,
            stats.depth_guard_drops,
            stats.largest_micropolygon_px,
        );
        let workgroups = self
            .config(capacities.clone(), budget)
            .workgroups
            .unwrap_or(DEFAULT_WORKGROUPS);
        RenderError::LoopLimit(Box::new(LoopLimitError::new(
            counters.loops_cut(),
            waits,
            runs,
            workgroups,
            budget,
            batch,
            context,
        )))
    }

    fn read_counters(&self) -> Result<GpuCounters, RenderError> {
        let (buffers, _) = self.frame.as_ref().expect("prepared above");
        let bytes = read_buffer(
            &self.gpu.device,
            &self.gpu.queue,
            &buffers.stats,
            self.options.timeout,
        )?;
        Ok(GpuCounters::from_bytes(&bytes))
    }

    /// Clears the framebuffer and zeroes the statistics.
    fn clear_frame(&self) {
        let (buffers, target) = self.frame.as_ref().expect("prepared before clearing");
        buffers.reset_stats(&self.gpu.queue);
        self.resolver.clear(
            &self.gpu.device,
            &self.gpu.queue,
            target,
            &buffers.framebuffer,
            buffers.samples,
        );
    }
}

/// Queue capacities of one run and the input patches it seeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct BatchPlan {
    /// Capacity of the Bound queue (a power of two).
    bound: u32,
    /// Capacity of each work queue.
    work: u32,
    /// Input patches per run (at most `bound`).
    batch: u32,
}

/// Plans batches of at most `wanted` input patches with work queues of
/// `work` items, where `queue_bytes(bound, work)` is what the queues then
/// need and `limit` what one device buffer holds: the largest power-of-two
/// Bound queue up to `wanted` that fits next to `work`; `work` is halved
/// (not below [`MIN_WORK_CAPACITY`]) only while the batch would be smaller
/// than [`MIN_BATCH_PATCHES`] (and than `wanted`). `Err`: the bytes one
/// patch needs next to the smallest work queues, when that exceeds `limit`.
fn plan_batch(
    wanted: u32,
    work: u32,
    limit: u64,
    queue_bytes: impl Fn(u32, u32) -> u64,
) -> Result<BatchPlan, u64> {
    let wanted = wanted.clamp(1, 1 << 31);
    let mut work = work.max(MIN_WORK_CAPACITY);
    loop {
        let mut bound = wanted.next_power_of_two();
        while bound > 1 && queue_bytes(bound, work) > limit {
            bound /= 2;
        }
        let fits = queue_bytes(bound, work) <= limit;
        if fits && (bound >= wanted || bound >= MIN_BATCH_PATCHES || work <= MIN_WORK_CAPACITY) {
            return Ok(BatchPlan {
                bound,
                work,
                batch: wanted.min(bound),
            });
        }
        if work <= MIN_WORK_CAPACITY {
            return Err(queue_bytes(1, work));
        }
        work /= 2;
    }
}

/// The runs of one attempt at a tile.
#[derive(Debug, Default)]
struct Attempt {
    /// The report of the last run.
    report: Option<RunReport>,
    /// GPU time of the runs, when every run measured it.
    gpu_time: Option<Duration>,
    /// Host wall time of the runs.
    wall: Duration,
    /// Runs made (batches started).
    batches: u32,
}

impl Attempt {
    /// The batch the attempt stopped in (1-based) and the batches of the
    /// attempt, for `patches` patches in batches of `batch`.
    fn batch_of(&self, patches: usize, batch: u32) -> (u32, u32) {
        let count = patches.div_ceil(batch.max(1) as usize) as u32;
        (self.batches.max(1), count.max(1))
    }
}

/// The input patches `0..patches` in consecutive batches of at most `batch`
/// (at least one patch each); none for no patches.
fn batch_ranges(patches: usize, batch: u32) -> Vec<std::ops::Range<usize>> {
    let batch = batch.max(1) as usize;
    (0..patches)
        .step_by(batch)
        .map(|start| start..(start + batch).min(patches))
        .collect()
}

/// Whether `gpu`'s driver caps the loops of an invocation (llvmpipe behind
/// lavapipe), as the scheduler's [`scheduler::Quirks`] decide.
fn is_cpu(gpu: &Gpu) -> bool {
    scheduler::Quirks::of(&gpu.adapter.get_info()).caps_loops()
}

/// The chunks per batch `options` ask for on `gpu`, for a frame that samples
/// time or lens (`blurred`) or not.
fn chunks_per_batch(gpu: &Gpu, options: &GpuOptions, blurred: bool) -> u32 {
    options
        .chunks_per_batch
        .unwrap_or(if is_cpu(gpu) && !blurred {
            CPU_CHUNKS_PER_BATCH
        } else {
            1
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks that `tiles` cover the image exactly once, start at aligned
    /// origins and each hold at most `max_pixels` pixels.
    fn check_tiling(width: u32, height: u32, max_pixels: u64, tiles: &[Tile]) {
        let mut covered = vec![0u8; width as usize * height as usize];
        for tile in tiles {
            assert!(tile.width > 0 && tile.height > 0, "{tile:?}");
            assert!(
                u64::from(tile.width) * u64::from(tile.height) <= max_pixels,
                "{width}x{height}, {max_pixels}: {tile:?}"
            );
            if tiles.len() > 1 {
                assert!(tile.x0.is_multiple_of(TILE_ALIGN), "{tile:?}");
                assert!(tile.y0.is_multiple_of(TILE_ALIGN), "{tile:?}");
            }
            assert!(tile.x0 + tile.width <= width && tile.y0 + tile.height <= height);
            for y in tile.y0..tile.y0 + tile.height {
                for x in tile.x0..tile.x0 + tile.width {
                    covered[(y * width + x) as usize] += 1;
                }
            }
        }
        assert!(
            covered.iter().all(|&c| c == 1),
            "{width}x{height}, {max_pixels}: {tiles:?}"
        );
    }

    /// Six queues of 240-byte slots, as the Reyes graph has (Bound, SplitU,
    /// SplitV and three dice queues).
    fn six_queues(bound: u32, work: u32) -> u64 {
        240 * (u64::from(bound.next_power_of_two()) + 5 * u64::from(work.next_power_of_two()))
    }

    #[test]
    fn patches_beyond_the_queue_are_planned_in_batches() {
        // About 540k patches on lavapipe's 128 MiB: 2^17 per run next to
        // the full work queues (2^18 would need 141 MB), so five runs (D17).
        let plan = plan_batch(540_000, DEFAULT_WORK_CAPACITY, 1 << 27, six_queues).unwrap();
        assert_eq!(
            plan,
            BatchPlan {
                bound: 1 << 17,
                work: DEFAULT_WORK_CAPACITY,
                batch: 1 << 17
            }
        );
        assert_eq!(batch_ranges(540_000, plan.batch).len(), 5);
        // What fits is one run, with the batch limit if there is one.
        let plan = plan_batch(32, DEFAULT_WORK_CAPACITY, 1 << 27, six_queues).unwrap();
        assert_eq!((plan.bound, plan.batch), (32, 32));
        let plan = plan_batch(7, DEFAULT_WORK_CAPACITY, 1 << 27, six_queues).unwrap();
        assert_eq!((plan.bound, plan.batch), (8, 7));
    }

    #[test]
    fn work_queues_shrink_only_for_batches_below_the_minimum() {
        // Room for the work queues at 2^14 and a Bound queue of 2^12.
        let limit = six_queues(1 << 12, 1 << 14);
        let plan = plan_batch(100_000, 1 << 16, limit, six_queues).unwrap();
        assert_eq!(
            (plan.work, plan.bound, plan.batch),
            (1 << 14, 1 << 12, 1 << 12)
        );
        // A small scene keeps its one run with smaller work queues.
        let plan = plan_batch(100, 1 << 16, limit, six_queues).unwrap();
        assert_eq!((plan.bound, plan.batch), (128, 100));
        assert!(six_queues(128, plan.work) <= limit && plan.work >= 1 << 14);
        // At the smallest work queues any batch that fits is taken.
        let limit = six_queues(16, MIN_WORK_CAPACITY);
        let plan = plan_batch(1000, 1 << 16, limit, six_queues).unwrap();
        assert_eq!((plan.work, plan.batch), (MIN_WORK_CAPACITY, 16));
    }

    #[test]
    fn a_device_too_small_for_one_patch_says_what_it_needs() {
        let needed = six_queues(1, MIN_WORK_CAPACITY);
        assert_eq!(plan_batch(10, 1 << 16, needed - 1, six_queues), Err(needed));
        assert!(plan_batch(10, 1 << 16, needed, six_queues).is_ok());
        let message = RenderError::NoBatchFits {
            patches: 10,
            work_capacity: MIN_WORK_CAPACITY,
            needed,
            limit: needed - 1,
        }
        .to_string();
        assert!(message.contains("0 of the 10 patches fit"), "{message}");
        let message = RenderError::TooManyPatches {
            patches: 800_000,
            fit: 699_050,
            needed: 153_600_000,
            limit: 1 << 27,
        }
        .to_string();
        assert!(message.contains("699050 patches fit"), "{message}");
    }

    #[test]
    fn batches_cover_the_patches_in_order() {
        assert!(batch_ranges(0, 5).is_empty());
        assert_eq!(batch_ranges(3, 5), Vec::from_iter(std::iter::once(0..3)));
        assert_eq!(batch_ranges(10, 5), [0..5, 5..10]);
        assert_eq!(batch_ranges(11, 4), [0..4, 4..8, 8..11]);
        assert_eq!(batch_ranges(2, 0), [0..1, 1..2]);
        let attempt = Attempt {
            batches: 2,
            ..Attempt::default()
        };
        assert_eq!(attempt.batch_of(11, 4), (2, 3));
        assert_eq!(Attempt::default().batch_of(3, 8), (1, 1));
    }

    #[test]
    fn a_frame_that_fits_is_one_tile() {
        let tiles = plan_tiles(800, 600, 800 * 600).unwrap();
        assert_eq!(
            tiles,
            [Tile {
                x0: 0,
                y0: 0,
                width: 800,
                height: 600
            }]
        );
    }

    #[test]
    fn bands_are_preferred_and_evened_out() {
        // 1920x1080 at 64 spp under lavapipe's 128 MiB: 2^24 samples per tile.
        let tiles = plan_tiles(1920, 1080, (1 << 24) / 64).unwrap();
        check_tiling(1920, 1080, (1 << 24) / 64, &tiles);
        assert_eq!(tiles.len(), 9);
        assert!(tiles.iter().all(|t| t.x0 == 0 && t.width == 1920));
        // 800x600 at 64 spp: two bands (320 + 280 rows), not 320 + 256 + 24.
        let tiles = plan_tiles(800, 600, (1 << 24) / 64).unwrap();
        check_tiling(800, 600, (1 << 24) / 64, &tiles);
        let heights: Vec<u32> = tiles.iter().map(|t| t.height).collect();
        assert_eq!(heights, [320, 280]);
    }

    #[test]
    fn narrow_budgets_give_square_ish_tiles() {
        // 200x150 with room for 8192 pixels: no band of 64 rows fits.
        let tiles = plan_tiles(200, 150, 8192).unwrap();
        check_tiling(200, 150, 8192, &tiles);
        assert_eq!(tiles.len(), 6);
        assert!(tiles.iter().any(|t| !t.width.is_multiple_of(TILE_ALIGN)));
        assert!(tiles.iter().any(|t| !t.height.is_multiple_of(TILE_ALIGN)));
        // A short, wide image is cut into columns of its full height.
        let tiles = plan_tiles(10_000, 3, 1000).unwrap();
        check_tiling(10_000, 3, 1000, &tiles);
        assert!(tiles.iter().all(|t| t.y0 == 0 && t.height == 3));
    }

    #[test]
    fn impossible_budgets_are_refused() {
        assert_eq!(plan_tiles(200, 150, 64 * 64 - 1), None);
        assert_eq!(plan_tiles(10_000, 1, 63), None);
        assert_eq!(plan_tiles(30, 10_000, 30 * 64 - 1), None);
        assert!(plan_tiles(30, 10_000, 30 * 64).is_some());
    }

    #[test]
    fn random_plans_cover_the_image() {
        let mut state = 0x853c_49e6_748f_ea9bu64;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) % n
        };
        for _ in 0..300 {
            let width = 1 + next(700) as u32;
            let height = 1 + next(700) as u32;
            let max_pixels = 1 + next(u64::from(width) * u64::from(height) + 5000);
            match plan_tiles(width, height, max_pixels) {
                Some(tiles) => check_tiling(width, height, max_pixels, &tiles),
                None => assert!(
                    u64::from(width.min(TILE_ALIGN)) * u64::from(height.min(TILE_ALIGN))
                        > max_pixels
                ),
            }
        }
    }
}
