//! Shared support for the workspace's tests.
//!
//! GPU tests call [`gpu`]. Without an adapter it **panics**, so a machine
//! without a working driver fails loudly instead of passing by skipping. Set
//! `SKIP_GPU_TESTS=1` to skip GPU tests deliberately (the one switch for the
//! whole workspace): the build script turns it into the `skip_gpu_tests`
//! cfg, and every GPU test carries
//! `#[cfg_attr(skip_gpu_tests, ignore = "SKIP_GPU_TESTS=1")]`, so a skip shows
//! as `ignored` in the summary.

use std::sync::OnceLock;

use scheduler::{Capacities, DeviceRequest, ExecutorConfig, Gpu};

/// The shared device for GPU tests.
///
/// # Panics
/// When no adapter or device can be had, and when GPU tests are skipped
/// (`SKIP_GPU_TESTS=1`) but the calling test was not marked ignored: a GPU
/// test without the mark would otherwise pass without running.
pub fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
    if cfg!(skip_gpu_tests) {
        panic!(
            "SKIP_GPU_TESTS=1, but this GPU test is not marked \
             #[cfg_attr(skip_gpu_tests, ignore = \"SKIP_GPU_TESTS=1\")]"
        );
    }
    GPU.get_or_init(|| {
        let request = DeviceRequest {
            optional_features: scheduler::wgpu::Features::SHADER_INT64
                | scheduler::wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX,
            ..Default::default()
        };
        let gpu = Gpu::new(&request).unwrap_or_else(|e| {
            panic!(
                "GPU tests need an adapter ({e}); set SKIP_GPU_TESTS=1 to skip them deliberately"
            )
        });
        eprintln!("GPU tests run on: {}", gpu.describe());
        gpu
    })
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
