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
//! use scheduler::{item_type, Binding, CompileOptions, Executor, ExecutorConfig, Graph, Gpu, Procedure, Seeds};
//!
//! #[repr(C)]
//! #[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
//! struct Node { depth: u32, id: u32 }
//!
//! let node = item_type!(Node, "struct Node { depth: u32, id: u32 }", [depth, id]);
//! let mut graph = Graph::new("binary tree");
//! graph.procedure(Procedure::new("Grow", node).initial(true).body(
//!     "if (valid && item.depth < 10u) {
//!          enqueue_Grow(Node(item.depth + 1u, item.id * 2u));
//!          enqueue_Grow(Node(item.depth + 1u, item.id * 2u + 1u));
//!      }",
//! ));
//! graph.connect_with_fan_out("Grow", "Grow", 2);
//! let compiled = graph.compile(&CompileOptions::default())?;
//!
//! let gpu = Gpu::new(&Default::default())?;
//! let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &ExecutorConfig::default())?;
//! let report = executor.run(&Seeds::new().add("Grow", &[Node { depth: 0, id: 1 }]), &[])?;
//! assert_eq!(report.procedure("Grow").unwrap().executed, 2047);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! See `docs/scheduler.md` for the body contract, the queue protocol and the
//! arguments for termination and race freedom.

mod adapter;
mod codegen;
mod compile;
mod error;
mod graph;
mod item;
mod options;
pub mod readback;
mod runtime;

pub use adapter::{DeviceRequest, Gpu};
pub use compile::CompiledGraph;
pub use compile::plan::QueuePlan;
pub use error::{CompileError, DeviceError, RunError, SourceOrigin};
pub use graph::{Access, Connection, DEFAULT_PRIORITY, Graph, Procedure, Resource};
pub use item::ItemType;
pub use options::{CompileOptions, MAX_CHUNKS_PER_BATCH, Policy, recommended_features};
pub use runtime::config::{
    CPU_CHUNK_BUDGET, CPU_ITERATION_BUDGET, CPU_SPIN_LIMIT, Capacities, DEFAULT_CAPACITY,
    DEFAULT_TIMEOUT, DEFAULT_WORKGROUPS, ExecutorConfig, MemoryPlan,
};
pub use runtime::executor::{Binding, Executor, ResetFn, Retry};
pub use runtime::report::{ProcedureStats, RunReport};
pub use runtime::seeds::Seeds;
pub use runtime::strategy::{DEFAULT_ROUNDS_PER_BATCH, Strategy};

// Re-exported so that users and the `item_type!` macro name the same versions.
pub use bytemuck;
pub use wgpu;
