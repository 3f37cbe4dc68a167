//! Why a run failed: typed errors that carry the run's report.

use std::time::Duration;

use crate::RunReport;

/// Why a run failed. Every variant that happens after the kernel ran carries
/// the run's report, so statistics are never lost.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunError {
    /// The named procedure does not exist or does not accept initial items.
    #[error("cannot seed `{procedure}`: {reason}")]
    Seed {
        /// The procedure named.
        procedure: String,
        /// Why.
        reason: String,
    },
    /// A queue was too small. Every refused reservation is counted, so
    /// `needed` holds all the items this run made; the dropped items never
    /// ran and their descendants never existed, so a run that accepts them
    /// may need more.
    /// An overflow is reported before anything else that went wrong in the
    /// same run (a loop limit, a fan-out excess), which `also` lists: it is
    /// the likelier cause of the rest.
    #[error(
        "queue `{procedure}` overflowed: capacity {capacity}, {dropped} items did not fit (a capacity of {needed} would have held every item of this run, the children the refused items would have enqueued not included; `Executor::run_with_retry` grows it){}",
        also_note(also)
    )]
    QueueOverflow {
        /// The procedure whose queue overflowed.
        procedure: String,
        /// Its capacity in items.
        capacity: u32,
        /// Items that did not fit (a lower bound on the true shortfall).
        dropped: u64,
        /// A lower bound on the capacity this run needed: the largest fill
        /// one refused reservation asked for.
        needed_at_least: u64,
        /// The capacity that would have held every item of this run: the
        /// high-water mark plus every refused item.
        needed: u64,
        /// What else went wrong in the run, in words.
        also: Vec<String>,
        /// The full report of the run.
        report: Box<RunReport>,
    },
    /// Checked mode found an index past the end of a resource: `index` (the
    /// first recorded) into `resource`, whose bound buffer holds `bound`
    /// elements, made by an item of `procedure` (its body or the library
    /// code it called). The access itself was redirected to the last
    /// element, so nothing outside the buffer was touched, but the results
    /// are wrong. The same program without checked mode is undefined
    /// behaviour. Reported after an overflow of the same run, which `also`
    /// then lists first.
    #[error(
        "procedure `{procedure}` indexed resource `{resource}` out of bounds: index {index}, bound {bound} ({count} out-of-bounds access(es) in all){}",
        also_note(also)
    )]
    OutOfBounds {
        /// The procedure whose item made the access.
        procedure: String,
        /// The resource.
        resource: String,
        /// The first offending index recorded.
        index: u32,
        /// The bound buffer's length in elements.
        bound: u32,
        /// Out-of-bounds accesses of this procedure into this resource.
        count: u64,
        /// What else went wrong, in words (other violations included).
        also: Vec<String>,
        /// The full report of the run.
        report: Box<RunReport>,
    },
    /// More seeds than a queue holds; nothing ran.
    /// [`Executor::run_with_retry`](crate::Executor::run_with_retry) grows
    /// the queue to fit them.
    #[error("{seeds} seeds for `{procedure}` exceed its queue capacity {capacity}")]
    TooManySeeds {
        /// The procedure seeded.
        procedure: String,
        /// Seeds given.
        seeds: u64,
        /// Its queue's capacity.
        capacity: u32,
    },
    /// The run asked for more join records than the pool holds
    /// ([`Capacities::join_pool`](crate::Capacities::join_pool)):
    /// the `join_open` calls beyond it returned false, so their joins never
    /// opened. `needed` is every record the run asked for, the capacity that
    /// would have held them all (records are not reused within a run);
    /// [`Executor::run_with_retry`](crate::Executor::run_with_retry) grows
    /// the pool to it.
    #[error(
        "the join pool overflowed: capacity {capacity} records, the run asked for {needed} (`Executor::run_with_retry` grows it){}",
        also_note(also)
    )]
    JoinPoolOverflow {
        /// Records the pool held.
        capacity: u32,
        /// Records the run asked for.
        needed: u64,
        /// What else went wrong, in words.
        also: Vec<String>,
        /// The full report of the run.
        report: Box<RunReport>,
    },
    /// Joins opened and never fired: some child of theirs never finished
    /// (lost to an overflow, say), so their continuation never ran and the
    /// bottom-up results are incomplete. Names the first continuation with
    /// joins outstanding; `also` lists the rest.
    #[error(
        "{joins} join(s) of `{continuation}` never fired: a child of each never finished, so `{continuation}` never received their records{}",
        also_note(also)
    )]
    JoinsUnfinished {
        /// The continuation procedure whose joins are outstanding.
        continuation: String,
        /// Its joins opened and never fired.
        joins: u64,
        /// What else went wrong, in words.
        also: Vec<String>,
        /// The full report of the run.
        report: Box<RunReport>,
    },
    /// Items of one workgroup batch enqueued more into a queue than the declared
    /// fan-outs allow; the excess was counted, not silently dropped.
    #[error(
        "procedure bodies enqueued {excess} more items into `{procedure}` than the declared fan-out allows"
    )]
    FanOutExceeded {
        /// The target queue.
        procedure: String,
        /// How many enqueues did not fit.
        excess: u64,
        /// The full report of the run.
        report: Box<RunReport>,
    },
    /// Checked mode
    /// ([`CompileOptions::checked`](crate::CompileOptions::checked)): an item
    /// of `procedure` enqueued more items into `target` than the connection's
    /// fan-out, even if its batch as a whole stayed within its staging room.
    #[error(
        "item {item} of `{procedure}` enqueued {count} items into `{target}`, over the declared fan-out of {declared} ({items} item(s) of `{procedure}` went over)"
    )]
    ItemFanOutExceeded {
        /// The procedure whose item enqueued too much.
        procedure: String,
        /// The queue it enqueued into.
        target: String,
        /// The first offending item recorded, as its ticket in its
        /// procedure's queue: the items seeded into a queue are its tickets
        /// `0..` in the order given (on the run's first submission), and
        /// every item enqueued later takes the next ticket.
        item: u32,
        /// The enqueues that item made into `target`.
        count: u32,
        /// The connection's fan-out.
        declared: u32,
        /// The items of `procedure` that went over a fan-out.
        items: u64,
        /// What else went wrong, in words (other violations included).
        also: Vec<String>,
        /// The full report of the run.
        report: Box<RunReport>,
    },
    /// A loop of the megakernel or of a body ran out of the driver's loop
    /// budget (llvmpipe caps every invocation's loops), so the run's results
    /// cannot be trusted. The scheduler finds its own cut waits, and checks
    /// after every body call whether the budget ran out inside the body
    /// (`body_loops`); a caller can add the cuts its bodies count with
    /// [`Retry::check_loops`](crate::Retry::check_loops). Off llvmpipe,
    /// `waits` are waits for free slots that expired. `advice` fits the
    /// strategy, configuration and driver the run used.
    #[error(
        "loops were cut short: {}; the results are not trustworthy. {advice}",
        cut_loops(*waits, *body_loops)
    )]
    LoopLimit {
        /// The scheduler's spin-waits and loops that found themselves cut
        /// (after a body spent the budget, these follow from it).
        waits: u32,
        /// Body calls that spent the driver's loop budget, found by the
        /// check after each body call, plus the cuts the caller's
        /// [`Retry::check_loops`](crate::Retry::check_loops) reported.
        body_loops: u32,
        /// What to change, for this run's strategy and configuration.
        advice: String,
        /// The report of the run up to the submission that found the cut.
        report: Box<RunReport>,
    },
    /// Work remained, but submissions in a row executed no item: the
    /// workgroups made no progress (their bounded waits ended without the
    /// work they waited for moving). Ends the run instead of a device loss
    /// or a host timeout; persistent workgroups are not safe on this
    /// adapter, Rounds need no progress guarantee.
    #[error(
        "no progress: {submissions} submission(s) in a row executed no item while {pending} item(s) were outstanding; the workgroups made no progress, so run with `Strategy::Rounds` on this adapter"
    )]
    NoProgress {
        /// Submissions in a row that executed nothing.
        submissions: u32,
        /// Outstanding items after the last of them.
        pending: u32,
        /// The report of the run so far.
        report: Box<RunReport>,
    },
    /// The host-side timeout elapsed before the GPU finished. The report
    /// holds the counters of the last submission that completed (a run of
    /// several submissions: an iteration budget, batches of rounds), or is
    /// `None` when none did, which the message says.
    #[error(
        "the run did not finish within {limit:?}; the device may need to be recreated. {}",
        partial_note(report.as_deref(), also)
    )]
    Timeout {
        /// The configured limit.
        limit: Duration,
        /// The report up to the last submission that completed, if any did.
        report: Option<Box<RunReport>>,
        /// What that report shows went wrong (overflows first).
        also: Vec<String>,
    },
    /// The device failed (was lost, ran out of memory) while the run was in
    /// flight. The report holds the counters of the last submission that
    /// completed, or is `None` when none did.
    #[error(
        "the device failed during the run: {message}. {}",
        partial_note(report.as_deref(), also)
    )]
    DeviceFailed {
        /// wgpu's message.
        message: String,
        /// The report up to the last submission that completed, if any did.
        report: Option<Box<RunReport>>,
        /// What that report shows went wrong (overflows first).
        also: Vec<String>,
    },
    /// The bindings given do not match the graph's declared resources.
    #[error("binding problem: {0}")]
    Binding(String),
    /// A buffer bound (or created) for a typed resource is smaller than the
    /// resource's declared minimum; the run did not start.
    #[error(
        "resource `{resource}` is bound to {bytes} bytes but needs at least {needed}; the run did not start"
    )]
    BufferTooSmall {
        /// The resource.
        resource: String,
        /// Bytes bound.
        bytes: u64,
        /// Bytes its declared minimum length needs.
        needed: u64,
    },
    /// A retry measured that a queue needs more items than the device's
    /// buffer limits let it hold (a ring's capacity is a power of two, its
    /// slots and range markers must each fit one storage binding).
    #[error(
        "queue `{procedure}` needs {needed} items but at most {max} fit the device's storage buffer limits; lower the work per run (fewer seeds per run, less fan-out), or use a device with larger limits"
    )]
    QueueExceedsDevice {
        /// The queue's procedure.
        procedure: String,
        /// Items it was measured to need.
        needed: u64,
        /// The largest capacity the device allows it next to the other queues.
        max: u32,
        /// The report of the run that measured the need (none after
        /// over-seeding, where nothing ran).
        report: Option<Box<RunReport>>,
    },
    /// The graph, the configuration or a binding needs more than one of the
    /// device's limits allows; checked before anything is dispatched, so
    /// the run did not start.
    #[error(
        "{what} needs {needed} but the device's `{limit_name}` is {limit}; the run did not start"
    )]
    ExceedsDeviceLimit {
        /// What exceeds it, in words.
        what: String,
        /// What it needs.
        needed: u64,
        /// The device's limit.
        limit: u64,
        /// The name of the limit in `wgpu::Limits`.
        limit_name: &'static str,
    },
    /// The configuration asks for more memory than the device allows.
    #[error("configuration needs a {what} of {needed} bytes but the device allows {limit}")]
    TooLarge {
        /// Which buffer.
        what: &'static str,
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
    /// wgpu reported an error (validation, out of memory, device lost).
    #[error("wgpu error: {0}")]
    Gpu(String),
}

