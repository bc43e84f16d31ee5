#!/usr/bin/env bash
# Whether a change to the offsets keeps their outputs: the .oct bytes of two octsolid
# binaries (before and after) on offset.sh's solids, compared file by file.
#
# Cases: the classic part at depth 9 (surface_classic.toml) as voxels grown and shrunk
# by 10 voxels, the same along its surface section grown by 10, OpenSCAD PR 6647's
# case (offset_openscad_6647.toml) grown by 1 along its surface and as voxels, and the
# hull of scenes/profiles.toml (the hull's surface queries).
#
#   cp target/release/octsolid before-octsolid   # at the old commit, built
#   benches/peers/offset_same_bytes.sh before-octsolid target/release/octsolid [OUT_DIR]
# Prints one line a case (same or DIFFERENT) and exits non-zero when any differs.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
[ $# -ge 2 ] || { echo "usage: offset_same_bytes.sh BEFORE_BINARY AFTER_BINARY [OUT_DIR]" >&2; exit 2; }
before=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
after=$(cd "$(dirname "$2")" && pwd)/$(basename "$2")
out=${3:-$root/target/peers/offset-bytes}
mkdir -p "$out"
cd "$out"
export OCTSOLID_PROGRESS_SECONDS=1000000

"$after" build "$here/surface_classic.toml" -o part.oct >/dev/null
"$after" convert part.oct part.binvox >/dev/null
"$after" convert part.binvox part-voxels.oct >/dev/null
"$after" build "$here/offset_openscad_6647.toml" -o pr6647.oct >/dev/null
"$after" convert pr6647.oct pr6647.binvox >/dev/null
"$after" convert pr6647.binvox pr6647-voxels.oct >/dev/null

differ=0
# case NAME ARGS...: runs `octsolid ARGS... -o NAME-{before,after}.oct` with each binary.
case_() {
    local name=$1
    shift
    "$before" "$@" -o "$name-before.oct" >/dev/null
    "$after" "$@" -o "$name-after.oct" >/dev/null
    if cmp -s "$name-before.oct" "$name-after.oct"; then
        echo "same       $name ($*)"
    else
        echo "DIFFERENT  $name ($*)"
        differ=1
    fi
}
case_ part-grown offset part-voxels.oct --voxels 10
case_ part-shrunk offset part-voxels.oct --voxels -10
case_ part-surface-grown offset part.oct --voxels 10
case_ pr6647-grown offset pr6647.oct --by 1
case_ pr6647-voxels-grown offset pr6647-voxels.oct --by 1
case_ hull build "$root/scenes/profiles.toml" --solid hull
exit $differ
