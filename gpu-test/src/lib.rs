//! The workspace's GPU test harness, after wgpu's own (`gpu_test`,
//! `FailureCase`). Its contract:
//!
//! - **A GPU test is marked `#[gpu_test]`**, never `#[test]` alone. The
//!   attribute adds `#[test]` and, under the `skip_gpu_tests` cfg, `#[ignore]`.
//!   That cfg comes from `SKIP_GPU_TESTS=1` (the one switch for the whole
//!   workspace) through the crate's build script, which calls
//!   [`build::skip_gpu_tests_cfg`]: a deliberate skip shows as `ignored` in
//!   the summary, never as a pass.
//! - **Without an adapter a GPU test fails**: [`gpu`], the device every GPU
//!   test shares, panics when none can be had.
//! - **A driver a test is known to fail on is declared, not branched on**:
//!   `#[gpu_test(expect_fail(driver = "llvmpipe", message = "...", reason =
//!   "..."))]` (a [`FailureCase`]). On an adapter a case covers, the test
//!   must panic with the declared message; a pass there, or a panic with
//!   another message, fails it. Elsewhere it runs as a plain test.
//! - **On GL the tests take turns**: wgpu's GL backend makes every call
//!   under one lock on the adapter's context and panics when a thread waits
//!   for it over a second, so on a GL adapter each `#[gpu_test]` holds a
//!   process-wide lock while it runs (`WGPU_BACKEND=gl` runs the tests on
//!   GL; docs/scheduler.md, "Portability").
//! - **Where a driver chooses between two valid outcomes**, the test asks
//!   [`expect`] which one to check (`expect(gpu).loops_capped()`) instead of
//!   deciding from adapter names itself.
//!
//! ```text
//! use gpu_test::gpu_test;
//!
//! #[gpu_test]
//! fn runs_anywhere(gpu: &scheduler::Gpu) { /* ... */ }
//!
//! #[gpu_test(expect_fail(driver = "llvmpipe", message = "loop limit", reason = "llvmpipe caps loops"))]
//! fn long_loops_finish() { /* ... */ }
//! ```
//!
//! Build scripts take the crate with `default-features = false`: then it is
//! [`build`] alone, without the device (and wgpu) behind the `harness`
//! feature.

pub mod build;

#[cfg(feature = "harness")]
mod device;
#[cfg(feature = "harness")]
mod driver;
#[cfg(feature = "harness")]
mod failure_case;
#[cfg(feature = "harness")]
mod test_run;

#[cfg(feature = "harness")]
pub use device::gpu;
#[cfg(feature = "harness")]
pub use driver::{DriverBehaviour, expect};
#[cfg(feature = "harness")]
pub use failure_case::FailureCase;
#[cfg(feature = "harness")]
pub use gpu_test_macros::gpu_test;
#[cfg(feature = "harness")]
pub use test_run::GpuTest;
