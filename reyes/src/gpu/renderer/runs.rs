//! Running the megakernel: the executor's configuration and the runs of one
//! attempt at a tile, one per batch of input patches.

use std::time::{Duration, Instant};

use scheduler::{Capacities, DEFAULT_WORKGROUPS, Executor, ExecutorConfig, Seeds, Strategy};

use super::GpuRenderer;
use crate::gpu::batches::{Attempt, batch_ranges};
use crate::gpu::buffers::GpuCounters;
use crate::gpu::cpu_tuning::{CPU_ITERATION_BUDGET, cpu_workgroups, is_cpu};
use crate::gpu::graph::{BOUND, PatchItem};
use crate::gpu::render_error::RenderError;
use crate::prepare::PreparedScene;

impl GpuRenderer<'_> {
    /// The iteration budget of a first attempt (see
    /// [`GpuOptions::iteration_budget`](super::GpuOptions::iteration_budget)).
    pub(super) fn iteration_budget(&self) -> Option<u32> {
        self.options
            .iteration_budget
            .or_else(|| self.is_cpu().then_some(CPU_ITERATION_BUDGET))
    }

    /// Whether the adapter is a CPU (llvmpipe behind lavapipe).
    pub(super) fn is_cpu(&self) -> bool {
        is_cpu(self.gpu)
    }

    pub(super) fn config(
        &self,
        capacities: Capacities,
        iteration_budget: Option<u32>,
    ) -> ExecutorConfig {
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

    /// Runs the megakernel once per batch of `batch` input patches of
    /// `scene` into the cleared frame. Stops at the first failed run, or at
    /// the first run after which llvmpipe had cut rasterization loops (the
    /// frame is then rendered again anyway); otherwise returns the counters
    /// of all batches together.
    pub(super) fn run_batches(
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
        let bound = self
            .compiled()
            .procedure_id::<PatchItem>(BOUND)
            .expect("the Reyes graph's Bound consumes PatchItems");
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
                        &Seeds::new().add(&bound, &seeds),
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
}
