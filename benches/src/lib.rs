//! Benchmarks of the `scheduler` megakernel against a flat dispatch.
//!
//! The workload is a synthetic binary spawn tree (see [`workload`]): a single
//! root item spawns children until exactly `2^items_log2` items have run; each
//! item does a fixed number of integer-hash rounds and writes its result to
//! `out[id]`. The same per-item work over the same ids as one flat dispatch
//! (one thread per id, no queues) is the floor on scheduling overhead; the
//! ratio of the megakernel's items per second to the flat dispatch's is the
//! figure of merit.
//!
//! Both variants are timed on the device (GPU timestamps around the compute
//! pass, wall time around submit and wait where the device lacks
//! `TIMESTAMP_QUERY`), excluding pipeline creation and uploads, and every
//! benchmark run verifies both variants against a CPU reference.
//!
//! - [`workload`]: the item type, the WGSL constants and the CPU reference.
//! - [`flat`]: the flat compute pipeline.
//! - [`megakernel`]: the spawn-tree graph and its executor.
//! - [`gpu`]: small device helpers (buffers, waiting on wgpu futures).
//! - [`verify`]: reading `out` back and comparing it with the reference.
//! - [`timing`]: time sources and medians.
//! - [`suite`]: the whole comparison, producing [`suite::Row`]s.
//! - [`table`]: printing the rows.
//! - [`blur`]: the 5D sampling modes of the Reyes renderer (`blur-bench`).
//! - [`strategies`]: megakernel vs. Rounds under each policy, on the spawn
//!   tree; [`reyes_strategies`]: the same on Reyes frames.
//! - [`mandelbrot`]: the Mandelbrot example (Mariani–Silver subdivision)
//!   against a flat per-pixel dispatch (`scheduler-bench`).
//! - [`trace`]: a traced Mandelbrot run (`scheduler-bench --trace`) and
//!   the queue-fill charts of Chrome traces (`trace-plot`).

pub mod blur;
pub mod error;
pub mod flat;
pub mod gpu;
pub mod mandelbrot;
pub mod megakernel;
pub mod reyes_strategies;
pub mod strategies;
pub mod suite;
pub mod table;
pub mod timing;
pub mod trace;
pub mod verify;
pub mod workload;

pub use error::BenchError;
pub use suite::{BenchConfig, Row, SuiteReport, Variant, run_suite};
pub use workload::{SpawnItem, Workload};
