#!/usr/bin/env bash
# POV-Ray 3.7 renders whitted_classic.pov (the scene of scenes/whitted-classic.toml)
# at 800x600 on both cores (+WT2), with adaptive anti-aliasing (+A0.3 +R3), with
# recursive adaptive anti-aliasing (+A0.3 +AM2 +R3 -J: method 2, unjittered) and
# without, and prints one JSON line each: median wall seconds of RUNS renders, and
# POV-Ray's own trace seconds and ray count from its statistics. The pictures go to
# OUT_DIR (povray-aa.png, povray-am2.png, povray-noaa.png).
#
#   benches/peers/povray_whitted.sh [RUNS=3] [OUT_DIR=target/peers] [WIDTHxHEIGHT=800x600]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
runs=${1:-3}
out=${2:-$root/target/peers}
size=${3:-800x600}
width=${size%x*}
height=${size#*x}
command -v povray >/dev/null || { echo "povray_whitted: povray is missing (benches/peers/setup.sh)" >&2; exit 1; }
mkdir -p "$out"
log=$(mktemp)
trap 'rm -f "$log"' EXIT
version=$(povray --version 2>&1 | grep -m1 -oE 'POV-Ray [0-9.]*[0-9]' | cut -d' ' -f2)

render() { # name, AA options...
    local name=$1
    shift
    local times=()
    for _ in $(seq "$runs"); do
        local start
        start=$(date +%s%N)
        # -D: no preview window; +FN: PNG; -V: no progress lines (the statistics stay).
        povray "+I$here/whitted_classic.pov" "+O$out/povray-$name.png" +FN "+W$width" "+H$height" \
            +WT2 -D -V "$@" >"$log" 2>&1 || { cat "$log" >&2; exit 1; }
        times+=($(( ($(date +%s%N) - start) / 1000000 )))
    done
    local median
    median=$(printf '%s\n' "${times[@]}" | sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : int((a[NR/2] + a[NR/2+1]) / 2)}')
    local trace rays
    trace=$(grep -m1 -oE 'Trace Time:.*\([0-9.]+ seconds\)' "$log" | grep -oE '\([0-9.]+ seconds' | tr -d '(' | cut -d' ' -f1)
    rays=$(grep -m1 -oE 'Rays: +[0-9]+' "$log" | grep -oE '[0-9]+')
    printf '{"peer": "povray", "version": "%s", "scene": "whitted_classic.pov", "size": [%d, %d], "threads": 2, "aa": "%s", "runs": %d, "median_wall_s": %d.%03d, "trace_s": %s, "rays": %s, "image": "%s"}\n' \
        "$version" "$width" "$height" "$*" "$runs" $((median / 1000)) $((median % 1000)) "${trace:-null}" "${rays:-null}" "$out/povray-$name.png"
}

render aa +A0.3 +R3
render am2 +A0.3 +AM2 +R3 -J
render noaa -A
