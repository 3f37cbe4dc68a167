//! From the control words read back after a submission to the run's report,
//! and from the report to the run's outcome: every problem it shows, named
//! in one order (overflow first, as the likeliest cause of the rest).

use std::time::Duration;

use crate::plan::{Plan, checked, control, fan_out, joins};
use crate::{
    BoundsViolation, FanOutViolation, JoinPoolStats, JoinStats, ProcedureStats, RunError,
    RunReport, Strategy,
};

/// What a report is built from besides the control words.
pub(crate) struct RunFacts<'a> {
    pub plan: &'a Plan,
    pub strategy: Strategy,
    pub capacities: &'a [u32],
    pub seeded: &'a [u64],
    pub workgroups: u32,
    pub submissions: u32,
    pub dispatches: u32,
    pub wall_time: Duration,
    pub gpu_time: Option<Duration>,
}

/// The report of a run from its control words (`counters`).
pub(crate) fn report(facts: &RunFacts<'_>, counters: &[u32]) -> RunReport {
    RunReport {
        strategy: facts.strategy,
        procedures: facts
            .plan
            .queues
            .iter()
            .enumerate()
            .map(|(q, queue)| {
                let word = |field| u64::from(counters[control::index(q, field)]);
                let dropped = word(control::DROPPED);
                ProcedureStats {
                    name: queue.name.clone(),
                    capacity: facts.capacities[q],
                    seeded: facts.seeded[q],
                    executed: word(control::EXECUTED),
                    enqueued: word(control::ENQUEUED),
                    high_water: word(control::HIGH_WATER),
                    dropped,
                    needed_at_least: word(control::NEEDED),
                    grown_for: 0,
                    // Every refused reservation adds its size to `dropped` as
                    // it is refused, so the high-water mark plus them is what
                    // the queue would have held had it accepted them all.
                    needed: if dropped > 0 {
                        word(control::HIGH_WATER) + dropped
                    } else {
                        0
                    },
                    fan_out_overflow: word(control::FANOUT_OVERFLOW),
                }
            })
            .collect(),
        bounds_violations: bounds_violations(facts.plan, counters),
        fan_out_violations: fan_out_violations(facts.plan, counters),
        joins: join_stats(facts.plan, counters),
        join_pool: join_pool(facts.plan, counters),
        workgroups: facts.workgroups,
        submissions: facts.submissions,
        dispatches: facts.dispatches,
        rounds: match facts.strategy {
            Strategy::Rounds { .. } => counters[control::ROUNDS as usize],
            Strategy::Megakernel | Strategy::Auto => 0,
        },
        attempts: 1,
        retries: crate::RetryCauses::default(),
        wall_time: facts.wall_time,
        gpu_time: facts.gpu_time,
        trace: None,
    }
}

/// The joins opened and fired per continuation, from the joins' words.
fn join_stats(plan: &Plan, counters: &[u32]) -> Vec<JoinStats> {
    let first = joins::first_word(plan) + joins::KINDS;
    plan.joins
        .iter()
        .enumerate()
        .map(|(k, join)| {
            let word = (first + joins::KIND_WORDS * k as u32) as usize;
            let opened = u64::from(counters[word + joins::OPENED as usize]);
            let fired = u64::from(counters[word + joins::FIRED as usize]);
            JoinStats {
                continuation: plan.queues[join.continuation].name.clone(),
                opened,
                fired,
                outstanding: opened.saturating_sub(fired),
            }
        })
        .collect()
}

/// The join pool's capacity and the records asked for (zero without joins).
fn join_pool(plan: &Plan, counters: &[u32]) -> JoinPoolStats {
    if plan.joins.is_empty() {
        return JoinPoolStats::default();
    }
    let first = joins::first_word(plan) as usize;
    JoinPoolStats {
        capacity: counters[first + joins::CAPACITY as usize],
        requested: u64::from(counters[first + joins::NEXT as usize]),
    }
}

