//! [`GpuRenderer`]: runs one frame of the Reyes megakernel and returns the
//! image, the coverage and the [`RenderStats`](crate::stats::RenderStats).
//!
//! What the renderer takes and gives ([`GpuOptions`], [`GpuRendered`],
//! [`RenderError`]), the screen tiles ([`plan_tiles`]), the batches of input
//! patches live in modules of their own beside this one and are re-exported
//! here. The renderer's methods are split by what they do: fitting a frame
//! to the device (`limits`), running the megakernel (`runs`, where the
//! scheduler's `run_with_retry` retries after queue overflows and llvmpipe's
//! loop limit) and rendering in screen tiles (`tiled`); this file compiles
//! the megakernel and renders one tile. Per-driver defaults come from the
//! scheduler's [`scheduler::Quirks`].

use std::sync::Arc;
use std::time::Instant;

use image::Rgba32FImage;
use scheduler::readback::read_buffer;
use scheduler::{Capacities, CompiledGraph, Executor, Gpu, Quirks, RunError};

use super::batches::TileRuns;
use super::buffers::{FrameBuffers, GpuCounters};
use super::graph::{self, UserCode, WIDE_ATOMICS};
use super::loop_limit::{LoopLimitContext, LoopLimitError};
use super::render_error::ShadingRateTooSmall;
use super::resolve::{ResolveTarget, Resolver};
use super::variant::KernelVariant;
use crate::prepare::PreparedScene;
use crate::surface_shader::SurfaceShader;

pub use super::options::{
    DEFAULT_RENDER_TIMEOUT, DEFAULT_WORK_CAPACITY, FrameTimings, GpuOptions, GpuRendered,
};
pub use super::render_error::RenderError;
pub use super::tiles::{TILE_ALIGN, Tile, plan_tiles, plan_tiles_with_margin};
pub use runs::RENDER_ATTEMPTS;

mod limits;
mod runs;
mod tiled;

/// The chunks per batch `options` ask for on `gpu`, for a frame that samples
/// time or lens (`blurred`) or not: by default what the driver's quirks
/// favour ([`Quirks::chunks_per_batch`]) for frames without motion blur or
/// depth of field, whose rasterization loops are short enough; blurred
/// frames keep 1, as their loops ran into llvmpipe's loop limit at 4 chunks
/// per batch and the bookkeeping is a small share of their time.
fn chunks_per_batch(gpu: &Gpu, options: &GpuOptions, blurred: bool) -> u32 {
    options.chunks_per_batch.unwrap_or(if blurred {
        1
    } else {
        Quirks::of_device(&gpu.device).chunks_per_batch()
    })
}

/// `variant` as the renderer runs it on `gpu`: with the 32-bit depth test
/// where the device lacks 64-bit atomics or `options` ask for it
/// ([`GpuOptions::two_pass_depth_test`]).
fn on_device(gpu: &Gpu, options: &GpuOptions, variant: KernelVariant) -> KernelVariant {
    if options.two_pass_depth_test || !gpu.device.features().contains(WIDE_ATOMICS) {
        variant.with_32_bit_atomics()
    } else {
        variant
    }
}

/// Programs of other variants a renderer keeps (with their executors,
/// which hold queue buffers) besides the current one.
const MAX_PARKED_PROGRAMS: usize = 3;

/// What selects a megakernel module.
#[derive(Debug, PartialEq)]
struct ProgramKey {
    variant: KernelVariant,
    /// The frame's surface and displacement shaders (compared by content).
    surfaces: Vec<Arc<SurfaceShader>>,
    chunks: u32,
}

/// A compiled megakernel not in use, with its executor if one was made.
#[derive(Debug)]
struct ParkedProgram {
    key: ProgramKey,
    compiled: CompiledGraph,
    executor: Option<(Capacities, Option<u32>, Executor)>,
}

