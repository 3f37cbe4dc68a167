//! Running the megakernel: the executor's configuration and the runs of a
//! tile, one per batch of input patches, each through the scheduler's
//! [`Executor::run_with_retry`].

use std::time::{Duration, Instant};

use scheduler::readback::read_buffer;
use scheduler::{
    Capacities, DEFAULT_WORKGROUPS, Executor, ExecutorConfig, Quirks, Retry, RunError, Seeds,
    Strategy,
};

use super::GpuRenderer;
use crate::gpu::batches::{TileRuns, batch_ranges};
use crate::gpu::buffers::GpuCounters;
use crate::gpu::graph::{BOUND, COLOUR_PASS, DEPTH_PASS, InputPatch, PASS_RESOURCE};
use crate::gpu::variant::DepthTest;
use crate::gpu::options::GpuRendered;
use crate::gpu::pipeline_cache::PipelineInfo;
use crate::gpu::render_error::RenderError;
use crate::prepare::PreparedScene;
use crate::progress::{AdapterSummary, ProgressEvent};

/// Attempts at each batch of input patches, the first included: the
/// scheduler's queue growth converged within two extra attempts in every
/// measured run (docs/scheduler.md, "Overflow and retry"), and a loop limit
/// halves the first budget of 16 batches per dispatch down to 2 in three
/// more.
pub const RENDER_ATTEMPTS: u32 = 6;

