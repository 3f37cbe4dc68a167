//! What a run reports: per-procedure counters and timings, as text or JSON.

use std::fmt;
use std::time::Duration;

use crate::ProcedureId;

/// Counters of one procedure's queue for one run.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ProcedureStats {
    /// Procedure name.
    pub name: String,
    /// Queue capacity in items.
    pub capacity: u32,
    /// Items seeded by the host.
    pub seeded: u64,
    /// Items executed.
    pub executed: u64,
    /// Items enqueued by procedures and accepted into the queue.
    pub enqueued: u64,
    /// Highest number of items the queue held at once (reserved, unclaimed).
    pub high_water: u64,
    /// Items that did not fit into the queue (overflow).
    pub dropped: u64,
    /// A lower bound on the capacity this run needed, if it overflowed: the
    /// largest fill one refused reservation asked for.
    pub needed_at_least: u64,
    /// The capacity that would have held every item this run put into the
    /// queue or had refused, if it overflowed (0 otherwise): the high-water
    /// mark plus every refused item. Refused items never ran, so the
    /// children they would have enqueued come on top of it in a run that
    /// accepts them (docs/scheduler.md, "When a run fails").
    #[serde(default)]
    pub needed: u64,
    /// The need a retry ([`Executor::run_with_retry`](crate::Executor::run_with_retry))
    /// grew this queue for: the largest `needed` (or, for a queue grown for
    /// its producers' refused items, high-water mark) of the attempts before
    /// this one; 0 if no retry grew it. The capacity is at most twice this.
    /// A megakernel's high-water mark varies from run to run, so it can be
    /// above this run's own.
    #[serde(default)]
    pub grown_for: u64,
    /// Enqueues beyond the staging room of the declared fan-out.
    pub fan_out_overflow: u64,
}

/// Out-of-bounds indices of one procedure into one resource, found in
/// checked mode ([`CompileOptions::checked`](crate::CompileOptions::checked)).
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct BoundsViolation {
    /// The procedure whose item (its body or the library code it called)
    /// made the access.
    pub procedure: String,
    /// The resource indexed.
    pub resource: String,
    /// Out-of-bounds indices counted (every thread's access counts).
    pub count: u64,
    /// The first offending index recorded.
    pub first_index: u32,
    /// The bound it was checked against: the bound buffer's length in
    /// elements.
    pub bound: u32,
}

/// An item whose enqueues into one target went over the connection's
/// fan-out, found in checked mode
/// ([`CompileOptions::checked`](crate::CompileOptions::checked)).
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct FanOutViolation {
    /// The procedure whose item enqueued.
    pub procedure: String,
    /// The queue it enqueued into.
    pub target: String,
    /// The first offending item recorded, as its ticket in `procedure`'s
    /// queue (seeds are tickets `0..` in the order given).
    pub item: u32,
    /// The enqueues that item made into `target`.
    pub count: u32,
    /// The connection's fan-out.
    pub declared: u32,
    /// The items of `procedure` that went over a fan-out.
    pub items: u64,
}

/// The joins of one continuation in one run ([`Graph::join`](crate::Graph::join)).
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct JoinStats {
    /// The continuation procedure.
    pub continuation: String,
    /// Joins opened (records granted by the pool).
    pub opened: u64,
    /// Joins fired: their last child finished and their record was staged
    /// for the continuation.
    pub fired: u64,
    /// Joins opened and never fired: `opened - fired`, nonzero only in a run
    /// that failed (a lost child, an overflow).
    pub outstanding: u64,
}

/// The pool of join records in one run (all zero without joins).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct JoinPoolStats {
    /// Records the pool held.
    pub capacity: u32,
    /// Records the run asked for: every `join_open` call, granted or not.
    /// Above `capacity`, the pool overflowed and this is the capacity that
    /// would have held them all (records are not reused within a run).
    pub requested: u64,
}

/// The retries of one [`Executor::run_with_retry`](crate::Executor::run_with_retry)
/// call, by cause (all 0 for a run without retries).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct RetryCauses {
    /// Retries after a queue overflow, with the queues grown.
    pub overflow: u32,
    /// Of the `overflow` retries, those that held a queue feeding itself at
    /// twice its measured need, below the estimate of what its refused
    /// items' children would need: the bound on memory (docs/scheduler.md,
    /// "Overflow and retry"). Such a retry can measure only about one more
    /// level of that queue, so a deep tree started from small queues takes
    /// one of them per level that outgrows twice the last.
    #[serde(default)]
    pub overflow_held: u32,
    /// Retries after too many seeds, with the seeded queue grown.
    pub seeds: u32,
    /// Retries after a join pool overflow, with the pool grown.
    #[serde(default)]
    pub join_pool: u32,
    /// Retries after a loop limit (the scheduler's waits or, reported by
    /// [`Retry::check_loops`](crate::Retry::check_loops), the bodies' own
    /// loops), with a lower iteration budget.
    pub loop_limit: u32,
}

