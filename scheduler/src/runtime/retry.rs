//! Opt-in automatic retry of a run: after an overflow or over-seeding the
//! queues grow to the measured need, after a loop limit the iteration budget
//! shrinks; and the advice a loop limit carries.

use crate::runtime::executor::{Binding, Executor};
use crate::runtime::growth::{capacities_for_seeds, grown_capacities, measured_need};
use crate::runtime::reset::ResetContext;
use crate::runtime::state::{QueueState, Tuning};
use crate::{RetryCauses, RunError, RunReport, Seeds, Strategy};

/// Restores the user's resources before a retry, given the device, the queue
/// and the executor's own buffers ([`ResetContext`]).
pub type ResetFn<'a> = Box<dyn FnMut(&ResetContext<'_>) + 'a>;

/// Counts, after a run, the loops of the bodies that the driver cut short
/// (see [`Retry::check_loops`]).
pub type LoopCheckFn<'a> =
    Box<dyn FnMut(&wgpu::Device, &wgpu::Queue) -> Result<u32, RunError> + 'a>;

/// Opt-in automatic retry after a queue overflow, too many seeds, or a loop
/// the driver cut short ([`RunError::LoopLimit`], llvmpipe).
///
/// - After an overflow, each overflowing queue grows in one step to the
///   need the run measured ([`ProcedureStats::needed`](crate::ProcedureStats::needed):
///   its high-water mark plus every refused item), plus room for an estimate
///   of the children the refused items would have enqueued, as a power of
///   two. A measured need the device cannot hold fails with
///   [`RunError::QueueExceedsDevice`].
/// - After [`RunError::JoinPoolOverflow`], the join pool grows in one step
///   to the records the run asked for, as a power of two. The need is
///   complete when bodies enqueue their children whether or not their
///   join opened (the run explores everything and counts every request).
/// - After [`RunError::TooManySeeds`], the seeded queue grows to hold the
///   seeds (or fails the same way).
/// - After a loop limit under the megakernel, the iteration budget halves
///   (down to 1), so workgroups leave sooner; this changes the dispatches,
///   never the results. At a budget of 1, and under Rounds, the same
///   configuration runs again. A loop limit is the scheduler's own (its
///   queue waits were cut) or one the bodies' loops saw, which only the
///   bodies can count: with [`Retry::check_loops`] the caller reports those
///   after each run, and they are retried the same way.
///
/// Each retry reallocates the scheduler's buffers, calls `reset` so the
/// user can restore their own resources (clear a framebuffer, zero
/// counters; [`Retry::with_context`] hands it the executor's own buffers
/// too, through [`ResetContext::clear`]), and runs again from the seeds. A run that succeeds after
/// retries therefore gives the same results as one configured right from
/// the start. The grown capacities and the lowered budget stay for later
/// runs. The report counts the attempts and their causes
/// ([`RunReport::retries`]).
pub struct Retry<'a> {
    /// Attempts in all, the first included (at least 1).
    pub max_attempts: u32,
    /// Restores the user's resources before each retry.
    pub reset: ResetFn<'a>,
    /// Counts the bodies' loops the driver cut in the run just made (`None`:
    /// only the scheduler's own waits are checked).
    pub check_loops: Option<LoopCheckFn<'a>>,
}

