#!/usr/bin/env bash
# The scheduler's GPU tests again on a second backend: wgpu's GL backend on
# Mesa's llvmpipe (OpenGL 4.5 through EGL, headless), with naga's GLSL
# writer instead of its SPIR-V one (docs/scheduler.md, "Portability").
# Differences are declared per backend in the tests
# (`#[gpu_test(expect_fail(backend = "gl", ...))]`), never skipped.
#
# GL offers no 64-bit atomics, so the Reyes renderer takes its two-pass
# 32-bit depth test there. With GL_REYES=1 a Reyes test (every standard
# surface and light against the CPU reference) runs on GL too, and the
# default frame is compared between the backends. It is not run by default:
# with an empty shader cache llvmpipe's GL takes 19 minutes or more to
# compile the Reyes megakernel on a 2-core machine (docs/scheduler.md,
# "Portability"), half of CI's budget; with the cache, seconds.
set -euo pipefail
cd "$(dirname "$0")/.."

tests=(
    scheduler_gpu strategies_gpu examples_gpu random_graphs_gpu failures_gpu
    joins_gpu checked_gpu fan_out_gpu item_helpers_gpu typed_resources_gpu
    trace_gpu round_kernels_gpu scheduler_defaults_gpu retry_growth_gpu
    pipeline_cache_gpu harness_gpu
)
args=()
for test in "${tests[@]}"; do
    args+=(--test "$test")
done
# The harness names the adapter it runs on: make sure it is GL, not a
# fallback.
adapter=$(WGPU_BACKEND=gl cargo test --release -p tests --test harness_gpu -- --nocapture 2>&1 |
    grep -m1 "GPU tests run on" || true)
echo "$adapter"
case "$adapter" in
    *", Gl,"*) ;;
    *) echo "the GL backend did not run the tests (WGPU_BACKEND=gl)" >&2; exit 1 ;;
esac
# Two random graphs per test instead of four: the Vulkan run draws four
# more, and GL takes twice as long per graph (docs/performance.md).
RANDOM_GRAPH_CASES=2 WGPU_BACKEND=gl cargo test --release -p tests "${args[@]}"

if [ "${GL_REYES:-0}" != 1 ]; then
    echo "the Reyes renderer's GL checks were not run (19 minutes or more with a cold shader cache): GL_REYES=1 .ci/gl-tests.sh runs them"
    exit 0
fi
RANDOM_GRAPH_CASES=2 WGPU_BACKEND=gl cargo test --release -p tests --test reyes_surfaces_gpu

# The default Reyes frame on both backends: Vulkan keeps each sample's
# nearest surface with 64-bit atomics from naga's SPIR-V, GL with the
# two-pass 32-bit test from naga's GLSL. The linear floats (EXR) and the
# encoded image (PNG) must be the same bytes.
reyes=target/release/reyes
[ -x "$reyes" ] || cargo build --release -p reyes
frames=$(mktemp -d)
trap 'rm -rf "$frames"' EXIT
for backend in vulkan gl; do
    for format in exr png; do
        WGPU_BACKEND=$backend "$reyes" render -o "$frames/$backend.$format" >/dev/null
    done
done
for format in exr png; do
    if ! cmp "$frames/vulkan.$format" "$frames/gl.$format"; then
        echo "the default frame differs between Vulkan and GL ($format)" >&2
        exit 1
    fi
done
echo "the default Reyes frame is byte-identical on Vulkan and GL (EXR and PNG)"
