//! A task-graph scheduler for irregular GPU workloads, in the spirit of
//! Whippletree (Steinberger et al. 2014).
//!
//! Users declare [`Procedure`]s: an item type, a number of threads per item, a
//! WGSL body and the procedures it may enqueue into. [`Graph::compile`] turns
//! the whole graph into **one WGSL megakernel** in which persistent workgroups
//! pop items from per-procedure queues, run the matching body and push new
//! items until no work is left. An [`Executor`] runs it on a `wgpu` device.
//!
//! ```no_run
//! use scheduler::{CompileOptions, Executor, ExecutorConfig, Graph, Gpu, Procedure, Seeds};
//!
//! // The item type, stated once: its WGSL struct is derived from it.
//! #[scheduler::item]
//! struct Node { depth: u32, id: u32 }
//!
//! let mut graph = Graph::new("binary tree");
//! graph.constant("MAX_DEPTH", 10u32);
//! let grow = graph.procedure(Procedure::of::<Node>("Grow").initial(true).body(
//!     "if (valid && item.depth < MAX_DEPTH) {
//!          enqueue_Grow(Node(item.depth + 1u, item.id * 2u));
//!          enqueue_Grow(Node(item.depth + 1u, item.id * 2u + 1u));
//!      }",
//! ));
//! graph.connect_with_fan_out(&grow, &grow, 2);
//! let compiled = graph.compile(&CompileOptions::default())?;
//!
//! let gpu = Gpu::new(&Default::default())?;
//! let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &ExecutorConfig::default())?;
//! let report = executor.run(&Seeds::new().add(&grow, &[Node { depth: 0, id: 1 }]), &[])?;
//! assert_eq!(report.procedure(&grow).unwrap().executed, 2047);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! [`Graph::procedure`] returns a [`ProcedureId`] typed by the item, so seeds
//! of the wrong type do not compile; see [`Item`] for the derive and the
//! layouts it accepts, and [`Graph::constant`] for host values.
//!
//! # The body contract
//!
//! A body is the text of a WGSL function. **Every** thread of the workgroup
//! calls it, once per chunk of the batch, whether it has an item or not:
//!
//! | parameter | type | meaning |
//! |---|---|---|
//! | `item` | the item type | this thread's item (zeroed when `valid` is false) |
//! | `valid` | `bool` | whether this thread has an item in this chunk; the last chunk of a batch may be partly filled |
//! | `thread` | `u32` | the thread's index within its item, `0..threads_per_item` |
//! | `slot` | `u32` | the item's slot in the workgroup, `0..workgroup_size / threads_per_item`; the threads of one slot share an item and are all valid or all invalid |
//!
//! - **Barriers** (`workgroupBarrier`, `storageBarrier`,
//!   `workgroupUniformLoad`) and the item-wide helpers below, which contain
//!   barriers, are allowed only at the body's **top level**: never inside a
//!   branch or loop on `valid`, `thread`, `slot` or data. Every thread must
//!   reach each of them the same number of times. naga does not check this.
//! - Consecutive calls are separated by a workgroup barrier, so scratch and
//!   the body's own workgroup variables may be reused from call to call.
//! - `enqueue_<Target>(item)` may be called from any thread, under any
//!   condition, up to the declared fan-out; the items are published when the
//!   batch ends.
//! - `join_open_<Continuation>(record)`, in a procedure declared with
//!   [`Graph::join`], opens a join: the thread's enqueues from then on (and
//!   all their descendants) are its children, and once the last of them has
//!   finished, `record` is enqueued into the continuation, exactly once.
//!
//! # Runtime helpers
//!
//! **Scratch**, per item slot, in workgroup memory:
//!
//! - typed, with [`Procedure::scratch::<S>()`](Procedure::scratch): the body
//!   gets `scratch`, a `ptr<workgroup, S>` to its slot's value
//!   (`scratch.total = 0u;`);
//! - untyped, with [`Procedure::scratch_bytes`]: `scratch_load_u32(slot,
//!   index)`, `scratch_store_u32(slot, index, value)` and the `_i32`/`_f32`
//!   variants read and write the slot's `scratch_bytes / 4` words (an index
//!   beyond them is clamped into the slot's own words).
//!
//! **Item-wide helpers**: each thread of an item passes a value and every
//! thread of the item gets the result.
//!
//! | helper | result |
//! |---|---|
//! | `item_min_u32`, `item_min_i32`, `item_min_f32` | the minimum |
//! | `item_max_u32`, `item_max_i32`, `item_max_f32` | the maximum |
//! | `item_sum_u32`, `item_sum_i32`, `item_sum_f32` | the sum (integers wrap; `f32` adds in a fixed tree order: pairs `threads_per_item / 2` apart, then half that, down to 1) |
//! | `item_all_equal_u32(value) -> bool` | whether every thread passed the same value |
//! | `item_all(condition)`, `item_any(condition)` | whether the condition holds in every, or in some, thread |
//! | `item_broadcast_u32`, `item_broadcast_i32`, `item_broadcast_f32` | thread 0's value |
//!
//! They contain workgroup barriers, so **every thread of the workgroup**
//! calls them at the top level of the body, with or without an item, in the
//! same order. Threads without an item reduce among themselves (an item's
//! threads are all valid or all invalid): they never change another item's
//! result, need not pass a neutral value, and their own result is
//! meaningless. The helpers and their workgroup array (one word per thread:
//! 4 × `workgroup_size` bytes) are added to the module only when a body or
//! the library calls one. With one thread per item they return the value
//! itself.
//!
//! ```no_run
//! # use scheduler::Procedure;
//! # #[scheduler::item] struct Row { index: u32 }
//! # let mut graph = scheduler::Graph::new("rows");
//! graph.resource(scheduler::Resource::storage::<[f32]>("rows"));
//! graph.procedure(Procedure::of::<Row>("Normalize").initial(true).threads_per_item(32).body(
//!     "var value = 0.0;
//!      if (valid) { value = rows[item.index * 32u + thread]; }
//!      let total = item_sum_f32(value);      // top level: every thread calls it
//!      if (valid) { rows[item.index * 32u + thread] = value / total; }",
//! ));
//! ```
//!
//! See `docs/scheduler.md` for the queue protocol and the arguments for
//! termination and race freedom.

