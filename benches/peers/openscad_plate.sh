#!/usr/bin/env bash
# OpenSCAD (Debian's, 2021.01: CGAL Nef polyhedra) renders plate.scad to STL under a
# time limit, and prints one JSON line: finished or not, wall seconds, the STL's size.
#
#   benches/peers/openscad_plate.sh [TIMEOUT_S=60] [GRID=20]
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
limit=${1:-60}
grid=${2:-20}
command -v openscad >/dev/null || { echo "openscad_plate: openscad is missing (benches/peers/setup.sh)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
version=$(openscad --version 2>&1 | grep -oE '[0-9]{4}\.[0-9.]+' | head -1)
start=$(date +%s%N)
timeout "$limit" openscad -q -D "grid=$grid" -o "$out/plate.stl" "$here/plate.scad" >"$out/log" 2>&1
status=$?
ms=$(( ($(date +%s%N) - start) / 1000000 ))
if [ $status -eq 124 ]; then
    printf '{"peer": "openscad", "version": "%s", "model": "plate", "holes": %d, "finished": false, "timeout_s": %s, "note": "did not finish in %s s"}\n' \
        "$version" $((grid * grid)) "$limit" "$limit"
elif [ $status -ne 0 ]; then
    echo "openscad_plate: openscad failed (exit $status):" >&2
    cat "$out/log" >&2
    exit 1
else
    facets=$(grep -c '^ *facet normal' "$out/plate.stl" || true)
    printf '{"peer": "openscad", "version": "%s", "model": "plate", "holes": %d, "finished": true, "seconds": %d.%03d, "triangles": %d}\n' \
        "$version" $((grid * grid)) $((ms / 1000)) $((ms % 1000)) "$facets"
fi