impl RunError {
    /// A timeout after `limit`, before any report was read.
    pub fn timeout(limit: Duration) -> Self {
        Self::Timeout {
            limit,
            report: None,
            also: Vec::new(),
        }
    }

    /// The report the error carries, if any: every error after the kernel
    /// ran has one, except an interrupted run none of whose submissions
    /// completed.
    pub fn report(&self) -> Option<&RunReport> {
        match self {
            Self::QueueOverflow { report, .. }
            | Self::JoinPoolOverflow { report, .. }
            | Self::JoinsUnfinished { report, .. }
            | Self::FanOutExceeded { report, .. }
            | Self::ItemFanOutExceeded { report, .. }
            | Self::OutOfBounds { report, .. }
            | Self::LoopLimit { report, .. }
            | Self::NoProgress { report, .. } => Some(report),
            Self::Timeout { report, .. }
            | Self::DeviceFailed { report, .. }
            | Self::QueueExceedsDevice { report, .. } => report.as_deref(),
            _ => None,
        }
    }
}

/// What a loop limit cut: the scheduler's waits, the bodies' own loops, or
/// both.
fn cut_loops(waits: u32, body_loops: u32) -> String {
    match (waits, body_loops) {
        (waits, 0) => format!(
            "{waits} of the scheduler's loop(s) (the driver's loop limit, or a bounded wait that expired)"
        ),
        (0, body) => format!("the bodies' own loops ({body} cut)"),
        (waits, body) => format!(
            "the bodies' own loops ({body} cut), and after them {waits} of the scheduler's loop(s)"
        ),
    }
}

/// The end of an interrupted run's message: what its partial report shows,
/// or that none could be read.
fn partial_note(report: Option<&RunReport>, also: &[String]) -> String {
    match report {
        None => "No report could be read: no submission of the run completed.".to_owned(),
        Some(report) => {
            let mut note = format!(
                "The report holds the counters after {} completed submission(s)",
                report.submissions
            );
            if also.is_empty() {
                note.push('.');
            } else {
                note.push_str(&format!("; by then: {}.", also.join("; ")));
            }
            note
        }
    }
}

/// The tail of an overflow's message naming what else went wrong.
fn also_note(also: &[String]) -> String {
    if also.is_empty() {
        String::new()
    } else {
        format!("; also: {}", also.join("; "))
    }
}