impl<'a> Retry<'a> {
    /// Up to `max_attempts` attempts, with `reset` called before each retry.
    pub fn new(max_attempts: u32, mut reset: impl FnMut(&wgpu::Device, &wgpu::Queue) + 'a) -> Self {
        Self::with_context(max_attempts, move |context: &ResetContext<'_>| {
            reset(context.device(), context.queue());
        })
    }

    /// Up to `max_attempts` attempts, with `reset` called before each retry
    /// with a [`ResetContext`]: the device, the queue, and the executor's own
    /// buffers by resource name (`context.clear("counts")`).
    pub fn with_context(max_attempts: u32, reset: impl FnMut(&ResetContext<'_>) + 'a) -> Self {
        Self {
            max_attempts,
            reset: Box::new(reset),
            check_loops: None,
        }
    }

    /// Up to `max_attempts` attempts, for graphs whose resources need no reset.
    pub fn without_reset(max_attempts: u32) -> Self {
        Self::with_context(max_attempts, |_| {})
    }

    /// Reports cuts of the bodies' own loops: after each run that found
    /// nothing else wrong, `check` returns how many loops of the bodies the
    /// driver cut short (a body counts them itself, for example by testing
    /// after its loop whether the loop reached its end, into a counter
    /// resource that `check` reads back; llvmpipe cuts every loop of an
    /// invocation once they have run 65,535 iterations together). A nonzero
    /// count is a loop limit like the scheduler's own: the same halving of
    /// the iteration budget, the same `reset`, the same attempt count, and
    /// once the attempts are spent a [`RunError::LoopLimit`] whose
    /// `body_loops` holds the count. A read-back error of `check` ends the
    /// run with that error.
    pub fn check_loops(
        mut self,
        check: impl FnMut(&wgpu::Device, &wgpu::Queue) -> Result<u32, RunError> + 'a,
    ) -> Self {
        self.check_loops = Some(Box::new(check));
        self
    }
}

impl std::fmt::Debug for Retry<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Retry")
            .field("max_attempts", &self.max_attempts)
            .field("check_loops", &self.check_loops.is_some())
            .finish_non_exhaustive()
    }
}

