//! `SKIP_GPU_TESTS=1` marks every `#[gpu_test]` test ignored (`gpu_test::build`);
//! `SKIP_SHADER_TOOLS=1` marks ignored the test that runs `spirv-val` and
//! `glslangValidator` on the translated modules (tests/shader_languages.rs).

fn main() {
    gpu_test::build::skip_gpu_tests_cfg();
    println!("cargo::rustc-check-cfg=cfg(skip_shader_tools)");
    println!("cargo::rerun-if-env-changed=SKIP_SHADER_TOOLS");
    if std::env::var("SKIP_SHADER_TOOLS").as_deref() == Ok("1") {
        println!("cargo::rustc-cfg=skip_shader_tools");
    }
}
