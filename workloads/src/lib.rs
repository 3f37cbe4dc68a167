//! The scheduler's example workloads, shared by the examples
//! (`scheduler/examples/`), the workspace tests and the benchmarks: each
//! module holds a workload's item types, parameters, graph builder, CPU
//! reference and a checked GPU run that compares the two exactly.
//!
//! * [`mandelbrot`]: the Mandelbrot set by Mariani–Silver subdivision, two
//!   procedures of different widths;
//! * [`quadrature`]: adaptive Simpson quadrature in fixed point, one
//!   recursive procedure;
//! * [`bfs`]: breadth-first search levels, two procedures enqueueing each
//!   other;
//! * [`tree_sum`]: a hierarchical sum over a random tree built top-down and
//!   summed bottom-up with joins in the same run.

pub mod bfs;
mod checked;
pub mod mandelbrot;
pub mod quadrature;
pub mod tree_sum;

pub use checked::Checked;