// The derives name `::scheduler`, which must also resolve inside this crate
// (its unit tests derive items).
extern crate self as scheduler;

mod adapter;
mod codegen;
mod compile;
mod constant;
mod error;
mod graph;
mod handle;
mod item;
mod naming;
mod options;
mod plan;
mod quirks;
mod resource;
mod runtime;
mod uncaptured;

pub use adapter::{DeviceRequest, Gpu};
pub use compile::diagnostics::validation_capabilities;
pub use compile::{CompiledGraph, Specialization};
pub use constant::ConstantValue;
pub use error::{CompileError, DeviceError, SourceOrigin};
pub use graph::{Connection, DEFAULT_PRIORITY, Graph, Join, Procedure};
pub use handle::{ProcedureId, Untyped};
pub use item::{Item, ItemType, WgslStructs, WgslType, layout as wgsl_layout};
pub use options::{
    CompileOptions, MAX_CHUNKS_PER_BATCH, Policy, TraceOptions, recommended_features,
};
pub use plan::QueuePlan;
pub use quirks::{CpuWorkgroups, DEFAULT_SPIN_LIMIT, LoopBudget, PersistentThreads, Quirks};
pub use resource::{Access, Atomic, BufferContents, BufferShape, Resource, ResourceKind};
pub use runtime::config::{
    Capacities, DEFAULT_CAPACITY, DEFAULT_JOIN_POOL, DEFAULT_TIMEOUT, DEFAULT_WORKGROUPS,
    ExecutorConfig, MemoryPlan,
};
pub use runtime::error::RunError;
pub use runtime::executor::{Binding, Executor};
pub use runtime::pipeline_cache::{self, CompileTimings, PipelineCacheState};
pub use runtime::readback;
pub use runtime::report::{
    BoundsViolation, FanOutViolation, JoinPoolStats, JoinStats, ProcedureStats, RetryCauses,
    RunReport,
};
pub use runtime::reset::ResetContext;
pub use runtime::retry::{LoopCheckFn, ResetFn, Retry};
pub use runtime::seeds::Seeds;
pub use runtime::strategy::{DEFAULT_ROUNDS_PER_BATCH, Strategy};
pub use runtime::trace::{BatchRecord, SubmissionTrace, Trace};
pub use scheduler_derive::{Item, item};
pub use uncaptured::UncapturedErrors;

// Re-exported so that users, the `item_type!` macro and `#[item]` name the
// same versions.
pub use bytemuck;
#[cfg(feature = "glam")]
pub use glam;
pub use wgpu;
