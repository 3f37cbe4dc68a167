//! The build-script half of the harness: `SKIP_GPU_TESTS=1` becomes the
//! `skip_gpu_tests` cfg that `#[gpu_test]` turns into `#[ignore]`.

/// The environment variable that skips every GPU test of the workspace.
pub const SKIP_VARIABLE: &str = "SKIP_GPU_TESTS";

/// Declares the `skip_gpu_tests` cfg and sets it when `SKIP_GPU_TESTS=1`.
/// A crate with `#[gpu_test]` tests calls it from its build script.
pub fn skip_gpu_tests_cfg() {
    println!("cargo::rustc-check-cfg=cfg(skip_gpu_tests)");
    println!("cargo::rerun-if-env-changed={SKIP_VARIABLE}");
    if skipping(std::env::var(SKIP_VARIABLE).ok().as_deref()) {
        println!("cargo::rustc-cfg=skip_gpu_tests");
    }
}

/// Whether the variable's value asks to skip: exactly `1`.
fn skipping(value: Option<&str>) -> bool {
    value == Some("1")
}

#[cfg(test)]
mod tests {
    use super::skipping;

    #[test]
    fn only_one_skips() {
        assert!(skipping(Some("1")));
        for other in [None, Some(""), Some("0"), Some("true"), Some(" 1")] {
            assert!(!skipping(other), "{other:?}");
        }
    }
}
