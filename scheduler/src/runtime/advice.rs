//! What a loop limit's error advises, for the strategy, the configuration and
//! the driver that ran: the one change that helps, and nothing that cannot.

use crate::runtime::executor::Executor;
use crate::{DEFAULT_WORKGROUPS, Strategy};

impl Executor {
    /// What to change after a loop limit under `strategy` (a resolved one);
    /// `body_loops` are the bodies' own loops found cut (by the check after
    /// each body call, or reported through
    /// [`Retry::check_loops`](crate::Retry::check_loops)).
    pub(super) fn loop_limit_advice(&self, strategy: Strategy, body_loops: u32) -> String {
        if !self.quirks.caps_loops() && body_loops == 0 {
            return format!(
                "This driver caps no loops, so a wait for free slots expired: the workgroups holding them made no progress. Persistent workgroups are not safe here ({}); run with `Strategy::Rounds`.",
                self.quirks.persistent_threads.platform
            );
        }
        let advice = self.budget_advice(strategy, body_loops > 0);
        if body_loops == 0 {
            return advice;
        }
        format!(
            "The bodies' own loops ran out the driver's per-invocation loop budget ({body_loops} cut); the scheduler's waits are not the cause. {advice}"
        )
    }

    /// What to change about the iteration budget, the workgroups, the chunks
    /// or the bodies.
    fn budget_advice(&self, strategy: Strategy, bodies: bool) -> String {
        let chunks = self.compiled.plan.chunks_per_batch;
        let budget = self.tuning.iteration_budget;
        let round_workgroups = self.tuning.round_workgroups;
        let shorten = if chunks > 1 {
            format!(
                "the bodies' own loops are too long for the driver: shorten them, or compile with fewer chunks per batch (now {chunks})"
            )
        } else {
            "the bodies' own loops are too long for the driver: shorten them".to_owned()
        };
        match strategy {
            Strategy::Rounds { .. } if round_workgroups < DEFAULT_WORKGROUPS => format!(
                "Under Rounds each workgroup strides over its share of a round's batches within one loop budget, and {round_workgroups} workgroup(s) per round dispatch take many batches each: raise `ExecutorConfig::round_workgroups` (default {DEFAULT_WORKGROUPS}){}.",
                if bodies {
                    "; the bodies' own loops are too long for the driver, so shorten them too"
                } else {
                    ""
                }
            ),
            Strategy::Rounds { .. } => format!(
                "Under Rounds each workgroup runs its share of a round's batches in one dispatch, so {shorten}."
            ),
            Strategy::Megakernel if budget == u32::MAX => {
                "The megakernel ran without an iteration budget: `Executor::run_with_retry` sets one, or set `ExecutorConfig::iteration_budget` (e.g. 64).".to_owned()
            }
            Strategy::Megakernel if budget > 1 => format!(
                "`Executor::run_with_retry` runs again with half the iteration budget (now {budget}); by hand, set `ExecutorConfig::iteration_budget` below {budget}."
            ),
            _ => format!(
                "Every workgroup already leaves after one batch (iteration budget 1), so {shorten}."
            ),
        }
    }
}
