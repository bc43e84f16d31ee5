#!/usr/bin/env bash
# Byte-for-byte comparison of two octsolid binaries' solid writers: the bundled
# scenes and models, and the .vox files of the tests, each written as .vox, .vdb,
# .binvox and .glb by both; prints one line a file and fails on the first difference.
# For changes to a writer that must not change its output.
#
#   scripts/writer-bytes.sh OLD_OCTSOLID NEW_OCTSOLID [DEPTH]
#
# DEPTH (default 8) is the depth the scenes' shape solids and the models are
# voxelized at.
set -euo pipefail
old=$(realpath "${1:?old octsolid binary}"); new=$(realpath "${2:?new octsolid binary}"); depth=${3:-8}
repo=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
cd "$work"
inputs=()
for scene in "$repo"/scenes/*.toml; do
  name=$(basename "$scene" .toml)
  # Scenes without shape solids (meshes, .oct leaves) are built whole at their own depth.
  if "$new" build "$scene" --depth "$depth" -o "scene-$name.oct" >/dev/null 2>&1 \
    || "$new" build "$scene" -o "scene-$name.oct" >/dev/null 2>&1; then
    inputs+=("scene-$name.oct")
  fi
done
for model in "$repo"/models/*.obj "$repo"/models/*.patches; do
  name=$(basename "$model"); name=${name%.*}
  "$new" voxelize "$model" --depth "$depth" -o "model-$name.oct" >/dev/null
  inputs+=("model-$name.oct")
done
for vox in "$repo"/tests/data/vox/*.vox; do
  cp "$vox" "data-$(basename "$vox")"
  inputs+=("data-$(basename "$vox")")
done
for input in "${inputs[@]}"; do
  for ext in vox vdb binvox glb; do
    out="${input%.*}.$ext"
    [ "${input##*.}" = "$ext" ] && out="${input%.*}-again.$ext"
    if "$old" convert "$input" "old-$out" >/dev/null 2>&1; then
      "$new" convert "$input" "new-$out" >/dev/null
      cmp "old-$out" "new-$out"
      echo "same  $out ($(stat -c %s "new-$out") bytes)"
      rm -f "old-$out" "new-$out"
    else
      echo "skip  $out (the old binary refuses it)"
    fi
  done
done
