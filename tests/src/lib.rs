//! Shared support for the workspace's tests.
//!
//! GPU tests are marked `#[gpu_test]` (the `gpu-test` crate, whose doc
//! states the contract) and take the shared device from [`gpu`]. Without an
//! adapter it **panics**, so a machine without a working driver fails loudly
//! instead of passing by skipping. `SKIP_GPU_TESTS=1` skips GPU tests
//! deliberately (the one switch for the whole workspace): the build script
//! turns it into the `skip_gpu_tests` cfg, under which `#[gpu_test]` marks
//! every GPU test ignored, so a skip shows as `ignored` in the summary. A
//! test's known failures on a driver are declared on its attribute
//! (`#[gpu_test(expect_fail(driver = "llvmpipe", ...))]`), and outcomes that
//! legitimately differ between drivers are asked of `gpu_test::expect`.

use scheduler::{Capacities, ExecutorConfig, Gpu};

/// The shared device for GPU tests ([`gpu_test::gpu`]).
///
/// # Panics
/// When no adapter or device can be had, and when GPU tests are skipped
/// (`SKIP_GPU_TESTS=1`) but the calling test was not marked `#[gpu_test]`:
/// a GPU test without the mark would otherwise pass without running.
pub fn gpu() -> &'static Gpu {
    if cfg!(skip_gpu_tests) {
        panic!("SKIP_GPU_TESTS=1, but this GPU test is not marked #[gpu_test]");
    }
    gpu_test::gpu()
}

/// A fresh random seed, printed so a failure can be replayed with
/// `TEST_SEED=<seed>`.
pub fn seed(test: &str) -> u64 {
    let seed = std::env::var("TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            use std::hash::{BuildHasher, RandomState};
            RandomState::new().hash_one(std::time::SystemTime::now())
        });
    eprintln!("{test}: seed {seed} (replay with TEST_SEED={seed})");
    seed
}

pub mod crack_scene;
pub mod generated_modules;
pub mod graphs;
pub mod random_graph;
pub mod reyes_support;
pub mod shapes;
pub mod watertight;

/// An executor configuration with `workgroups` persistent workgroups and
/// every queue holding `capacity` items.
pub fn config(workgroups: u32, capacity: u32) -> ExecutorConfig {
    ExecutorConfig {
        workgroups: Some(workgroups),
        capacities: Capacities::uniform(capacity),
        ..Default::default()
    }
}
