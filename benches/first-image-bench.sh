#!/usr/bin/env bash
# Time to the first image: how long `reyes render` takes from the command to
# the written PNG, cold (the driver's shader cache disabled and an empty
# pipeline cache) and warm (both caches filled by a previous run), next to
# the frame's GPU time and the CPU reference's time, for one or more builds
# of the `reyes` binary side by side. Run it with the machine otherwise idle.
#
#   benches/first-image-bench.sh REYES [REYES...]
#
# Frames: the default teapot, the Killeroo at 800x600 and spp 1
# (../shared/data/killeroo.bpt, skipped with a notice when absent) and a
# blurred frame (Interleave UVT with spin and aperture, spp 16).
# FIRST_IMAGE_KILLEROO=PATH reads the Killeroo elsewhere;
# FIRST_IMAGE_ONLY=teapot,blurred limits the frames; FIRST_IMAGE_RUNS (default
# 5) sets the warm runs (the median is reported); FIRST_IMAGE_COLD=0 skips the
# cold runs, which take minutes each on lavapipe.
#
# Columns: cold wall (s), warm wall (median, s), the driver's compile in the
# cold run and in the last warm one (pipeline creation plus the first
# dispatch, from the renderer's log; cold minus warm wall for builds that do
# not log it), the frame's GPU time (the megakernel's, from --stats-json, warm,
# ms), warm wall over GPU time, and `--cpu` wall (median, s). The module
# sizes of the variants are printed by
# `cargo test --release -p tests --test reyes_variants -- --nocapture`.
set -uo pipefail
[ $# -ge 1 ] || { echo "usage: first-image-bench.sh REYES [REYES...]" >&2; exit 2; }
runs=${FIRST_IMAGE_RUNS:-5}
cold=${FIRST_IMAGE_COLD:-1}
killeroo=${FIRST_IMAGE_KILLEROO:-"$(dirname "$0")/../../shared/data/killeroo.bpt"}
out=$(mktemp -d)

frames=(
    "teapot|"
    "blurred|--sampling interleave --spin 30 --aperture 0.15 --spp 16"
)
if [ -f "$killeroo" ]; then
    frames+=("killeroo|$killeroo --width 800 --height 600 --spp 1")
else
    echo "notice: $killeroo is absent; the Killeroo frame is skipped"
fi

# The value of an arithmetic expression of decimals (awk: no `bc` needed).
calc() {
    awk "BEGIN { printf \"%.6f\\n\", $1 }"
}

# Seconds (wall) of one run of "$@", or "fail".
wall() {
    local start end
    start=$(date +%s.%N)
    if ! "$@" > "$out/last.log" 2>&1; then
        echo fail
        return
    fi
    end=$(date +%s.%N)
    calc "$end - $start"
}

# "%.2f" of a number, or the text as it is ("-", "fail").
num() {
    if [[ "$1" =~ ^-?[0-9]*\.?[0-9]+$ ]]; then printf "%.${2:-2}f" "$1"; else printf '%s' "$1"; fi
}

# The driver compile the last run logged, in seconds, or "-".
driver_compile() {
    local s
    s=$(grep -o 'driver compile [0-9.]* s' "$out/last.log" | grep -o '[0-9.]*' | tail -1)
    echo "${s:--}"
}

median() {
    sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else print v[int((NR + 1) / 2)] }'
}

printf '| build | frame | cold wall s | cold driver compile s | warm wall s | warm driver compile s | frame GPU ms | warm / GPU | --cpu s |\n'
printf '|---|---|---|---|---|---|---|---|---|\n'
for frame in "${frames[@]}"; do
    name=${frame%%|*}
    if [ -n "${FIRST_IMAGE_ONLY:-}" ] && [[ ",$FIRST_IMAGE_ONLY," != *",$name,"* ]]; then
        continue
    fi
    read -r -a args <<< "${frame#*|}"
    for bin in "$@"; do
        cache=$(mktemp -d)
        png="$out/$name.png"
        cold_s="-"
        compile_s="-"
        if [ "$cold" = 1 ]; then
            # Mesa's and NVIDIA's own shader caches off, an empty pipeline cache.
            cold_s=$(wall env MESA_SHADER_CACHE_DISABLE=true __GL_SHADER_DISK_CACHE=0 REYES_CACHE_DIR="$cache" \
                RUST_LOG=reyes=info "$bin" render "${args[@]}" -o "$png")
            compile_s=$(driver_compile)
            if [ "$compile_s" = "-" ]; then compile_s=cold-warm; fi
        fi
        # Fill both caches, then time the warm runs.
        wall env REYES_CACHE_DIR="$cache" "$bin" render "${args[@]}" -o "$png" > /dev/null
        warm_s=$(for _ in $(seq "$runs"); do
            wall env REYES_CACHE_DIR="$cache" RUST_LOG=reyes=info "$bin" render "${args[@]}" \
                -o "$png" --stats-json "$out/$name.json"
        done | median)
        warm_compile_s=$(driver_compile)
        gpu_ms=$(grep -o '"frame_time_ms": *[0-9.]*' "$out/$name.json" 2>/dev/null \
            | grep -o '[0-9.]*$')
        gpu_ms=${gpu_ms:--}
        cpu_s=$(for _ in $(seq "$runs"); do
            wall "$bin" render "${args[@]}" --cpu -o "$png"
        done | median)
        ratio="-"
        if [ "$compile_s" = cold-warm ]; then
            compile_s="-"
            if [[ "$cold_s" =~ ^[0-9.]+$ && "$warm_s" =~ ^[0-9.]+$ ]]; then
                compile_s=$(calc "$cold_s - $warm_s")
            fi
        fi
        if [[ "$gpu_ms" =~ ^[0-9.]+$ && "$warm_s" =~ ^[0-9.]+$ ]]; then
            ratio=$(calc "$warm_s * 1000 / $gpu_ms")
        fi
        echo "| $(basename "$bin") | $name | $(num "$cold_s" 1) | $(num "$compile_s" 1) | $(num "$warm_s") | $(num "$warm_compile_s") | $(num "$gpu_ms" 0) | $(num "$ratio") | $(num "$cpu_s") |"
        rm -rf "$cache"
    done
done
rm -rf "$out"
