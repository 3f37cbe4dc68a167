//! `SKIP_GPU_TESTS=1` becomes the `skip_gpu_tests` cfg, so that every GPU
//! test can be marked `#[cfg_attr(skip_gpu_tests, ignore = ...)]` and a
//! deliberate skip shows as `ignored` in the test summary, never as a pass.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(skip_gpu_tests)");
    println!("cargo::rerun-if-env-changed=SKIP_GPU_TESTS");
    if std::env::var("SKIP_GPU_TESTS").is_ok_and(|v| v == "1") {
        println!("cargo::rustc-cfg=skip_gpu_tests");
    }
}
