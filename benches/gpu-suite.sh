#!/usr/bin/env bash
# Every benchmark of the workspace, sized to finish in under 10 minutes on
# a real GPU, into one markdown report: `benches/gpu-suite.sh [OUT.md]`
# (default: gpu-suite.md in the current directory). Each benchmark prints
# its own markdown or text table; the report holds them in order, headed by
# the device and the commands, so it can be pasted into docs/performance.md.
# The Killeroo rows need ../shared/data/killeroo.bpt beside the workspace.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-gpu-suite.md}
cargo build --release -p benches --bins >&2

# A benchmark whose output is markdown already.
markdown() {
    echo
    echo "#### \`$*\`"
    "./target/release/$@" 2>/dev/null
}

# A benchmark that prints a text table.
text() {
    echo
    echo "#### \`$*\`"
    echo
    echo '```text'
    "./target/release/$@" 2>/dev/null
    echo '```'
}

{
    echo "# GPU suite, $(date -u +%Y-%m-%d), $(uname -n)"
    markdown reyes-bench --frames 5 --spp 1,16 --resolutions 800x600,1920x1080
    text strategy-bench --runs 5
    text scheduler-bench --runs 7
    text blur-bench --spp 16 --runs 3 --blurs motion,dof,both
} | tee "$out"
echo "wrote $out" >&2
