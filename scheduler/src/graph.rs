//! The procedure graph a user declares: procedures, their connections, a shared
//! WGSL library, constants and extra resources. Building the graph never
//! fails; all checks happen in [`Graph::compile`](crate::Graph::compile) so
//! that every problem is reported as a typed [`CompileError`](crate::CompileError).

use std::fmt;
use std::marker::PhantomData;
use std::sync::Arc;

use crate::{ConstantValue, Item, ItemType, ProcedureId, Resource, Untyped, WgslStructs, WgslType};

/// Default priority of a procedure. Higher runs first under
/// [`Policy::Priority`](crate::Policy::Priority).
pub const DEFAULT_PRIORITY: i32 = 0;

/// One kind of work: an item type, a thread count per item and a WGSL body.
///
/// The body is the text of a WGSL function body. It is called by **every**
/// thread of the workgroup with these parameters:
///
/// | parameter | type | meaning |
/// |---|---|---|
/// | `item` | the item type | the item (zeroed when `valid` is false) |
/// | `valid` | `bool` | whether this thread has an item in this batch |
/// | `thread` | `u32` | the thread's index within its item, `0..threads_per_item` |
/// | `slot` | `u32` | the item's slot within the workgroup |
///
/// The threads of one slot share an item, so they are all valid or all
/// invalid; with several chunks per batch, the last chunk may be partly
/// filled.
///
/// Barriers (`workgroupBarrier`, `storageBarrier`, `workgroupUniformLoad`)
/// and the item-wide helpers (`item_sum_u32`, `item_broadcast_f32`, ...,
/// which contain barriers) are allowed only at the body's top level, never
/// inside a branch or loop on `valid`, `thread`, `slot` or data: every thread
/// reaches them, including those without an item. A workgroup barrier
/// separates consecutive calls.
///
/// Scratch is per slot: typed with [`Procedure::scratch`] (the body's
/// `scratch` pointer), or untyped words with [`Procedure::scratch_bytes`]
/// (`scratch_load_u32(slot, index)`, `scratch_store_u32(slot, index,
/// value)`, and `_i32`/`_f32`). The crate's front page lists the helpers.
///
/// `T` is the Rust item type: [`Procedure::of`] takes it from a type that
/// derives [`Item`], and [`Graph::procedure`] returns a [`ProcedureId<T>`]
/// that only accepts seeds of that type. [`Procedure::new`] takes an explicit
/// [`ItemType`] instead and makes an [`Untyped`] procedure.
pub struct Procedure<T = Untyped> {
    pub(crate) name: String,
    pub(crate) item: ItemType,
    pub(crate) threads_per_item: u32,
    pub(crate) initial: bool,
    pub(crate) scratch_bytes: u32,
    pub(crate) scratch_type: Option<ScratchType>,
    pub(crate) priority: i32,
    pub(crate) body: String,
    marker: PhantomData<fn() -> T>,
}

/// A procedure's typed scratch: one value of a WGSL type per item slot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct ScratchType {
    /// The WGSL type, e.g. `Partial` or `array<f32, 4>`.
    pub wgsl_type: String,
    /// Struct declarations the type needs, dependencies first (empty for a
    /// type named by [`Procedure::scratch_wgsl`], declared in the library).
    pub structs: Vec<(String, String)>,
}

impl Procedure {
    /// A procedure with items of an explicit [`ItemType`] (for example from
    /// [`item_type!`](crate::item_type)), one thread per item, no scratch,
    /// default priority and an empty body. Its seeds are checked by size at
    /// run time only; prefer [`Procedure::of`].
    pub fn new(name: impl Into<String>, item: ItemType) -> Self {
        Self {
            name: name.into(),
            item,
            threads_per_item: 1,
            initial: false,
            scratch_bytes: 0,
            scratch_type: None,
            priority: DEFAULT_PRIORITY,
            body: String::new(),
            marker: PhantomData,
        }
    }

    /// A procedure whose items are `T`, otherwise like [`Procedure::new`]:
    /// `Procedure::of::<Node>("Grow")`.
    pub fn of<T: Item>(name: impl Into<String>) -> Procedure<T> {
        Procedure::new(name, ItemType::of::<T>()).retype()
    }
}

impl<T> Procedure<T> {
    /// The same procedure with another item type parameter.
    fn retype<U>(self) -> Procedure<U> {
        Procedure {
            name: self.name,
            item: self.item,
            threads_per_item: self.threads_per_item,
            initial: self.initial,
            scratch_bytes: self.scratch_bytes,
            scratch_type: self.scratch_type,
            priority: self.priority,
            body: self.body,
            marker: PhantomData,
        }
    }

