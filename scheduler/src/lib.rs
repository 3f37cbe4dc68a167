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
//! See `docs/scheduler.md` for the body contract, the queue protocol and the
//! arguments for termination and race freedom.

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
mod options;
pub mod readback;
mod runtime;

pub use adapter::{DeviceRequest, Gpu};
pub use compile::CompiledGraph;
pub use compile::plan::QueuePlan;
pub use constant::ConstantValue;
pub use error::{CompileError, DeviceError, RunError, SourceOrigin};
pub use graph::{Access, Connection, DEFAULT_PRIORITY, Graph, Procedure, Resource};
pub use handle::{ProcedureId, Untyped};
pub use item::{Item, ItemType, WgslStructs, WgslType, layout as wgsl_layout};
pub use options::{CompileOptions, MAX_CHUNKS_PER_BATCH, Policy, recommended_features};
pub use runtime::config::{
    CPU_CHUNK_BUDGET, CPU_ITERATION_BUDGET, CPU_SPIN_LIMIT, Capacities, DEFAULT_CAPACITY,
    DEFAULT_TIMEOUT, DEFAULT_WORKGROUPS, ExecutorConfig, MemoryPlan,
};
pub use runtime::executor::{Binding, Executor, ResetFn, Retry};
pub use runtime::report::{ProcedureStats, RunReport};
pub use runtime::seeds::Seeds;
pub use runtime::strategy::{DEFAULT_ROUNDS_PER_BATCH, Strategy};
pub use scheduler_derive::{Item, item};

// Re-exported so that users, the `item_type!` macro and `#[item]` name the
// same versions.
pub use bytemuck;
#[cfg(feature = "glam")]
pub use glam;
pub use wgpu;
