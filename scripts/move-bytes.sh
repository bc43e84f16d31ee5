#!/usr/bin/env bash
# Byte-for-byte comparison of two octsolid binaries' moves of solids that carry
# surface data: `transform` (quarter and eighth turns, a scale, a target domain whose
# lattice does not nest) and `csg` of operands in other domains (fitted exactly, or
# made again from the smooth surface). Prints one line an output and fails on the
# first difference. For changes to the move and fit paths that must not change output.
#
#   scripts/move-bytes.sh OLD_OCTSOLID NEW_OCTSOLID [DEPTH]
#
# DEPTH (default 7) is the depth the solids are made at.
set -euo pipefail
old=$(realpath "${1:?old octsolid binary}"); new=$(realpath "${2:?new octsolid binary}"); depth=${3:-7}
repo=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
"$new" shape sphere --radius 1 --depth "$depth" -o ball.oct >/dev/null
"$new" shape box --size 1.6,1.6,1.6 --depth "$depth" --domain -1.05,-1.05,-1.05,2.1 -o cube.oct >/dev/null
"$new" shape torus --radius 0.7 --tube 0.25 --depth "$depth" -o ring.oct >/dev/null
"$new" build "$repo/scenes/gear.toml" --depth "$depth" -o gear.oct >/dev/null
"$new" voxelize "$repo/models/stanford-bunny.obj" --depth "$depth" -o bunny.oct >/dev/null
# Every output is written by both binaries; stdout (timings) is not compared.
same() {
  local out=$1; shift
  "$old" "$@" -o "old-$out" >/dev/null
  "$new" "$@" -o "new-$out" >/dev/null
  cmp "old-$out" "new-$out"
  echo "same  $out ($(stat -c %s "new-$out") bytes): $*"
}
for solid in ball cube ring gear bunny; do
  same "$solid-quarter.oct" transform "$solid.oct" --rotate z,90 --translate 0.1,0,0
  same "$solid-eighth.oct" transform "$solid.oct" --rotate z,45 --translate 0,0,1
  same "$solid-tilted.oct" transform "$solid.oct" --rotate x,30 --rotate y,20
  same "$solid-scaled.oct" transform "$solid.oct" --scale 1.5
  same "$solid-refined.oct" transform "$solid.oct" --rotate y,90 --depth $((depth + 1))
  same "$solid-offgrid.oct" transform "$solid.oct" --domain -1.013,-1.02,-1.007,2.1
  same "$solid-eighth.stl" transform "$solid.oct" --rotate z,45
done
same hollow.oct csg difference cube.oct ball.oct
same all3.oct csg union ball.oct cube.oct ring.oct
same cut.oct csg difference gear.oct ball.oct
same moved.oct csg intersect bunny.oct ball.oct --domain -1.1,-1.1,-1.1,2.2
