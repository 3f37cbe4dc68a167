//! The one device the GPU tests of a test binary share.

use std::sync::OnceLock;

use scheduler::{DeviceRequest, Gpu};

/// The shared device for GPU tests, with the optional 64-bit integer
/// features the tests use where the adapter has them.
///
/// # Panics
/// When no adapter or device can be had: a machine without a working
/// driver fails its GPU tests instead of passing them (`SKIP_GPU_TESTS=1`
/// skips them deliberately).
pub fn gpu() -> &'static Gpu {
    static GPU: OnceLock<Gpu> = OnceLock::new();
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