/// Renders prepared scenes with the Reyes megakernel. Pipelines, the
/// executor (for a given queue sizing) and the frame buffers (for a given
/// resolution) are created on first use and reused by later frames.
#[derive(Debug)]
pub struct GpuRenderer<'a> {
    gpu: &'a Gpu,
    options: GpuOptions,
    compiled: CompiledGraph,
    /// What `compiled` was compiled for: its variant, the user shaders,
    /// the chunks per batch.
    compiled_key: ProgramKey,
    resolver: Resolver,
    executor: Option<(Capacities, Option<u32>, Executor)>,
    /// Megakernels of other variants compiled before, with their executors
    /// (most recently used last), so that a program that alternates between
    /// variants (the viewer toggling motion blur) compiles each once.
    parked: Vec<ParkedProgram>,
    frame: Option<(FrameBuffers, ResolveTarget)>,
    /// Executors (and so pipelines: the driver's compile) created so far.
    pipelines_created: u32,
}

impl<'a> GpuRenderer<'a> {
    /// Compiles the megakernel for `gpu`'s device. A device with 64-bit
    /// atomics ([`WIDE_ATOMICS`], which [`super::create_gpu`] asks for)
    /// keeps each sample's nearest surface in one pass; any other in two
    /// ([`DepthTest::TwoPass32`](super::DepthTest::TwoPass32)).
    pub fn new(gpu: &'a Gpu, options: GpuOptions) -> Result<Self, RenderError> {
        let variant = on_device(gpu, &options, KernelVariant::default());
        let chunks = chunks_per_batch(gpu, &options, false);
        if let Some(max) = Quirks::of_device(&gpu.device).max_chunks_per_batch()
            && chunks > max
        {
            return Err(RenderError::TooManyChunks { chunks, max });
        }
        let compiled = graph::compile_traced(
            scheduler::recommended_features(&gpu.device),
            variant,
            &UserCode::NONE,
            (options.policy, chunks),
            options.trace,
        )?;
        if options.chunks_per_batch.is_some() {
            // A chosen chunk count is likely a module the driver has not
            // cached (see `prepare_megakernel`).
            log::info!(
                "megakernel with {chunks} chunk(s) per batch: the driver compiles it when the renderer creates its executor, which takes minutes on lavapipe when its shader cache lacks it"
            );
        }
        Ok(Self {
            gpu,
            options,
            compiled,
            compiled_key: ProgramKey {
                variant,
                surfaces: Vec::new(),
                chunks,
            },
            resolver: Resolver::new(&gpu.device),
            executor: None,
            parked: Vec::new(),
            frame: None,
            pipelines_created: 0,
        })
    }

    /// The compiled megakernel (of the last scene's variant and user
    /// shaders).
    pub fn compiled(&self) -> &CompiledGraph {
        &self.compiled
    }

    /// The variant the megakernel is specialized to (the last scene's).
    pub fn variant(&self) -> KernelVariant {
        self.compiled_key.variant
    }

    /// How many pipelines (executors, each a driver compile of a megakernel
    /// module) this renderer has created: a frame that reuses the program
    /// and queues of an earlier one creates none.
    pub fn pipelines_created(&self) -> u32 {
        self.pipelines_created
    }

    /// Compiles the megakernel again when `scene` needs a different variant
    /// ([`KernelVariant::of`], on this device), user shaders, or chunks per
    /// batch than the one compiled in. The current program is parked, and
    /// one parked before is taken back when it fits (up to
    /// `MAX_PARKED_PROGRAMS`, least recently used first out), so that
    /// alternating frames compile each module and create each pipeline
    /// once.
    fn prepare_megakernel(&mut self, scene: &PreparedScene) -> Result<(), RenderError> {
        let chunks = chunks_per_batch(self.gpu, &self.options, scene.samples_time_and_lens());
        let key = ProgramKey {
            variant: on_device(self.gpu, &self.options, KernelVariant::of(scene)),
            surfaces: scene.shaders.shaders.clone(),
            chunks,
        };
        if key == self.compiled_key {
            return Ok(());
        }
        let program = match self.parked.iter().position(|p| p.key == key) {
            Some(index) => self.parked.remove(index),
            None => self.compile_program(key)?,
        };
        let current = ParkedProgram {
            key: std::mem::replace(&mut self.compiled_key, program.key),
            compiled: std::mem::replace(&mut self.compiled, program.compiled),
            executor: std::mem::replace(&mut self.executor, program.executor),
        };
        self.parked.push(current);
        if self.parked.len() > MAX_PARKED_PROGRAMS {
            self.parked.remove(0);
        }
        Ok(())
    }