    /// Threads that work on one item: a power of two up to the workgroup size.
    pub fn threads_per_item(mut self, threads: u32) -> Self {
        self.threads_per_item = threads;
        self
    }

    /// Whether the host may seed this procedure's queue with initial items.
    pub fn initial(mut self, initial: bool) -> Self {
        self.initial = initial;
        self
    }

    /// Bytes of untyped workgroup scratch memory per item (rounded up to
    /// 4-byte words), read and written with `scratch_load_u32(slot, index)`
    /// and its siblings. Prefer [`Procedure::scratch`].
    pub fn scratch_bytes(mut self, bytes: u32) -> Self {
        self.scratch_bytes = bytes;
        self
    }

    /// Typed scratch: one `S` of workgroup memory per item, which the body
    /// reaches through the pointer `scratch` (`scratch.total += 1u;`,
    /// `(*scratch)[thread] = x;`). The generator declares
    /// `var<workgroup> sched_scratch_<Procedure>: array<S, items per chunk>`
    /// and starts the body with `let scratch = &sched_scratch_<Procedure>[slot];`.
    /// Its size is measured by naga with the rest of the workgroup memory.
    /// `S` is any [`WgslType`]: a struct deriving [`Item`], a scalar, or an
    /// array. Unlike untyped scratch, each procedure's typed scratch is its
    /// own variable, so typed scratch of several procedures adds up.
    ///
    /// ```
    /// #[scheduler::item]
    /// struct Partial { total: u32, count: u32 }
    ///
    /// let sum = scheduler::Procedure::of::<Partial>("Sum")
    ///     .threads_per_item(4)
    ///     .scratch::<Partial>()
    ///     .body("if (valid && thread == 0u) { scratch.total = item.total; }");
    /// ```
    pub fn scratch<S: WgslType>(mut self) -> Self {
        let mut structs = WgslStructs::default();
        S::wgsl_structs(&mut structs);
        self.scratch_type = Some(ScratchType {
            wgsl_type: S::wgsl_type(),
            structs: structs
                .into_entries()
                .into_iter()
                .map(|(name, source)| (name.to_owned(), source))
                .collect(),
        });
        self
    }

    /// Typed scratch of a WGSL type the graph's library declares (a struct
    /// with a `bool` or an atomic, say), otherwise like [`Procedure::scratch`].
    pub fn scratch_wgsl(mut self, wgsl_type: impl Into<String>) -> Self {
        self.scratch_type = Some(ScratchType {
            wgsl_type: wgsl_type.into(),
            structs: Vec::new(),
        });
        self
    }

    /// Scheduling priority; higher is picked first under the priority policy.
    pub fn priority(mut self, priority: i32) -> Self {
        self.priority = priority;
        self
    }

    /// The WGSL function body (see the type's documentation for the contract).
    pub fn body(mut self, wgsl: impl Into<String>) -> Self {
        self.body = wgsl.into();
        self
    }

    /// The procedure's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The procedure's item type.
    pub fn item_type(&self) -> &ItemType {
        &self.item
    }
}

// Written out rather than derived: derives would require `T: Clone` and
// `T: Debug`, but `T` is only a marker.
impl<T> Clone for Procedure<T> {
    fn clone(&self) -> Self {
        Self {
            name: self.name.clone(),
            item: self.item.clone(),
            body: self.body.clone(),
            scratch_type: self.scratch_type.clone(),
            marker: PhantomData,
            ..*self
        }
    }
}

impl<T> fmt::Debug for Procedure<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Procedure")
            .field("name", &self.name)
            .field("item", &self.item)
            .field("threads_per_item", &self.threads_per_item)
            .field("initial", &self.initial)
            .field("scratch_bytes", &self.scratch_bytes)
            .field("scratch_type", &self.scratch_type)
            .field("priority", &self.priority)
            .field("body", &self.body)
            .finish()
    }
}

/// Permission for `from` to enqueue into `to`, with the most items one item of
/// `from` may enqueue into `to` (its fan-out): declared, or derived from the
/// body when compiling (`None`). The fan-out sizes the per-workgroup staging
/// area; exceeding it is reported, never silently dropped.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Connection {
    pub(crate) from: String,
    pub(crate) to: String,
    pub(crate) fan_out: Option<u32>,
}

