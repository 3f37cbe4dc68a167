#!/usr/bin/env bash
# Renders the same frames with two builds of the `reyes` binary and checks
# that they agree byte for byte: the images, and the statistics apart from
# the frame time. For refactors that must not change behaviour.
#
#   benches/compare-renders.sh OLD_REYES NEW_REYES [OUT_DIR]
#
# The frames: the default teapot on the GPU and the CPU, the Killeroo
# (../shared/data/killeroo.bpt, skipped with a notice when absent) at spp 4
# and 1, three blurred frames (Interleave UVT, Adaptive and INTERVAL with
# spin and aperture), nearest and Simple UVT, the grids, depth and normal
# AOVs, fixed dicing, flat shading on one-sided objects, and displacement.
# COMPARE_ONLY=teapot,killeroo-cpu limits the run to the frames named.
# Exits non-zero when any frame differs or fails to render.
set -uo pipefail
old=${1:?usage: compare-renders.sh OLD_REYES NEW_REYES [OUT_DIR]}
new=${2:?usage: compare-renders.sh OLD_REYES NEW_REYES [OUT_DIR]}
out=${3:-$(mktemp -d)}
killeroo="$(dirname "$0")/../../shared/data/killeroo.bpt"

frames=(
    "teapot|"
    "teapot-cpu|--cpu"
    "blur-interleave|--sampling interleave --spin 30 --aperture 0.15 --spp 16"
    "blur-interleave-cpu|--sampling interleave --spin 30 --aperture 0.15 --spp 16 --cpu"
    "blur-adaptive|--sampling adaptive --spin 30 --aperture 0.15 --spp 16"
    "blur-interval|--sampling interval --spin 30 --spp 16"
    "nearest|--sampling nearest"
    "simple|--sampling simple --spin 10 --spp 4"
    "grids|--aov grids --shading-rate 4"
    "depth|--aov depth"
    "normal|--aov normal --dicing fixed"
    "flat|--flat-shading --sides 1"
    "displaced|--displace bumps --displace-scale 0.1"
    "displaced-cpu|--displace bumps --displace-scale 0.1 --cpu"
)
if [ -f "$killeroo" ]; then
    frames+=("killeroo|$killeroo" "killeroo-cpu|$killeroo --cpu" "killeroo-spp1|$killeroo --spp 1")
else
    echo "notice: $killeroo is absent; the Killeroo frames are skipped"
fi

failed=0
for frame in "${frames[@]}"; do
    name=${frame%%|*}
    if [ -n "${COMPARE_ONLY:-}" ] && [[ ",$COMPARE_ONLY," != *",$name,"* ]]; then
        continue
    fi
    read -r -a args <<< "${frame#*|}"
    for build in old new; do
        bin=$old; [ "$build" = new ] && bin=$new
        mkdir -p "$out/$build"
        if ! "$bin" render "${args[@]}" -o "$out/$build/$name.png" \
            --stats-json "$out/$build/$name.json" > "$out/$build/$name.log" 2>&1; then
            echo "FAILED  $name ($build build; see $out/$build/$name.log)"
            failed=1
            continue 2
        fi
    done
    if ! cmp -s "$out/old/$name.png" "$out/new/$name.png"; then
        echo "DIFFERS $name: the images"
        failed=1
    elif ! cmp -s <(grep -v '"frame_time_ms"' "$out/old/$name.json") \
                  <(grep -v '"frame_time_ms"' "$out/new/$name.json"); then
        echo "DIFFERS $name: the statistics"
        failed=1
    else
        echo "same    $name"
    fi
done
[ "$failed" = 0 ] && echo "every frame is byte-identical (images and statistics)"
exit "$failed"
