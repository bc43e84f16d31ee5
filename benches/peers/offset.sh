#!/usr/bin/env bash
# Issue 39's offset targets in one sitting: `octsolid offset` against the `edt` package
# (PyPI `edt`: the dense exact Euclidean distance transform, one core, `parallel=1`;
# offset_edt.py) on the same solids, and OpenSCAD PR 6647's case on its own.
#
# 1. The classic CSG part at depth 9 in [-1.1, 1.1]^3 (voxel 2.2/512), built as
#    surface.sh builds it (`octsolid build surface_classic.toml -o part.oct`), grown by 10
#    voxels. Both sides get the same voxels: `convert part.oct part.binvox` (edt's input)
#    and back, `convert part.binvox part-voxels.oct` (octsolid's input, the band
#    transform over the cubes). The built part.oct also carries its surface section, so
#    `offset part.oct` measures along the true surface; that row is timed too.
# 2. The Stanford bunny (models/stanford-bunny.obj) voxelized at depth 9, grown by 10
#    voxels, the same two ways.
# 3. OpenSCAD PR 6647's case (offset_openscad_6647.toml): cube(10) minus sphere(6) at
#    depth 9 in a domain of edge 14, `offset --by 1`: the offset command alone and the
#    whole pipeline (build + offset); also the same voxels without the surface section
#    (`convert` to .binvox and back: the band transform over the cubes); its volume against offset_6647_volume.py (the exact
#    distance to the solid integrated on a grid).
#
# Times are medians of RUNS whole processes (wall clock, load and write included);
# each side's inner time (octsolid's "offset in", edt's transform) is given too.
# Prints Markdown tables.
#
#   benches/peers/setup.sh && cargo build --release -p octsolid-cli
#   benches/peers/offset.sh [RUNS=5] [OUT_DIR=target/peers/offset]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
runs=${1:-5}
out=${2:-$root/target/peers/offset}
mkdir -p "$out"
out=$(cd "$out" && pwd)
bin="$root/target/release/octsolid"
py="$root/target/peers-venv/bin/python"
[ -x "$bin" ] || { echo "offset.sh: build first: cargo build --release -p octsolid-cli" >&2; exit 1; }
"$py" -c 'import edt' 2>/dev/null || { echo "offset.sh: run benches/peers/setup.sh first (the venv with edt)" >&2; exit 1; }
export OCTSOLID_PROGRESS_SECONDS=1000000

