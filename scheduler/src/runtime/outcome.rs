//! From the control words read back after a submission to the run's report,
//! and from the report to the run's outcome: every problem it shows, named
//! in one order (overflow first, as the likeliest cause of the rest).

use std::time::Duration;

use crate::plan::{Plan, checked, control, fan_out};
use crate::{BoundsViolation, FanOutViolation, ProcedureStats, RunError, RunReport, Strategy};

/// What a report is built from besides the control words.
pub(crate) struct RunFacts<'a> {
    pub plan: &'a Plan,
    pub strategy: Strategy,
    pub capacities: &'a [u32],
    pub seeded: &'a [u64],
    pub workgroups: u32,
    pub submissions: u32,
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
        workgroups: facts.workgroups,
        dispatches: facts.submissions,
        rounds: match facts.strategy {
            Strategy::Megakernel => 0,
            Strategy::Rounds { .. } => counters[control::ROUNDS as usize],
        },
        attempts: 1,
        retries: crate::RetryCauses::default(),
        wall_time: facts.wall_time,
        gpu_time: facts.gpu_time,
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
/// out-of-bounds accesses, loops the driver cut (`loops_cut`), items over a
/// fan-out (checked mode), and batches over their staging room.
pub(crate) fn problems(report: &RunReport, loops_cut: u32) -> Vec<String> {
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
    problems.extend(report.bounds_violations.iter().map(|v| {
        format!(
            "`{}` indexed `{}` out of bounds {} time(s), first at {} (bound {})",
            v.procedure, v.resource, v.count, v.first_index, v.bound
        )
    }));
    if loops_cut > 0 {
        let why = if report.procedures.iter().all(|q| q.dropped == 0) {
            ""
        } else {
            ", likely because the full queue kept workgroups waiting"
        };
        problems.push(format!(
            "the driver's loop limit cut {loops_cut} loop(s) short{why}"
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
    problems
}

/// The outcome of a finished run: the report, or the first of its problems
/// as an error that names the others. `advice` says what to do about a
/// loop limit under the strategy that ran.
pub(crate) fn judge(
    report: RunReport,
    loops_cut: u32,
    advice: impl FnOnce() -> String,
) -> Result<RunReport, RunError> {
    let mut problems = problems(&report, loops_cut);
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
    if loops_cut > 0 {
        return Err(RunError::LoopLimit {
            waits: loops_cut,
            body_loops: 0,
            advice: advice(),
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
    Ok(report)
}

/// A run that never finished (`error`, a timeout or a device failure from a
/// read-back), given the control words of the last submission that could be
/// read (if any): the error, with that partial report and its problems.
pub(crate) fn interrupted(
    error: RunError,
    limit: Duration,
    partial: Option<(RunReport, u32)>,
) -> RunError {
    let (report, also) = match partial {
        Some((report, loops_cut)) => {
            let also = problems(&report, loops_cut);
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