/// The report of one run.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunReport {
    /// The strategy that ran ([`Strategy::Auto`](crate::Strategy::Auto)
    /// resolved to the one it chose).
    pub strategy: crate::Strategy,
    /// One entry per procedure, in declaration order.
    pub procedures: Vec<ProcedureStats>,
    /// Out-of-bounds accesses found in checked mode (always empty without).
    #[serde(default)]
    pub bounds_violations: Vec<BoundsViolation>,
    /// Items over a fan-out found in checked mode, at most one per procedure
    /// (always empty without).
    #[serde(default)]
    pub fan_out_violations: Vec<FanOutViolation>,
    /// The joins of each continuation, in the order of their first
    /// [`Graph::join`](crate::Graph::join) (empty without joins).
    #[serde(default)]
    pub joins: Vec<JoinStats>,
    /// The pool of join records.
    #[serde(default)]
    pub join_pool: JoinPoolStats,
    /// Workgroups launched per dispatch.
    pub workgroups: u32,
    /// Command submissions it took, each followed by a read-back of the
    /// counters: one per megakernel dispatch, one per batch of rounds.
    #[serde(default)]
    pub submissions: u32,
    /// Compute dispatches encoded: the megakernel's (more than one only with
    /// an iteration budget, a spin limit or a retry), or under Rounds every
    /// indirect dispatch of a procedure (one per procedure per round, empty
    /// ones included) and every prepare dispatch.
    pub dispatches: u32,
    /// Rounds that found work (Rounds strategy; 0 for the megakernel).
    pub rounds: u32,
    /// Attempts it took (more than one only after retries of
    /// [`Executor::run_with_retry`](crate::Executor::run_with_retry)).
    pub attempts: u32,
    /// Why the attempts before the last were retried.
    #[serde(default)]
    pub retries: RetryCauses,
    /// Host wall time from the first submission to the final read-back.
    #[serde(with = "duration_ms")]
    pub wall_time: Duration,
    /// GPU time from timestamp queries, when the device has them.
    #[serde(with = "option_duration_ms")]
    pub gpu_time: Option<Duration>,
    /// The run's trace, when the graph was compiled with
    /// [`CompileOptions::trace`](crate::CompileOptions::trace) (see
    /// [`RunReport::trace`]). Not part of the JSON report: export it with
    /// [`Trace::to_chrome_json`](crate::Trace::to_chrome_json).
    #[serde(skip)]
    pub trace: Option<crate::Trace>,
}

impl RunReport {
    /// Stats of a procedure.
    pub fn procedure<T>(&self, procedure: &ProcedureId<T>) -> Option<&ProcedureStats> {
        self.procedure_named(procedure.name())
    }

    /// Stats of the procedure called `name` (for a report read back from
    /// JSON, which has no handles).
    pub fn procedure_named(&self, name: &str) -> Option<&ProcedureStats> {
        self.procedures.iter().find(|p| p.name == name)
    }

    /// Join counts of a continuation procedure.
    pub fn join<T>(&self, continuation: &ProcedureId<T>) -> Option<&JoinStats> {
        self.joins
            .iter()
            .find(|j| j.continuation == continuation.name())
    }

    /// The run's trace: present when the graph was compiled with
    /// [`CompileOptions::trace`](crate::CompileOptions::trace).
    pub fn trace(&self) -> Option<&crate::Trace> {
        self.trace.as_ref()
    }

    /// Total items executed.
    pub fn total_executed(&self) -> u64 {
        self.procedures.iter().map(|p| p.executed).sum()
    }

    /// The report as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}

impl fmt::Display for RunReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:<20}{:>10}{:>12}{:>12}{:>12}{:>11}{:>9}",
            "procedure", "capacity", "seeded", "executed", "enqueued", "high-water", "dropped"
        )?;
        for p in &self.procedures {
            writeln!(
                f,
                "{:<20}{:>10}{:>12}{:>12}{:>12}{:>11}{:>9}",
                p.name, p.capacity, p.seeded, p.executed, p.enqueued, p.high_water, p.dropped
            )?;
        }
        for j in &self.joins {
            writeln!(
                f,
                "joins of {:<11}{:>10} opened{:>10} fired{:>10} outstanding (pool {} of {})",
                j.continuation,
                j.opened,
                j.fired,
                j.outstanding,
                self.join_pool.requested,
                self.join_pool.capacity
            )?;
        }
        write!(
            f,
            "{}, {} workgroups, {} submission(s), {} dispatch(es)",
            self.strategy, self.workgroups, self.submissions, self.dispatches
        )?;
        if self.rounds > 0 {
            write!(f, ", {} rounds", self.rounds)?;
        }
        if self.attempts > 1 {
            write!(f, ", {} attempts", self.attempts)?;
            if self.retries.overflow_held > 0 {
                write!(
                    f,
                    " ({} grew a self-feeding queue to only twice its need)",
                    self.retries.overflow_held
                )?;
            }
        }
        write!(f, ", wall {:.3} ms", self.wall_time.as_secs_f64() * 1e3)?;
        if let Some(gpu) = self.gpu_time {
            write!(f, ", GPU {:.3} ms", gpu.as_secs_f64() * 1e3)?;
        }
        if let Some(trace) = &self.trace {
            write!(
                f,
                ", traced: {} batches ({} dropped)",
                trace.batches,
                trace.dropped()
            )?;
        }
        Ok(())
    }
}

mod duration_ms {
    use std::time::Duration;

    pub(super) fn serialize<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_f64(d.as_secs_f64() * 1e3)
    }

    pub(super) fn deserialize<'de, D: serde::Deserializer<'de>>(
        d: D,
    ) -> Result<Duration, D::Error> {
        let ms: f64 = serde::Deserialize::deserialize(d)?;
        Ok(Duration::from_secs_f64(ms.max(0.0) / 1e3))
    }
}

mod option_duration_ms {
    use std::time::Duration;

    pub(super) fn serialize<S: serde::Serializer>(
        d: &Option<Duration>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        match d {
            Some(d) => s.serialize_some(&(d.as_secs_f64() * 1e3)),
            None => s.serialize_none(),
        }
    }

    pub(super) fn deserialize<'de, D: serde::Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Duration>, D::Error> {
        let ms: Option<f64> = serde::Deserialize::deserialize(d)?;
        Ok(ms.map(|ms| Duration::from_secs_f64(ms.max(0.0) / 1e3)))
    }
}
