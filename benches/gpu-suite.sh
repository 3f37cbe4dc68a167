#!/usr/bin/env bash
# Every benchmark of the workspace, sized to finish in under 10 minutes on
# a real GPU, into one markdown report: `benches/gpu-suite.sh [OUT.md]`
# (default: gpu-suite.md in the current directory). Each benchmark prints
# its own markdown or text table; the report holds them in order, headed by
# the device and the commands, so it can be pasted into docs/performance.md.
# The Killeroo rows need ../shared/data/killeroo.bpt beside the workspace.
# On a machine without a Rust toolchain, build the benches elsewhere, copy
# them into target/release and set GPU_SUITE_PREBUILT=1 to skip the build.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-gpu-suite.md}
if [ "${GPU_SUITE_PREBUILT:-0}" != 1 ]; then
    cargo build --release -p benches --bins >&2
fi

# A benchmark that fails (a wrong result, a missed acceptance check) is
# recorded with its last error line and the suite goes on, so one failure
# does not cost the rest of a run on a borrowed machine.
status=0
run_bench() {
    local err
    err=$(mktemp)
    if ! "./target/release/$@" 2>"$err"; then
        echo "FAILED: $(tail -n 1 "$err")"
        status=1
    fi
    rm -f "$err"
}

# A benchmark whose output is markdown already.
markdown() {
    echo
    echo "#### \`$*\`"
    run_bench "$@"
}

# A benchmark that prints a text table.
text() {
    echo
    echo "#### \`$*\`"
    echo
    echo '```text'
    run_bench "$@"
    echo '```'
}

{
    echo "# GPU suite, $(date -u +%Y-%m-%d), $(uname -n)"
    markdown reyes-bench --frames 5 --spp 1,16 --resolutions 800x600,1920x1080 --tables dicing,rates,interpolation,rounds
    # Look development: a textured Killeroo within 1.5x of plain plastic.
    markdown reyes-bench --frames 5 --resolutions 800x600 --tables materials
    markdown ste-bench --width 800 --height 600
    text strategy-bench --runs 5
    text scheduler-bench --runs 7
    text blur-bench --spp 16 --runs 3 --blurs motion,dof,both
    # Sattlecker and Steinberger's Table 1: Simple, bounding box and
    # Interleave UVT with tiles of 2, 3 and 4 pixels, at 16 and 64 spp.
    text blur-bench --spp 16,64 --runs 3 --blurs both --modes simple,bbox,interleave
    text blur-bench --spp 16,64 --runs 3 --blurs both --modes interleave --interleave-tile 3
    text blur-bench --spp 16,64 --runs 3 --blurs both --modes interleave --interleave-tile 4
    # Adaptive against INTERVAL and Interleave UVT, and on a mixed scene.
    text blur-bench --spp 16 --runs 5 --adaptive
    text blur-bench --spp 16 --runs 5 --blurs mixed --modes interval,interleave,adaptive
} > >(tee "$out")
echo "wrote $out" >&2
exit "$status"