impl Executor {
    /// Runs like [`run_with`](Self::run_with), but on a queue overflow, too
    /// many seeds or a loop limit (the scheduler's, or the bodies' reported
    /// by [`Retry::check_loops`]) adapts the queues or the iteration budget
    /// and runs again from a clean state (see [`Retry`]). The report counts
    /// the attempts and their causes. Fails with the last overflow or loop
    /// limit once `retry.max_attempts` are spent, with
    /// [`RunError::QueueExceedsDevice`] when the measured need of a queue
    /// does not fit the device, and at once on any other error.
    pub fn run_with_retry(
        &mut self,
        strategy: Strategy,
        seeds: &Seeds,
        bindings: &[Binding<'_>],
        mut retry: Retry<'_>,
    ) -> Result<RunReport, RunError> {
        let strategy = strategy.resolve(&self.quirks);
        let resources = self.resource_bind_group(bindings)?;
        let mut attempt = 1;
        let mut causes = RetryCauses::default();
        // Per queue, the largest need a retry grew it for.
        let mut grown_for = vec![0u64; self.state.capacities.len()];
        loop {
            let outcome = self.attempt(strategy, seeds, resources.as_ref());
            let outcome = self.with_body_loops(strategy, outcome, retry.check_loops.as_mut())?;
            match outcome {
                Ok(mut report) => {
                    report.attempts = attempt;
                    report.retries = causes;
                    for (stats, &need) in report.procedures.iter_mut().zip(&grown_for) {
                        stats.grown_for = need;
                    }
                    return Ok(report);
                }
                Err(RunError::QueueOverflow { report, .. }) if attempt < retry.max_attempts => {
                    let growth =
                        grown_capacities(&self.compiled.plan, &self.device.limits(), &report)?;
                    let capacities = growth.capacities;
                    log::info!(
                        "attempt {attempt} overflowed; retrying with capacities {capacities:?}"
                    );
                    for (q, stats) in report.procedures.iter().enumerate() {
                        if capacities[q] > self.state.capacities[q] {
                            grown_for[q] = grown_for[q].max(measured_need(stats));
                        }
                    }
                    self.rebuild_state(capacities, self.tuning)?;
                    (retry.reset)(&ResetContext::new(self));
                    causes.overflow += 1;
                    causes.overflow_held += u32::from(growth.held);
                    attempt += 1;
                }
                Err(RunError::JoinPoolOverflow { needed, .. }) if attempt < retry.max_attempts => {
                    let mut tuning = self.tuning;
                    tuning.join_pool = u32::try_from(needed)
                        .unwrap_or(u32::MAX)
                        .checked_next_power_of_two()
                        .unwrap_or(u32::MAX)
                        .max(tuning.join_pool);
                    log::info!(
                        "attempt {attempt}: {needed} join records asked for; retrying with a pool of {}",
                        tuning.join_pool
                    );
                    self.rebuild_state(self.state.capacities.clone(), tuning)?;
                    (retry.reset)(&ResetContext::new(self));
                    causes.join_pool += 1;
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
                    if let Some(q) = self.compiled.plan.queue_index(&procedure) {
                        grown_for[q] = grown_for[q].max(seeds);
                    }
                    self.rebuild_state(capacities, self.tuning)?;
                    causes.seeds += 1;
                    attempt += 1;
                }
                Err(RunError::LoopLimit {
                    waits, body_loops, ..
                }) if attempt < retry.max_attempts => {
                    let tuning = self.lowered_budget(strategy);
                    log::info!(
                        "attempt {attempt}: {waits} wait(s) and {body_loops} body loop(s) cut by the driver; retrying with an iteration budget of {}",
                        tuning.iteration_budget
                    );
                    self.rebuild_state(self.state.capacities.clone(), tuning)?;
                    (retry.reset)(&ResetContext::new(self));
                    causes.loop_limit += 1;
                    attempt += 1;
                }
                Err(RunError::LoopLimit {
                    waits,
                    body_loops,
                    advice,
                    mut report,
                }) => {
                    report.attempts = attempt;
                    report.retries = causes;
                    return Err(RunError::LoopLimit {
                        waits,
                        body_loops,
                        advice,
                        report,
                    });
                }
                Err(error) => return Err(error),
            }
        }
    }

    /// `outcome` with the bodies' loop cuts that `check` counts: a run that
    /// succeeded, or hit the scheduler's own loop limit, becomes a loop
    /// limit with `body_loops` when `check` counts any. Other failures are
    /// left as they are (an overflow is retried first, as
    /// [`run_with`](Self::run_with) reports it first). `Err` only when
    /// `check` failed.
    fn with_body_loops(
        &self,
        strategy: Strategy,
        outcome: Result<RunReport, RunError>,
        check: Option<&mut LoopCheckFn<'_>>,
    ) -> Result<Result<RunReport, RunError>, RunError> {
        let Some(check) = check else {
            return Ok(outcome);
        };
        let (waits, found, report) = match outcome {
            Ok(report) => (0, 0, Box::new(report)),
            Err(RunError::LoopLimit {
                waits,
                body_loops,
                report,
                ..
            }) => (waits, body_loops, report),
            other => return Ok(other),
        };
        let body_loops = found.saturating_add(check(&self.device, &self.queue)?);
        if waits == 0 && body_loops == 0 {
            return Ok(Ok(*report));
        }
        Ok(Err(RunError::LoopLimit {
            waits,
            body_loops,
            advice: self.loop_limit_advice(strategy, body_loops),
            report,
        }))
    }

    /// The tuning to retry with after a loop limit: the driver cut a loop
    /// (llvmpipe), and the megakernel's workgroups leave sooner with a
    /// smaller iteration budget, which changes the dispatches, never the
    /// results. Without a budget the driver's default is set. At a budget of
    /// 1 (and under Rounds) the same configuration runs again: a cut under
    /// CPU contention may not recur.
    fn lowered_budget(&self, strategy: Strategy) -> Tuning {
        let mut tuning = self.tuning;
        if strategy == Strategy::Megakernel && tuning.iteration_budget > 1 {
            tuning.iteration_budget = if tuning.iteration_budget == u32::MAX {
                self.quirks
                    .default_iteration_budget(self.compiled.plan.chunks_per_batch)
                    .unwrap_or(64)
            } else {
                tuning.iteration_budget / 2
            };
        }
        tuning
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
}
