//! `SKIP_GPU_TESTS=1` marks every `#[gpu_test]` test ignored (`gpu_test::build`).

fn main() {
    gpu_test::build::skip_gpu_tests_cfg();
}
