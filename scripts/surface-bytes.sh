#!/usr/bin/env bash
# Byte-for-byte comparison of two octsolid binaries' smooth surfaces: the classic
# CSG part (from its .oct file and as a difference of two saved files), the bundled
# scenes and the models, each exported unsimplified and simplified at several
# tolerances by both; prints one line a file and fails on the first difference. For
# changes to the surface extraction (dual contouring, untangling, the cell merge, the
# simplifier) that must not change its output.
#
#   scripts/surface-bytes.sh OLD_OCTSOLID NEW_OCTSOLID [DEPTH] [TOLERANCES]
#
# DEPTH (default 8) is the depth of the part, the scenes' shape solids and the
# models; TOLERANCES (default "0 0.04 0.3 1") the `--tolerance` values, in voxels.
set -euo pipefail
old=$(realpath "${1:?old octsolid binary}"); new=$(realpath "${2:?new octsolid binary}")
depth=${3:-8}; tolerances=${4:-0 0.04 0.3 1}
repo=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
export OCTSOLID_PROGRESS_SECONDS=1000000
inputs=()
"$new" build "$repo/benches/peers/surface_classic.toml" --depth "$depth" -o part.oct >/dev/null
"$new" build "$repo/benches/peers/surface_classic_operands.toml" --depth "$depth" --solid body -o body.oct >/dev/null
"$new" build "$repo/benches/peers/surface_classic_operands.toml" --depth "$depth" --solid bores -o bores.oct >/dev/null
"$new" csg difference body.oct bores.oct -o part-csg.oct >/dev/null
inputs+=(part.oct part-csg.oct)
for scene in "$repo"/scenes/*.toml; do
  name=$(basename "$scene" .toml)
  if "$new" build "$scene" --depth "$depth" -o "scene-$name.oct" >/dev/null 2>&1; then
    inputs+=("scene-$name.oct")
  fi
done
for model in "$repo"/models/*.obj; do
  name=$(basename "$model" .obj)
  "$new" voxelize "$model" --depth "$depth" -o "model-$name.oct" >/dev/null
  inputs+=("model-$name.oct")
done
for input in "${inputs[@]}"; do
  for tolerance in $tolerances; do
    out="${input%.oct}-$tolerance.obj"
    "$old" export "$input" -o "old-$out" --tolerance "$tolerance" >/dev/null
    "$new" export "$input" -o "new-$out" --tolerance "$tolerance" >/dev/null
    cmp "old-$out" "new-$out"
    echo "same: $out"
  done
done