# timed NAME CMD...: runs CMD RUNS times (stdout to $out/NAME.log, one per run, the
# inner times collected by $inner, a command reading the log), sets $median and
# $inner_median (seconds).
timed() {
    local name=$1
    shift
    local times=() inner=()
    log="$out/$name.log"
    for _ in $(seq "$runs"); do
        local start
        start=$(date +%s%N)
        "$@" >"$log"
        times+=($(( ($(date +%s%N) - start) / 1000000 )))
        [ -n "${inner_cmd:-}" ] && inner+=("$($inner_cmd "$log")")
    done
    median=$(printf '%s\n' "${times[@]}" | median_ms)
    inner_median=""
    [ ${#inner[@]} -gt 0 ] && inner_median=$(printf '%s\n' "${inner[@]}" | median_ms)
    return 0
}
median_ms() { sort -n | awk '{a[NR]=$1} END {m = (NR % 2) ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2; printf "%.2f", m / 1000}'; }
# The milliseconds of octsolid's "IN: offset in X ms" line, of edt.edt in offset_edt.py's JSON.
octsolid_inner() { awk '/: offset in / {print $(NF-1); exit}' "$1"; }
edt_inner() { /usr/bin/python3 -c 'import json,sys; print(json.loads(open(sys.argv[1]).read().splitlines()[-1])["edt_s"] * 1000)' "$1"; }
voxels_of() { "$bin" info "$1" | awk '/^voxels/ {print $2; exit}'; }
edt_voxels() { /usr/bin/python3 -c 'import json,sys; print(json.loads(open(sys.argv[1]).read().splitlines()[-1])["voxels_out"])' "$1"; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", a / b}'; }

cd "$out"
echo "load before: $(uptime)"
echo "edt $("$py" -c 'from importlib.metadata import version; print(version("edt"))'), numpy $("$py" -c 'import numpy; print(numpy.__version__)'), octsolid on $(nproc) cores, edt on 1"
echo

# grow_pair NAME: NAME.oct grown by 10 voxels: octsolid on NAME-voxels.oct (and on
# NAME.oct with its surface section, when it has one), edt on NAME.binvox; one table row each.
grow_pair() {
    local name=$1 label=$2
    "$bin" convert "$name.oct" "$name.binvox" >/dev/null
    "$bin" convert "$name.binvox" "$name-voxels.oct" >/dev/null
    inner_cmd=octsolid_inner timed "$name-octsolid" "$bin" offset "$name-voxels.oct" --voxels 10 -o "$name-grown.oct"
    local o=$median oi=$inner_median ov
    ov=$(voxels_of "$name-grown.oct")
    inner_cmd=edt_inner timed "$name-edt" "$py" "$here/offset_edt.py" "$name.binvox" --voxels 10 -o "$name-edt-grown.binvox"
    local e=$median ei=$inner_median ev
    ev=$(edt_voxels "$name-edt.log")
    echo "| $label, grown by 10 voxels | $o s ($oi s offset; $ov voxels) | $e s ($ei s edt.edt; $ev voxels) | $(ratio "$e" "$o")x |"
    if "$bin" info "$name.oct" | grep -q '^surface'; then
        inner_cmd=octsolid_inner timed "$name-octsolid-surface" "$bin" offset "$name.oct" --voxels 10 -o "$name-grown-surface.oct"
        echo "| the same along its surface section (\`offset $name.oct\`) | $median s ($inner_median s offset; $(voxels_of "$name-grown-surface.oct") voxels) | | $(ratio "$e" "$median")x |"
    fi
}

echo "Grown by 10 voxels at depth 9 (512^3): medians of $runs whole processes (load and write included)"
echo
echo "| workload | octsolid \`offset --voxels 10\` | edt (dense, 1 core) | edt / octsolid |"
echo "|---|---|---|---|"
"$bin" build "$here/surface_classic.toml" -o part.oct >/dev/null
grow_pair part "the classic part"
"$bin" voxelize "$root/models/stanford-bunny.obj" --depth 9 -o bunny.oct >/dev/null
grow_pair bunny "the Stanford bunny voxelized at depth 9"
echo

# OpenSCAD PR 6647.
echo "OpenSCAD PR 6647: cube(10) minus sphere(6), depth 9, domain edge 14, grown by a ball of radius 1; medians of $runs"
echo
inner_cmd="" timed pr6647-build "$bin" build "$here/offset_openscad_6647.toml" -o pr6647.oct
build_s=$median
inner_cmd=octsolid_inner timed pr6647-offset "$bin" offset pr6647.oct --by 1 -o pr6647-grown.oct
offset_s=$median offset_inner=$inner_median
"$bin" convert pr6647.oct pr6647.binvox >/dev/null
"$bin" convert pr6647.binvox pr6647-voxels.oct >/dev/null
inner_cmd=octsolid_inner timed pr6647-offset-voxels "$bin" offset pr6647-voxels.oct --by 1 -o pr6647-voxels-grown.oct
voxels_s=$median voxels_inner=$inner_median
pipeline() { "$bin" build "$here/offset_openscad_6647.toml" -o pr6647-p.oct && "$bin" offset pr6647-p.oct --by 1 -o pr6647-p-grown.oct; }
inner_cmd="" timed pr6647-pipeline pipeline
pipeline_s=$median
solid_volume=$("$bin" info pr6647.oct | awk '/^volume/ {print $2; exit}')
grown_volume=$("$bin" info pr6647-grown.oct | awk '/^volume/ {print $2; exit}')
oracle=$("$py" "$here/offset_6647_volume.py" --radius 1)
exact_solid=$(echo "$oracle" | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["solid"])')
exact_grown=$(echo "$oracle" | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["grown"])')
bound=$(echo "$oracle" | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["cube_grown_bound"])')
err() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%+.3f%%", 100 * (a - b) / b}'; }
echo "| step | median | volume | exact | error |"
echo "|---|---|---|---|---|"
echo "| \`build offset_openscad_6647.toml -o pr6647.oct\` | $build_s s | $solid_volume | $exact_solid | $(err "$solid_volume" "$exact_solid") |"
echo "| \`offset pr6647.oct --by 1 -o pr6647-grown.oct\` | $offset_s s ($offset_inner s offset) | $grown_volume | $exact_grown (grid, offset_6647_volume.py) | $(err "$grown_volume" "$exact_grown") |"
echo "| the same without the surface section (\`offset pr6647-voxels.oct --by 1\`, over the cubes) | $voxels_s s ($voxels_inner s offset) | $("$bin" info pr6647-voxels-grown.oct | awk '/^volume/ {print $2; exit}') | $exact_grown | $(err "$("$bin" info pr6647-voxels-grown.oct | awk '/^volume/ {print $2; exit}')" "$exact_grown") |"
echo "| build + offset (the pipeline) | $pipeline_s s | | cube(10) grown by 1, the upper bound: $bound | |"
echo
echo "load after: $(uptime)"