/// A procedure graph: compile it with [`Graph::compile`].
#[derive(Clone, Debug, Default)]
pub struct Graph {
    pub(crate) name: String,
    pub(crate) procedures: Vec<Procedure>,
    pub(crate) connections: Vec<Connection>,
    pub(crate) library: String,
    pub(crate) constants: Vec<(String, ConstantValue)>,
    pub(crate) resources: Vec<Resource>,
    pub(crate) joins: Vec<Join>,
}

/// A join: items of `parent` may open a join record whose continuation is
/// `continuation` (see [`Graph::join`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Join {
    pub(crate) parent: String,
    pub(crate) continuation: String,
}

impl Graph {
    /// An empty graph; the name appears in the generated module's header.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            ..Self::default()
        }
    }

    /// Adds a procedure and returns its handle, which connections, seeds and
    /// report look-ups take.
    pub fn procedure<T>(&mut self, procedure: Procedure<T>) -> ProcedureId<T> {
        let id = ProcedureId::new(Arc::from(procedure.name.as_str()));
        self.procedures.push(procedure.retype());
        id
    }

    /// The handle of the procedure called `name`, if the graph has one whose
    /// item type is `T`: for code that gets a graph without its handles.
    pub fn procedure_id<T: Item>(&self, name: &str) -> Option<ProcedureId<T>> {
        let item = ItemType::of::<T>();
        self.procedures
            .iter()
            .find(|p| p.name == name && p.item == item)
            .map(|p| ProcedureId::new(Arc::from(p.name.as_str())))
    }

    /// Lets `from` enqueue into `to`, with the fan-out (the most items one
    /// item of `from` enqueues into `to`) derived from `from`'s body when
    /// compiling: the calls to `enqueue_<to>` on the path through the body
    /// (and the functions it calls) that makes the most of them, counted once
    /// per thread of the item unless an `if (thread == C)` (alone or in a
    /// `&&`) admits one thread. If no call is made, the fan-out is 1.
    ///
    /// A call inside a loop has no such bound: compiling then fails with
    /// [`CompileError::FanOutNotDerivable`](crate::CompileError::FanOutNotDerivable),
    /// and the connection needs [`Graph::connect_with_fan_out`].
    ///
    /// ```
    /// # #[scheduler::item] struct Node { depth: u32 }
    /// let mut graph = scheduler::Graph::new("tree");
    /// let grow = graph.procedure(
    ///     scheduler::Procedure::of::<Node>("Grow").initial(true).body(
    ///         "if (valid && item.depth < 3u) {
    ///     enqueue_Grow(Node(item.depth + 1u));
    ///     enqueue_Grow(Node(item.depth + 1u));
    /// }",
    ///     ),
    /// );
    /// graph.connect(&grow, &grow); // fan-out 2, from the two calls
    /// let compiled = graph.compile(&scheduler::CompileOptions::default()).unwrap();
    /// assert_eq!(compiled.queues()[0].targets, [(0, 2)]);
    /// ```
    pub fn connect<A, B>(&mut self, from: &ProcedureId<A>, to: &ProcedureId<B>) -> &mut Self {
        self.connections.push(Connection {
            from: from.name().to_owned(),
            to: to.name().to_owned(),
            fan_out: None,
        });
        self
    }

    /// Lets `from` enqueue up to `fan_out` items into `to` per item it runs:
    /// for bodies whose enqueues a loop makes, or whose fan-out depends on
    /// data. Where the body's calls do have a bound (see [`Graph::connect`]),
    /// a `fan_out` below it is a compile error,
    /// [`CompileError::FanOutBelowBound`](crate::CompileError::FanOutBelowBound).
    ///
    /// What a run checks: every run counts the items a batch (a workgroup's
    /// items) stages for `to` against the batch's room, items per batch times
    /// the fan-out, and fails with
    /// [`RunError::FanOutExceeded`](crate::RunError::FanOutExceeded) when it
    /// overflows; the enqueues beyond the room are lost. Checked mode
    /// ([`CompileOptions::checked`](crate::CompileOptions::checked)) counts
    /// every item's enqueues against the fan-out itself, so that one item
    /// over it fails the run with
    /// [`RunError::ItemFanOutExceeded`](crate::RunError::ItemFanOutExceeded),
    /// naming the item, even when its batch stayed within its room. That
    /// check costs tens of percent of a run on lavapipe, hence checked mode
    /// only (docs/scheduler.md, "Fan-out", has the measurements).
    pub fn connect_with_fan_out<A, B>(
        &mut self,
        from: &ProcedureId<A>,
        to: &ProcedureId<B>,
        fan_out: u32,
    ) -> &mut Self {
        self.connections.push(Connection {
            from: from.name().to_owned(),
            to: to.name().to_owned(),
            fan_out: Some(fan_out),
        });
        self
    }

    /// Lets items of `parent` open joins whose continuation is
    /// `continuation`: top-down work that is finished bottom-up (split a
    /// tree, then refit it from the leaves).
    ///
    /// In `parent`'s body, `join_open_<Continuation>(record)` opens a join
    /// whose record is an item of the continuation's type `C` (the node to
    /// refit, say) and returns whether it did. From then until the body
    /// ends, the thread's enqueues are the join's children. Children's own
    /// enqueues (and the joins they open) are the join's too, transitively:
    /// once every one of them has finished, the last to finish enqueues
    /// `record` into `continuation`, exactly once. The continuation runs as
    /// part of whatever the opener ran under, so joins nest: a continuation
    /// finishing is what finishes its opener for the join above it.
    ///
    /// Results flow up through the graph's resources (an array indexed by
    /// node): a child's writes are visible to the continuation, as
    /// docs/scheduler.md ("Joins") argues. Each thread opens at most one
    /// join per item (a second call returns `false`). Records live in a
    /// pool of [`Capacities::join_pool`](crate::Capacities::join_pool)
    /// records per run; a run that asks for more fails with
    /// [`RunError::JoinPoolOverflow`](crate::RunError::JoinPoolOverflow)
    /// and its measured need, and a join that never fires (a child lost to an
    /// overflow) is reported as
    /// [`RunError::JoinsUnfinished`](crate::RunError::JoinsUnfinished).
    ///
    /// ```
    /// # #[scheduler::item] struct Node { id: u32, depth: u32 }
    /// # #[scheduler::item] struct Refit { id: u32 }
    /// let mut graph = scheduler::Graph::new("tree");
    /// let split = graph.procedure(scheduler::Procedure::of::<Node>("Split").initial(true).body(
    ///     "if (valid && item.depth < 3u && join_open_Refit(Refit(item.id))) {
    ///     enqueue_Split(Node(2u * item.id, item.depth + 1u));
    ///     enqueue_Split(Node(2u * item.id + 1u, item.depth + 1u));
    /// }",
    /// ));
    /// let refit = graph.procedure(scheduler::Procedure::of::<Refit>("Refit"));
    /// graph.connect(&split, &split).join(&split, &refit);
    /// graph.compile(&scheduler::CompileOptions::default()).unwrap();
    /// ```
    pub fn join<P, C>(
        &mut self,
        parent: &ProcedureId<P>,
        continuation: &ProcedureId<C>,
    ) -> &mut Self {
        self.joins.push(Join {
            parent: parent.name().to_owned(),
            continuation: continuation.name().to_owned(),
        });
        self
    }

    /// Declares `const NAME: TYPE = value;` in the generated module, where
    /// bodies and the library use it by name. `value` is a `u32`, `i32`,
    /// `f32` (written so that it parses back to the same bits) or `bool`.
    ///
    /// ```
    /// let mut graph = scheduler::Graph::new("tree");
    /// graph.constant("MAX_DEPTH", 10u32).constant("SCALE", 0.1f32);
    /// ```
    ///
    /// Compiling rejects a name that is not a WGSL identifier, is a WGSL
    /// keyword, starts with `sched_`, `SCHED_` or `enqueue_`, or is declared
    /// twice, and a NaN or infinite `f32`.
    pub fn constant(
        &mut self,
        name: impl Into<String>,
        value: impl Into<ConstantValue>,
    ) -> &mut Self {
        self.constants.push((name.into(), value.into()));
        self
    }

    /// Appends WGSL to the graph's shared library (helper functions, structs,
    /// constants). Names must not start with `sched_`, `SCHED_` or `enqueue_`,
    /// which the generator reserves.
    pub fn library(&mut self, wgsl: &str) -> &mut Self {
        if !self.library.is_empty() && !self.library.ends_with('\n') {
            self.library.push('\n');
        }
        self.library.push_str(wgsl);
        self
    }

    /// Declares an extra resource (bound at group 1, binding = declaration index).
    pub fn resource(&mut self, resource: Resource) -> &mut Self {
        self.resources.push(resource);
        self
    }

    /// The procedures in declaration order.
    pub fn procedures(&self) -> &[Procedure] {
        &self.procedures
    }
}