/// Checked mode's violations, per procedure and guarded resource, from the
/// control words after the counters.
fn bounds_violations(plan: &Plan, counters: &[u32]) -> Vec<BoundsViolation> {
    let guarded = plan.guarded_resources();
    let mut violations = Vec::new();
    for (q, queue) in plan.queues.iter().enumerate() {
        for (r, resource) in guarded.iter().enumerate() {
            let word = checked::check_word(plan, q, r) as usize;
            let count = counters[word + checked::COUNT as usize];
            if count > 0 {
                violations.push(BoundsViolation {
                    procedure: queue.name.clone(),
                    resource: (*resource).to_owned(),
                    count: u64::from(count),
                    first_index: counters[word + checked::FIRST_INDEX as usize],
                    bound: counters[word + checked::BOUND as usize],
                });
            }
        }
    }
    violations
}

/// Loops the driver cut in a run: the scheduler's own, and body calls that
/// spent the driver's loop budget (control words `LOOPS_CUT` and
/// `BODY_LOOPS_CUT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Cuts {
    pub waits: u32,
    pub body_loops: u32,
}

impl Cuts {
    /// The cuts the control words `counters` hold.
    pub(crate) fn of(counters: &[u32]) -> Self {
        Self {
            waits: counters[control::LOOPS_CUT as usize],
            body_loops: counters[control::BODY_LOOPS_CUT as usize],
        }
    }

    /// Whether any loop was cut.
    pub(crate) fn any(self) -> bool {
        self.waits > 0 || self.body_loops > 0
    }
}

/// Checked mode's items over a fan-out, one per procedure, from its words
/// after the bounds checks'.
fn fan_out_violations(plan: &Plan, counters: &[u32]) -> Vec<FanOutViolation> {
    if !fan_out::checked(plan) {
        return Vec::new();
    }
    let mut violations = Vec::new();
    for (q, queue) in plan.queues.iter().enumerate() {
        let word = (fan_out::first_word(plan) + fan_out::WORDS * q as u32) as usize;
        let items = counters[word + fan_out::ITEMS as usize];
        if items == 0 {
            continue;
        }
        let target = counters[word + fan_out::TARGET as usize] as usize;
        violations.push(FanOutViolation {
            procedure: queue.name.clone(),
            target: plan
                .queues
                .get(target)
                .map_or_else(String::new, |t| t.name.clone()),
            item: counters[word + fan_out::ITEM as usize],
            count: counters[word + fan_out::COUNT as usize],
            declared: queue
                .targets
                .iter()
                .find(|&&(t, _)| t == target)
                .map_or(0, |&(_, f)| f),
            items: u64::from(items),
        });
    }
    violations
}

/// Every problem `report` shows, in words: overflows first, then
/// out-of-bounds accesses, loops the driver cut (`cuts`: the bodies' named
/// first, as the cause of the scheduler's that follow), and fan-out
/// excesses.
pub(crate) fn problems(report: &RunReport, cuts: Cuts) -> Vec<String> {
    let mut problems: Vec<String> = report
        .procedures
        .iter()
        .filter(|q| q.dropped > 0)
        .map(|q| {
            format!(
                "queue `{}` (capacity {}) dropped {} items",
                q.name, q.capacity, q.dropped
            )
        })
        .collect();
    if report.join_pool.requested > u64::from(report.join_pool.capacity) {
        problems.push(format!(
            "the join pool (capacity {}) was asked for {} records",
            report.join_pool.capacity, report.join_pool.requested
        ));
    }
    problems.extend(report.bounds_violations.iter().map(|v| {
        format!(
            "`{}` indexed `{}` out of bounds {} time(s), first at {} (bound {})",
            v.procedure, v.resource, v.count, v.first_index, v.bound
        )
    }));
    if cuts.body_loops > 0 {
        problems.push(format!(
            "the driver's loop limit cut the bodies' own loops ({} cut)",
            cuts.body_loops
        ));
    } else if cuts.waits > 0 {
        let why = if report.procedures.iter().all(|q| q.dropped == 0) {
            ""
        } else {
            ", likely because the full queue kept workgroups waiting"
        };
        problems.push(format!(
            "the driver's loop limit cut {} loop(s) short{why}",
            cuts.waits
        ));
    }
    problems.extend(report.fan_out_violations.iter().map(|v| {
        format!(
            "{} item(s) of `{}` went over a fan-out, first item {} with {} enqueues into `{}` (fan-out {})",
            v.items, v.procedure, v.item, v.count, v.target, v.declared
        )
    }));
    problems.extend(
        report
            .procedures
            .iter()
            .filter(|q| q.fan_out_overflow > 0)
            .map(|q| {
                format!(
                    "{} enqueues into `{}` exceeded the declared fan-out",
                    q.fan_out_overflow, q.name
                )
            }),
    );
    problems.extend(report.joins.iter().filter(|j| j.outstanding > 0).map(|j| {
        format!(
            "{} join(s) of `{}` never fired",
            j.outstanding, j.continuation
        )
    }));
    problems
}

