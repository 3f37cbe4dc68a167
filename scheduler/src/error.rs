//! Typed errors for compiling a graph and for running it.

use std::time::Duration;

use crate::RunReport;

/// Where a line of the generated module came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SourceOrigin {
    /// The body of the named procedure.
    Body(String),
    /// The graph's shared WGSL library.
    Library,
    /// The WGSL declaration of the named item type.
    Item(String),
    /// Code the generator wrote (a bug in the generator if it fails).
    Generated,
}

impl std::fmt::Display for SourceOrigin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Body(p) => write!(f, "body of procedure `{p}`"),
            Self::Library => f.write_str("graph library"),
            Self::Item(t) => write!(f, "WGSL declaration of item type `{t}`"),
            Self::Generated => f.write_str("generated code"),
        }
    }
}

/// Why a graph did not compile.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CompileError {
    /// Two procedures share a name.
    #[error("duplicate procedure name `{0}`")]
    DuplicateProcedure(String),
    /// A procedure name is not usable as a WGSL identifier suffix.
    #[error(
        "procedure name `{0}` must be an ASCII identifier (letters, digits, '_', not starting with a digit)"
    )]
    InvalidProcedureName(String),
    /// No procedure accepts initial items, so nothing could ever run.
    #[error("no procedure accepts initial items; mark at least one with `.initial(true)`")]
    NoInitialProcedure,
    /// A connection names a procedure that does not exist.
    #[error("connection `{from}` -> `{to}` names unknown procedure `{unknown}`")]
    UnknownProcedure {
        /// Source of the connection.
        from: String,
        /// Target of the connection.
        to: String,
        /// The name that does not exist.
        unknown: String,
    },
    /// A connection has fan-out zero.
    #[error("connection `{from}` -> `{to}` has fan-out 0; it must be at least 1")]
    ZeroFanOut {
        /// Source of the connection.
        from: String,
        /// Target of the connection.
        to: String,
    },
    /// Threads per item is not a power of two up to the workgroup size.
    #[error(
        "procedure `{procedure}` asks for {threads} threads per item; it must be a power of two from 1 to the workgroup size {workgroup_size}"
    )]
    InvalidThreadCount {
        /// The procedure.
        procedure: String,
        /// Its requested threads per item.
        threads: u32,
        /// The workgroup size compiled for.
        workgroup_size: u32,
    },
    /// The workgroup size is not a power of two within the limits.
    #[error(
        "workgroup size {size} must be a power of two no larger than the limits allow ({limit})"
    )]
    InvalidWorkgroupSize {
        /// Requested size.
        size: u32,
        /// What the limits allow.
        limit: u32,
    },
    /// `chunks_per_batch` is 0 or above [`crate::MAX_CHUNKS_PER_BATCH`].
    #[error("chunks per batch {chunks} must be between 1 and {max}")]
    InvalidChunksPerBatch {
        /// Requested chunks per batch.
        chunks: u32,
        /// The largest allowed.
        max: u32,
    },
    /// The workgroup memory of an entry point, measured on the module (the
    /// shared scratch region, the scheduler's own variables and the library's
    /// `var<workgroup>` declarations), exceeds
    /// `max_compute_workgroup_storage_size`.
    #[error(
        "procedure `{procedure}` needs {needed} bytes of workgroup memory ({per_item} bytes of scratch per item x {items} items + {internal} bytes of other workgroup variables, the library's included); the limit is {limit}"
    )]
    ScratchTooLarge {
        /// The procedure with the largest scratch need.
        procedure: String,
        /// Scratch bytes per item.
        per_item: u32,
        /// Items per workgroup.
        items: u32,
        /// The rest of the need: the scheduler's and the library's workgroup
        /// variables, each rounded up to 16 bytes as WebGPU counts them.
        internal: u32,
        /// Total bytes needed.
        needed: u32,
        /// The limit compiled for.
        limit: u32,
    },
    /// A body (or a helper it calls) enqueues into a procedure that it is not
    /// connected to.
    #[error(
        "procedure `{procedure}` enqueues into `{target}` (via {via}) but the graph has no connection `{procedure}` -> `{target}`"
    )]
    UndeclaredEnqueue {
        /// The procedure whose call graph reaches the enqueue.
        procedure: String,
        /// The target it enqueues into.
        target: String,
        /// The function that calls `enqueue_<target>`.
        via: String,
    },
    /// The Rust and WGSL layouts of an item type disagree.
    #[error("item type `{item}` (Rust `{rust}`): {detail}")]
    ItemLayoutMismatch {
        /// WGSL struct name.
        item: String,
        /// Rust type name.
        rust: String,
        /// What differs.
        detail: String,
    },
    /// The item type uses a field type the queues cannot carry.
    #[error("item type `{item}` field `{field}` has unsupported type: {detail}")]
    UnsupportedItemField {
        /// WGSL struct name.
        item: String,
        /// The field.
        field: String,
        /// Why.
        detail: String,
    },
    /// A procedure cannot be reached from any initial procedure.
    #[error("procedure `{0}` is unreachable: no initial procedure leads to it")]
    UnreachableProcedure(String),
    /// User WGSL declares a name the generator reserves.
    #[error(
        "the name `{name}` is reserved for generated code (names starting with `sched_`, `SCHED_` or `enqueue_`)"
    )]
    ReservedName {
        /// The offending name.
        name: String,
    },
    /// A graph constant's name is not a WGSL identifier, or is a WGSL keyword
    /// or reserved word.
    #[error(
        "constant name `{0}` must be a WGSL identifier (ASCII letters, digits, '_', not starting with a digit or `__`) and not a WGSL keyword"
    )]
    InvalidConstantName(String),
    /// Two graph constants share a name.
    #[error("duplicate constant name `{0}`")]
    DuplicateConstant(String),
    /// A graph constant is NaN or infinite, which WGSL cannot express.
    #[error("constant `{name}` is {value}; WGSL constants must be finite")]
    NonFiniteConstant {
        /// The constant.
        name: String,
        /// Its value.
        value: String,
    },
    /// Two resources share a name, or there are more than the limits allow.
    #[error("resource problem: {0}")]
    Resource(String),
    /// WGSL that does not parse or validate.
    #[error("WGSL error in {origin}, line {line}, column {column}: {message}")]
    Wgsl {
        /// Where the faulty line came from.
        origin: SourceOrigin,
        /// 1-based line within that source (the body's own line numbers for a body).
        line: u32,
        /// 1-based column.
        column: u32,
        /// naga's message.
        message: String,
    },
}

