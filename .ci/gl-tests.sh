#!/usr/bin/env bash
# The scheduler's GPU tests again on a second backend: wgpu's GL backend on
# Mesa's llvmpipe (OpenGL 4.5 through EGL, headless), with naga's GLSL
# writer instead of its SPIR-V one (docs/scheduler.md, "Portability").
# Differences are declared per backend in the tests
# (`#[gpu_test(expect_fail(backend = "gl", ...))]`), never skipped. GL
# offers no 64-bit atomics, so the Reyes renderer takes its two-pass 32-bit
# depth test there: one Reyes test (every standard surface and light against
# the CPU reference) runs here.
set -euo pipefail
cd "$(dirname "$0")/.."

tests=(
    scheduler_gpu strategies_gpu examples_gpu random_graphs_gpu failures_gpu
    joins_gpu checked_gpu fan_out_gpu item_helpers_gpu typed_resources_gpu
    trace_gpu round_kernels_gpu scheduler_defaults_gpu retry_growth_gpu
    pipeline_cache_gpu harness_gpu reyes_surfaces_gpu
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