/// The outcome of a finished run: the report, or the first of its problems
/// as an error that names the others. `advice` says what to do about a
/// loop limit under the strategy that ran, given the body loops cut.
pub(crate) fn judge(
    report: RunReport,
    cuts: Cuts,
    advice: impl FnOnce(u32) -> String,
) -> Result<RunReport, RunError> {
    let mut problems = problems(&report, cuts);
    if let Some(p) = report.procedures.iter().find(|p| p.dropped > 0) {
        problems.remove(0);
        return Err(RunError::QueueOverflow {
            procedure: p.name.clone(),
            capacity: p.capacity,
            dropped: p.dropped,
            needed_at_least: p.needed_at_least.max(u64::from(p.capacity) + 1),
            needed: p.needed,
            also: problems,
            report: Box::new(report),
        });
    }
    if report.join_pool.requested > u64::from(report.join_pool.capacity) {
        problems.remove(0);
        return Err(RunError::JoinPoolOverflow {
            capacity: report.join_pool.capacity,
            needed: report.join_pool.requested,
            also: problems,
            report: Box::new(report),
        });
    }
    if let Some(v) = report.bounds_violations.first() {
        problems.remove(0);
        return Err(RunError::OutOfBounds {
            procedure: v.procedure.clone(),
            resource: v.resource.clone(),
            index: v.first_index,
            bound: v.bound,
            count: v.count,
            also: problems,
            report: Box::new(report),
        });
    }
    if cuts.any() {
        return Err(RunError::LoopLimit {
            waits: cuts.waits,
            body_loops: cuts.body_loops,
            advice: advice(cuts.body_loops),
            report: Box::new(report),
        });
    }
    if let Some(v) = report.fan_out_violations.first() {
        problems.remove(0);
        return Err(RunError::ItemFanOutExceeded {
            procedure: v.procedure.clone(),
            target: v.target.clone(),
            item: v.item,
            count: v.count,
            declared: v.declared,
            items: v.items,
            also: problems,
            report: Box::new(report),
        });
    }
    if let Some(p) = report.procedures.iter().find(|p| p.fan_out_overflow > 0) {
        return Err(RunError::FanOutExceeded {
            procedure: p.name.clone(),
            excess: p.fan_out_overflow,
            report: Box::new(report),
        });
    }
    if let Some(j) = report.joins.iter().find(|j| j.outstanding > 0) {
        let first = problems
            .iter()
            .position(|p| p.ends_with("never fired"))
            .unwrap_or(0);
        problems.remove(first);
        return Err(RunError::JoinsUnfinished {
            continuation: j.continuation.clone(),
            joins: j.outstanding,
            also: problems,
            report: Box::new(report),
        });
    }
    Ok(report)
}

/// A run that never finished (`error`, a timeout or a device failure from a
/// read-back), given the control words of the last submission that could be
/// read (if any): the error, with that partial report and its problems.
pub(crate) fn interrupted(
    error: RunError,
    limit: Duration,
    partial: Option<(RunReport, Cuts)>,
) -> RunError {
    let (report, also) = match partial {
        Some((report, cuts)) => {
            let also = problems(&report, cuts);
            (Some(Box::new(report)), also)
        }
        None => (None, Vec::new()),
    };
    match error {
        RunError::Timeout { .. } => RunError::Timeout {
            limit,
            report,
            also,
        },
        RunError::Gpu(message) => RunError::DeviceFailed {
            message,
            report,
            also,
        },
        other => other,
    }
}

