//! Typed errors for compiling a graph and for getting a device. A run's
//! errors are the runtime's (`runtime::error`), next to the report they carry.

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
#[non_exhaustive]
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
    /// A join ([`Graph::join`](crate::Graph::join)) names a procedure the
    /// graph does not have.
    #[error("join `{parent}` -> `{continuation}` names unknown procedure `{unknown}`")]
    UnknownJoinProcedure {
        /// The procedure whose items open the joins.
        parent: String,
        /// The continuation.
        continuation: String,
        /// The name not found.
        unknown: String,
    },
    /// A procedure's body (or a helper it calls) opens a join with
    /// `join_open_<continuation>` without a declared
    /// [`Graph::join`](crate::Graph::join) from it to that continuation.
    #[error(
        "procedure `{procedure}` opens joins of `{continuation}` (via {via}) but the graph has no join `{procedure}` -> `{continuation}`"
    )]
    UndeclaredJoin {
        /// The procedure whose call graph reaches the open.
        procedure: String,
        /// The continuation of the join it opens.
        continuation: String,
        /// The function that calls `join_open_<continuation>`.
        via: String,
    },
    /// A connection made with [`Graph::connect`](crate::Graph::connect)
    /// has no fan-out to derive: the body (or a helper it calls) enqueues
    /// into the target inside a loop.
    #[error(
        "procedure `{procedure}` calls `enqueue_{target}` inside a loop (in {via}), so its fan-out into `{target}` cannot be derived; declare it with `connect_with_fan_out`"
    )]
    FanOutNotDerivable {
        /// The procedure whose body enqueues.
        procedure: String,
        /// The target it enqueues into.
        target: String,
        /// The function whose loop makes the call: `its body`, or a helper.
        via: String,
    },
    /// A fan-out declared with
    /// [`Graph::connect_with_fan_out`](crate::Graph::connect_with_fan_out) is
    /// below what the body's enqueue calls can reach.
    #[error(
        "connection `{procedure}` -> `{target}` declares a fan-out of {declared}, but one item of `{procedure}` may call `enqueue_{target}` {bound} times; declare at least {bound}"
    )]
    FanOutBelowBound {
        /// The procedure whose body enqueues.
        procedure: String,
        /// The target it enqueues into.
        target: String,
        /// The fan-out declared.
        declared: u32,
        /// The bound derived from the body's calls.
        bound: u32,
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

/// Why no device could be created.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
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
