//! Opt-in automatic retry of a run: after an overflow or over-seeding the
//! queues grow to the measured need, after a loop limit the iteration budget
//! shrinks; and the advice a loop limit carries.

use crate::runtime::executor::{Binding, Executor};
use crate::runtime::growth::{capacities_for_seeds, grown_capacities};
use crate::runtime::state::{QueueState, Tuning};
use crate::{Quirks, RunError, RunReport, Seeds, Strategy};

/// Restores the user's resources before a retry.
pub type ResetFn<'a> = Box<dyn FnMut(&wgpu::Device, &wgpu::Queue) + 'a>;

/// Opt-in automatic retry after a queue overflow, too many seeds, or a loop
/// the driver cut short ([`RunError::LoopLimit`], llvmpipe).
///
/// - After an overflow, each overflowing queue grows in one step to the
///   need the run measured ([`ProcedureStats::needed`](crate::ProcedureStats::needed):
///   its high-water mark plus every refused item), plus room for an estimate
///   of the children the refused items would have enqueued, as a power of
///   two. A measured need the device cannot hold fails with
///   [`RunError::QueueExceedsDevice`].
/// - After [`RunError::TooManySeeds`], the seeded queue grows to hold the
///   seeds (or fails the same way).
/// - After a loop limit under the megakernel, the iteration budget halves
///   (down to 1), so workgroups leave sooner; this changes the dispatches,
///   never the results. At a budget of 1, and under Rounds, the same
///   configuration runs again.
///
/// Each retry reallocates the scheduler's buffers, calls `reset` so the
/// user can restore their own resources (clear a framebuffer, zero
/// counters), and runs again from the seeds. A run that succeeds after
/// retries therefore gives the same results as one configured right from
/// the start. The grown capacities and the lowered budget stay for later
/// runs.
pub struct Retry<'a> {
    /// Attempts in all, the first included (at least 1).
    pub max_attempts: u32,
    /// Restores the user's resources before each retry.
    pub reset: ResetFn<'a>,
}

impl<'a> Retry<'a> {
    /// Up to `max_attempts` attempts, with `reset` called before each retry.
    pub fn new(max_attempts: u32, reset: impl FnMut(&wgpu::Device, &wgpu::Queue) + 'a) -> Self {
        Self {
            max_attempts,
            reset: Box::new(reset),
        }
    }

    /// Up to `max_attempts` attempts, for graphs whose resources need no reset.
    pub fn without_reset(max_attempts: u32) -> Self {
        Self::new(max_attempts, |_, _| {})
    }
}

impl std::fmt::Debug for Retry<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Retry")
            .field("max_attempts", &self.max_attempts)
            .finish_non_exhaustive()
    }
}

impl Executor {
    /// Runs like [`run_with`](Self::run_with), but on a queue overflow grows
    /// the overflowing queues and runs again from a clean state (see
    /// [`Retry`]). The report counts the attempts. Fails with the last
    /// overflow once `retry.max_attempts` are spent, with
    /// [`RunError::QueueExceedsDevice`] when the measured need of a queue
    /// does not fit the device, and at once on any other error.
    pub fn run_with_retry(
        &mut self,
        strategy: Strategy,
        seeds: &Seeds,
        bindings: &[Binding<'_>],
        mut retry: Retry<'_>,
    ) -> Result<RunReport, RunError> {
        let resources = self.resource_bind_group(bindings)?;
        let mut attempt = 1;
        loop {
            match self.attempt(strategy, seeds, resources.as_ref()) {
                Ok(mut report) => {
                    report.attempts = attempt;
                    return Ok(report);
                }
                Err(RunError::QueueOverflow { report, .. }) if attempt < retry.max_attempts => {
                    let capacities =
                        grown_capacities(&self.compiled.plan, &self.device.limits(), &report)?;
                    log::info!(
                        "attempt {attempt} overflowed; retrying with capacities {capacities:?}"
                    );
                    self.rebuild_state(capacities, self.tuning)?;
                    (retry.reset)(&self.device, &self.queue);
                    attempt += 1;
                }
                Err(RunError::TooManySeeds {
                    procedure, seeds, ..
                }) if attempt < retry.max_attempts => {
                    // Nothing ran, so the user's resources need no reset.
                    let capacities = capacities_for_seeds(
                        &self.compiled.plan,
                        &self.device.limits(),
                        &self.state.capacities,
                        &procedure,
                        seeds,
                    )?;
                    log::info!(
                        "attempt {attempt}: {seeds} seeds for `{procedure}`; retrying with capacities {capacities:?}"
                    );
                    self.rebuild_state(capacities, self.tuning)?;
                    attempt += 1;
                }
                Err(RunError::LoopLimit { waits, .. }) if attempt < retry.max_attempts => {
                    // The driver cut a loop (llvmpipe): the megakernel's
                    // workgroups leave sooner with a smaller iteration budget,
                    // which changes the dispatches, never the results. At a
                    // budget of 1 (and under Rounds) the same configuration
                    // runs again: a cut under CPU contention may not recur.
                    let mut tuning = self.tuning;
                    if strategy == Strategy::Megakernel && tuning.iteration_budget > 1 {
                        tuning.iteration_budget = if tuning.iteration_budget == u32::MAX {
                            Quirks::of_device(&self.device)
                                .default_iteration_budget(self.compiled.plan.chunks_per_batch)
                                .unwrap_or(64)
                        } else {
                            tuning.iteration_budget / 2
                        };
                    }
                    log::info!(
                        "attempt {attempt}: {waits} loop(s) cut by the driver; retrying with an iteration budget of {}",
                        tuning.iteration_budget
                    );
                    self.rebuild_state(self.state.capacities.clone(), tuning)?;
                    (retry.reset)(&self.device, &self.queue);
                    attempt += 1;
                }
                Err(error) => return Err(error),
            }
        }
    }

    /// Reallocates the queues with `capacities` and `tuning`, which later
    /// runs keep.
    pub(super) fn rebuild_state(
        &mut self,
        capacities: Vec<u32>,
        tuning: Tuning,
    ) -> Result<(), RunError> {
        self.state = QueueState::new(
            &self.device,
            &self.queue,
            &self.compiled,
            &self.layouts,
            capacities,
            tuning,
        )?;
        self.tuning = tuning;
        Ok(())
    }

    /// What to change after a loop limit, for the strategy and configuration
    /// that were used.
    pub(super) fn loop_limit_advice(&self, strategy: Strategy) -> String {
        let chunks = self.compiled.plan.chunks_per_batch;
        let budget = self.tuning.iteration_budget;
        let shorten = format!(
            "the bodies' own loops are too long for the driver: shorten them, or compile with fewer chunks per batch (now {chunks})"
        );
        match strategy {
            Strategy::Rounds { .. } => {
                format!("Under Rounds each workgroup runs one batch per dispatch, so {shorten}.")
            }
            Strategy::Megakernel if budget == u32::MAX => {
                "The megakernel ran without an iteration budget: `Executor::run_with_retry` sets one, or set `ExecutorConfig::iteration_budget` (e.g. 64).".to_owned()
            }
            Strategy::Megakernel if budget > 1 => format!(
                "`Executor::run_with_retry` runs again with half the iteration budget (now {budget}); by hand, set `ExecutorConfig::iteration_budget` below {budget}."
            ),
            Strategy::Megakernel => format!(
                "Every workgroup already leaves after one batch (iteration budget 1), so {shorten}."
            ),
        }
    }
}