/// Why a run failed. Every variant that happens after the kernel ran carries
/// the run's report, so statistics are never lost.
#[derive(Debug, thiserror::Error)]
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
    /// A loop of the megakernel or of a body ran out of the driver's loop
    /// budget (llvmpipe caps every invocation's loops), so the run's results
    /// cannot be trusted. The scheduler finds its own cut waits; cuts of the
    /// bodies' own loops only the bodies can count, and a caller reports
    /// them with [`Retry::check_loops`](crate::Retry::check_loops).
    /// `advice` fits the strategy and configuration the run used.
    #[error(
        "the driver's loop limit cut {} short (llvmpipe); the results are not trustworthy. {advice}",
        cut_loops(*waits, *body_loops)
    )]
    LoopLimit {
        /// Spin-waits and invocations that found a loop cut.
        waits: u32,
        /// Loops of the bodies that the caller's
        /// [`Retry::check_loops`](crate::Retry::check_loops) reported cut
        /// (0 without a check).
        body_loops: u32,
        /// What to change, for this run's strategy and configuration.
        advice: String,
        /// The report of the run up to the submission that found the cut.
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

/// Why no device could be created.
#[derive(Debug, thiserror::Error)]
pub enum DeviceError {
    /// No adapter matched.
    #[error(
        "no GPU adapter found ({0}); install a Vulkan driver (for example Mesa's lavapipe: `apt-get install mesa-vulkan-drivers`) or set WGPU_BACKEND / WGPU_ADAPTER_NAME"
    )]
    NoAdapter(String),
    /// The adapter refused the device request.
    #[error("could not create a device: {0}")]
    RequestDevice(String),
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
            | Self::FanOutExceeded { report, .. }
            | Self::OutOfBounds { report, .. }
            | Self::LoopLimit { report, .. } => Some(report),
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
        (waits, 0) => format!("{waits} loop(s)"),
        (0, body) => {
            format!("{body} of the bodies' own loop(s) (reported by `Retry::check_loops`)")
        }
        (waits, body) => format!(
            "{waits} of the scheduler's loop(s) and {body} of the bodies' own loop(s) (reported by `Retry::check_loops`)"
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
                report.dispatches
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