    /// Compiles the megakernel of `key` (the driver compiles it when its
    /// executor is created).
    fn compile_program(&self, key: ProgramKey) -> Result<ParkedProgram, RenderError> {
        let ProgramKey {
            variant,
            ref surfaces,
            chunks,
        } = key;
        let features = scheduler::recommended_features(&self.gpu.device);
        let code = UserCode { surfaces };
        let compiled = graph::compile_traced(
            features,
            variant,
            &code,
            (self.options.policy, chunks),
            self.options.trace,
        )
        .map_err(RenderError::Compile)?;
        log::info!(
            "new megakernel for {variant} ({chunks} chunk(s) per batch, {} user shader(s)): the driver compiles it when the executor is created, which takes minutes on lavapipe when its shader cache lacks it",
            surfaces.len()
        );
        Ok(ParkedProgram {
            key,
            compiled,
            executor: None,
        })
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
                target.write_params(queue, scene);
            }
            _ => {
                self.frame = None;
                self.frame = Some((
                    FrameBuffers::new(device, queue, scene),
                    ResolveTarget::new(device, scene),
                ));
            }
        }
    }

    /// Renders one frame.
    ///
    /// A frame whose sample framebuffer exceeds the device's limits (or
    /// [`GpuOptions::max_tile_samples`]) is rendered as screen tiles (see
    /// `plan_tiles`), one after another, each through a camera cropped to
    /// the tile (`crate::camera::Camera::crop`); their pixels are pasted
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
    /// Each run goes through the scheduler's
    /// [`Executor::run_with_retry`](scheduler::Executor::run_with_retry), up
    /// to `RENDER_ATTEMPTS` attempts: a queue overflow grows the queues to
    /// the measured need, and a run whose loops llvmpipe cut short (the
    /// scheduler's waits, or the rasterization loops the renderer counts and
    /// reports through [`scheduler::Retry::check_loops`]) runs again with
    /// half the iteration budget. Before a retry the statistics are restored
    /// to what they were before the batch; the framebuffer keeps the nearest
    /// sample, so a repeated batch changes nothing there. The grown queues
    /// and the lowered budget stay for later batches, tiles and frames; the
    /// result counts the retries.
    ///
    /// [`GpuOptions::progress`] hears the frame start and finish, the
    /// driver's compile of the megakernel, and the tiles and batches.
    ///
    /// A frame with pending shadows (`[[lights]] shadows = true`) renders
    /// its depth passes first, each an ordinary frame of the depth output
    /// from a light ([`PreparedScene::with_shadow_maps`]), then itself with
    /// the maps; [`RenderStats::passes`](crate::stats::RenderStats::passes)
    /// counts each pass.
    pub fn render(&mut self, scene: &PreparedScene) -> Result<GpuRendered, RenderError> {
        scene.render_with_shadows(|pass, _| self.observed_frame(pass, Self::render_frame))
    }

    /// [`Self::render`] without the observer's frame events.
    fn render_frame(&mut self, scene: &PreparedScene) -> Result<GpuRendered, RenderError> {
        let tiles = self.plan(scene)?;
        self.prepare_megakernel(scene)?;
        if let [_] = tiles[..] {
            return self.render_tile(scene);
        }
        self.render_tiles(scene, &tiles)
    }

    /// Renders `scene`, whose buffers fit the device, in one piece: one run
    /// of the megakernel per batch of input patches (see
    /// [`Self::capacities`]), all into the same framebuffer and statistics.
    /// The framebuffer keeps the nearest sample (a depth-tested atomicMin)
    /// and the counters are sums and maxima, so the batches compose into the
    /// frame one run of every patch would give.
    fn render_tile(&mut self, scene: &PreparedScene) -> Result<GpuRendered, RenderError> {
        let start = Instant::now();
        self.frame_buffers(scene);
        self.clear_frame()?;
        let (counters, runs) = if scene.patches.is_empty() {
            (self.read_counters()?, TileRuns::default())
        } else {
            let (capacities, batch) =
                self.capacities(scene.patches.len(), self.options.work_capacity)?;
            let budget = self.iteration_budget();
            match self.run_passes(scene, &capacities, budget, batch) {
                (Ok(counters), runs) => (counters, runs),
                (Err(RenderError::Run(error @ RunError::LoopLimit { .. })), runs) => {
                    // The scheduler's retries with smaller budgets are
                    // spent: say what is too long instead.
                    let batch = runs.batch_of(scene.patches.len(), batch);
                    return Err(self.loop_limit_error(scene, error, batch)?);
                }
                (
                    Err(RenderError::Run(RunError::QueueExceedsDevice {
                        procedure,
                        needed,
                        max,
                        ..
                    })),
                    _,
                ) if scene.dicing.mode() == crate::modes::Dicing::Rate => {
                    // The split and dice queues hold what the patches become
                    // at the shading rate: say so, and which rate fits.
                    let patches = batch.min(u32::try_from(scene.patches.len()).unwrap_or(u32::MAX));
                    return Err(RenderError::ShadingRateTooSmall(Box::new(
                        ShadingRateTooSmall::new(scene, procedure, needed, max, patches),
                    )));
                }
                (Err(e), _) => return Err(e),
            }
        };
        let (buffers, target) = self.frame.as_ref().expect("prepared above");
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let resolved = self.resolver.resolve(
            device,
            queue,
            target,
            &buffers.framebuffer,
            scene.aov == crate::Aov::Z,
            self.options.timeout,
        )?;
        let mut linear = Rgba32FImage::from_raw(target.width, target.height, resolved.linear)
            .expect("the image buffer holds width * height RGBA f32 pixels");
        if scene.aov == crate::Aov::Z {
            crate::depth::finish_depths(&mut linear);
        }
        // Encoded on the host, as the CPU reference does: equal floats give
        // equal 8-bit images, and the dither follows absolute pixels.
        let image = scene.encoding.encode(&linear, scene.camera.origin);
        let total_wall = start.elapsed();
        let mut stats = counters.to_stats();
        // Bound counts the patches it ran; a scene without patches runs nothing.
        stats.input_patches = scene.patches.len() as u64;
        let megakernel_gpu_ms = runs.gpu_time.map(|d| d.as_secs_f64() * 1e3);
        stats.frame_time_ms = Some(megakernel_gpu_ms.unwrap_or(total_wall.as_secs_f64() * 1e3));
        Ok(GpuRendered {
            image,
            linear,
            coverage: resolved.coverage,
            covered_samples: resolved.covered_samples,
            stats,
            report: runs.report,
            overflow_retries: runs.overflow_retries,
            loop_retries: runs.loop_retries,
            timings: FrameTimings {
                megakernel_gpu_ms,
                megakernel_wall_ms: runs.wall.as_secs_f64() * 1e3,
                total_wall_ms: total_wall.as_secs_f64() * 1e3,
            },
            tiles: 1,
            batches: runs.batches,
        })
    }

    /// The error after the scheduler's last retry still cut loops
    /// (`error`, a [`RunError::LoopLimit`]): its facts, the iteration budget
    /// the scheduler ended with, the counters of that last run and advice
    /// from the scene's configuration.
    fn loop_limit_error(
        &self,
        scene: &PreparedScene,
        error: RunError,
        batch: (u32, u32),
    ) -> Result<RenderError, RenderError> {
        let stats = self.read_counters()?.to_stats();
        let context = LoopLimitContext::new(
            scene,
            stats.depth_guard_drops,
            stats.largest_micropolygon_px,
        );
        let budget = self
            .executor
            .as_ref()
            .map(|(_, _, executor)| executor.iteration_budget())
            .filter(|&budget| budget != u32::MAX);
        Ok(
            match LoopLimitError::from_run(error, budget, batch, context) {
                Ok(error) => RenderError::LoopLimit(Box::new(error)),
                Err(error) => RenderError::Run(error),
            },
        )
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
    fn clear_frame(&self) -> Result<(), RenderError> {
        let (buffers, target) = self.frame.as_ref().expect("prepared before clearing");
        buffers.reset_stats(&self.gpu.queue);
        self.resolver.clear(
            &self.gpu.device,
            &self.gpu.queue,
            target,
            &buffers.framebuffer,
            buffers.samples,
        )
    }
}