impl GpuRenderer<'_> {
    /// The driver's quirks, which decide the defaults below.
    pub(super) fn quirks(&self) -> Quirks {
        Quirks::of_device(&self.gpu.device)
    }

    /// The iteration budget of a first attempt (see
    /// [`GpuOptions::iteration_budget`](super::GpuOptions::iteration_budget)):
    /// the rasterization loops are long, so on drivers that cap loops the
    /// budget for long-looping bodies.
    pub(super) fn iteration_budget(&self) -> Option<u32> {
        self.options.iteration_budget.or_else(|| {
            self.quirks()
                .long_body_iteration_budget(self.compiled_key.chunks)
        })
    }

    pub(super) fn config(
        &self,
        capacities: Capacities,
        iteration_budget: Option<u32>,
    ) -> ExecutorConfig {
        let mut config = ExecutorConfig {
            capacities,
            workgroups: self.options.workgroups.or_else(|| {
                (self.options.strategy == Strategy::Megakernel)
                    .then(|| self.quirks().megakernel_workgroups())
                    .flatten()
            }),
            round_workgroups: None,
            iteration_budget,
            timeout: self.options.timeout,
            pipeline_cache_dir: self.options.pipeline_cache_dir.clone(),
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

    /// The pipeline of the current executor: whether it came from the
    /// pipeline cache, and the driver's compile times. `None` before the
    /// first frame (and after a recompile, until the next).
    pub fn last_pipeline(&self) -> Option<PipelineInfo> {
        let (_, _, executor) = self.executor.as_ref()?;
        Some(PipelineInfo::of(executor))
    }

    /// Creates the executor unless the cached one was created for these
    /// capacities and budget. The cached one keeps what the scheduler's
    /// retries changed (grown queues, a lower budget) for later batches,
    /// tiles and frames.
    pub(super) fn executor(
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
            let compile = self.compile_started();
            let executor = Executor::new(
                &self.gpu.device,
                &self.gpu.queue,
                &self.compiled,
                &self.config(capacities.clone(), budget),
            )?;
            self.compile_finished(compile);
            self.pipelines_created += 1;
            self.executor = Some((capacities.clone(), budget, executor));
        }
        Ok(&mut self.executor.as_mut().expect("just created").2)
    }

    /// Tells the observer that the executor's pipeline is being created (the
    /// driver compiles the megakernel); returns what
    /// [`Self::compile_finished`] reports, `None` without an observer.
    fn compile_started(&self) -> Option<(AdapterSummary, Instant)> {
        let progress = &self.options.progress;
        progress.is_observed().then(|| {
            let adapter = AdapterSummary::of(&self.gpu.device.adapter_info());
            progress.send(|| ProgressEvent::CompileStarted {
                adapter: adapter.clone(),
            });
            (adapter, Instant::now())
        })
    }

    /// Tells the observer that the pipeline [`Self::compile_started`]
    /// announced is created.
    fn compile_finished(&self, compile: Option<(AdapterSummary, Instant)>) {
        if let Some((adapter, start)) = compile {
            self.options
                .progress
                .send(|| ProgressEvent::CompileFinished {
                    adapter,
                    elapsed: start.elapsed(),
                });
        }
    }

    /// Renders a frame with `render` between the observer's
    /// [`ProgressEvent::FrameStarted`] and, when it succeeds,
    /// [`ProgressEvent::FrameFinished`].
    pub(super) fn observed_frame(
        &mut self,
        scene: &PreparedScene,
        render: impl FnOnce(&mut Self, &PreparedScene) -> Result<GpuRendered, RenderError>,
    ) -> Result<GpuRendered, RenderError> {
        let start = Instant::now();
        self.options.progress.send(|| ProgressEvent::FrameStarted {
            width: scene.camera.width,
            height: scene.camera.height,
            spp: scene.spp,
        });
        let rendered = render(self, scene);
        // An error no scope caught (wgpu's handler would have panicked) is
        // the frame's error: what the frame returned may rest on it.
        if let Some(error) = self.gpu.uncaptured.take() {
            return Err(RenderError::Run(RunError::Gpu(error)));
        }
        let rendered = rendered?;
        self.options.progress.send(|| ProgressEvent::FrameFinished {
            elapsed: start.elapsed(),
        });
        Ok(rendered)
    }

    /// Runs the megakernel over every batch of `batch` input patches of
    /// `scene` into the cleared frame ([`Self::run_batches`]): once, or, with
    /// the 32-bit depth test ([`DepthTest::TwoPass32`]), twice, first the
    /// depth pass over every batch, then the colour pass (not for a frame of
    /// the depth output, which reads no colour). The colour pass counts what
    /// the depth pass counted again, so its statistics start from zero and
    /// are the frame's; its times and retries add to the depth pass's.
    pub(super) fn run_passes(
        &mut self,
        scene: &PreparedScene,
        capacities: &Capacities,
        budget: Option<u32>,
        batch: u32,
    ) -> (Result<GpuCounters, RenderError>, TileRuns) {
        if self.compiled_key.variant.depth_test != DepthTest::TwoPass32 {
            return self.run_batches(scene, capacities, budget, batch, None);
        }
        let (depths, runs) = self.run_batches(scene, capacities, budget, batch, Some(DEPTH_PASS));
        if depths.is_err() || scene.aov == crate::Aov::Z {
            return (depths, runs);
        }
        self.frame
            .as_ref()
            .expect("prepared above")
            .0
            .reset_stats(&self.gpu.queue);
        let (colours, colour_runs) =
            self.run_batches(scene, capacities, budget, batch, Some(COLOUR_PASS));
        match colours {
            // The error names the colour pass's batch.
            Err(error) => (Err(error), colour_runs),
            Ok(counters) => (Ok(counters), runs.then(colour_runs)),
        }
    }

    /// Runs the megakernel once per batch of `batch` input patches of
    /// `scene` into the cleared frame (in `pass` of a
    /// [`DepthTest::TwoPass32`] frame), each batch through
    /// [`Executor::run_with_retry`]: an overflow grows the queues, a loop
    /// limit (the scheduler's waits, or the rasterization loops counted in
    /// `STAT_LOOPS_CUT`) lowers the iteration budget, and before each retry
    /// the statistics are restored to what they were before the batch (the
    /// framebuffer's depth test makes a repeated batch harmless there).
    /// Stops at the first batch that fails; otherwise returns the counters
    /// of all batches together.
    pub(super) fn run_batches(
        &mut self,
        scene: &PreparedScene,
        capacities: &Capacities,
        budget: Option<u32>,
        batch: u32,
        pass: Option<u32>,
    ) -> (Result<GpuCounters, RenderError>, TileRuns) {
        let mut runs = TileRuns {
            gpu_time: Some(Duration::ZERO),
            ..TileRuns::default()
        };
        let ranges = batch_ranges(scene.patches.len(), batch);
        let count = ranges.len();
        let bound = self
            .compiled()
            .procedure_id::<InputPatch>(BOUND)
            .expect("the Reyes graph's Bound consumes InputPatches");
        let (strategy, timeout) = (self.options.strategy, self.options.timeout);
        for range in ranges {
            // Seeds name their stored patches: every run reads its
            // patches from the same scene buffers.
            let seeds: Vec<InputPatch> = scene.patches[range.clone()]
                .iter()
                .map(InputPatch::of)
                .collect();
            let run_start = Instant::now();
            // The executor borrows `self` mutably; take the buffers out meanwhile.
            let frame = self.frame.take().expect("prepared above");
            let buffers = &frame.0;
            buffers.save_stats(&self.gpu.device, &self.gpu.queue);
            let retry = Retry::new(RENDER_ATTEMPTS, |device, queue| {
                buffers.restore_stats(device, queue);
            })
            .check_loops(|device, queue| {
                // Earlier batches ended without cuts and a retry restores
                // the statistics, so the count is this batch's.
                let bytes = read_buffer(device, queue, &buffers.stats, timeout)?;
                Ok(GpuCounters::from_bytes(&bytes).loops_cut())
            });
            let result = self.executor(capacities, budget).and_then(|executor| {
                if let Some(pass) = pass {
                    executor.write(PASS_RESOURCE, &[pass])?;
                }
                executor
                    .run_with_retry(
                        strategy,
                        &Seeds::new().add(&bound, &seeds),
                        &buffers.bindings(),
                        retry,
                    )
                    .map_err(RenderError::Run)
            });
            self.frame = Some(frame);
            runs.wall += run_start.elapsed();
            runs.batches += 1;
            match result {
                Ok(report) => {
                    if report.attempts > 1 {
                        log::warn!(
                            "input patches {}..{} took {} attempts ({} after overflows, {} after llvmpipe cut loops); the grown queues and iteration budget {} stay for later runs",
                            range.start,
                            range.end,
                            report.attempts,
                            report.retries.overflow + report.retries.seeds,
                            report.retries.loop_limit,
                            self.executor
                                .as_ref()
                                .map_or(0, |(_, _, e)| e.iteration_budget())
                        );
                    }
                    runs.gpu_time = runs.gpu_time.zip(report.gpu_time).map(|(a, b)| a + b);
                    runs.add_retries(&report);
                    runs.report = Some(report);
                }
                Err(e) => return (Err(e), runs),
            }
            if count > 1 {
                self.options.progress.send(|| ProgressEvent::BatchFinished {
                    batch: runs.batches,
                    batches: u32::try_from(count).unwrap_or(u32::MAX),
                });
                log::info!(
                    "batch {}/{count} of input patches ({}..{}) done",
                    runs.batches,
                    range.start,
                    range.end
                );
            }
        }
        (self.read_counters(), runs)
    }
}