/// The compute dispatches one submission encodes under `strategy` (a
/// resolved one): the megakernel's one, or per round one indirect dispatch
/// per procedure and a prepare, plus the prepare that starts a run's first
/// batch of rounds (`Executor::encode_rounds`).
pub(crate) fn dispatches(plan: &Plan, strategy: Strategy, first_submission: bool) -> u32 {
    match strategy {
        Strategy::Rounds { rounds_per_batch } => {
            u32::from(first_submission) + rounds_per_batch.max(1) * (plan.queues.len() as u32 + 1)
        }
        Strategy::Megakernel | Strategy::Auto => 1,
    }
}

/// Submissions in a row that executed no item, while work was outstanding,
/// after which a run fails with [`RunError::NoProgress`]. One such
/// submission cannot happen on a driver that runs the protocol as argued
/// (docs/scheduler.md, "Progress"); two leave room for a claim that lost
/// every race.
pub(crate) const STALLED_SUBMISSIONS: u32 = 2;

/// Watches a run's submissions for progress: items executed between two
/// read-backs of the control words.
#[derive(Debug, Default)]
pub(crate) struct ProgressWatch {
    executed: u64,
    stalled: u32,
}

impl ProgressWatch {
    /// After a submission that left work outstanding, with its control
    /// words `counters`: `Some(submissions)` once [`STALLED_SUBMISSIONS`]
    /// in a row executed nothing.
    pub(crate) fn after(&mut self, plan: &Plan, counters: &[u32]) -> Option<u32> {
        let executed: u64 = (0..plan.queues.len())
            .map(|q| u64::from(counters[control::index(q, control::EXECUTED)]))
            .sum();
        if executed == self.executed {
            self.stalled += 1;
        } else {
            self.stalled = 0;
        }
        self.executed = executed;
        (self.stalled >= STALLED_SUBMISSIONS).then_some(self.stalled)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{CompileOptions, Graph, Procedure};

    #[crate::item]
    struct Node {
        id: u32,
    }

    #[test]
    fn submissions_that_execute_nothing_in_a_row_are_no_progress() {
        let mut graph = Graph::new("progress");
        graph.procedure(Procedure::of::<Node>("Run").initial(true).body(""));
        let plan = graph.compile(&CompileOptions::default()).unwrap().plan;
        let mut counters = vec![0u32; control::words(1) as usize];
        let executed = control::index(0, control::EXECUTED);
        let mut watch = ProgressWatch::default();
        counters[executed] = 5;
        assert_eq!(watch.after(&plan, &counters), None);
        // One submission without progress is tolerated, and progress resets it.
        assert_eq!(watch.after(&plan, &counters), None);
        counters[executed] = 6;
        assert_eq!(watch.after(&plan, &counters), None);
        assert_eq!(watch.after(&plan, &counters), None);
        assert_eq!(watch.after(&plan, &counters), Some(STALLED_SUBMISSIONS));
    }

    #[test]
    fn cut_body_loops_are_named_before_the_waits_they_cut() {
        let report = RunReport::default();
        let cuts = Cuts {
            waits: 368,
            body_loops: 3,
        };
        let error = judge(report, cuts, |body| format!("advice for {body}")).unwrap_err();
        let RunError::LoopLimit {
            waits,
            body_loops,
            advice,
            ..
        } = &error
        else {
            panic!("expected a loop limit, got {error:?}");
        };
        assert_eq!(
            (*waits, *body_loops, advice.as_str()),
            (368, 3, "advice for 3")
        );
        assert!(
            error
                .to_string()
                .starts_with("loops were cut short: the bodies' own loops (3 cut)"),
            "{error}"
        );
        assert_eq!(
            problems(&RunReport::default(), cuts),
            ["the driver's loop limit cut the bodies' own loops (3 cut)"]
        );
    }
}
