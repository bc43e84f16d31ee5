#!/usr/bin/env bash
# Byte-for-byte comparison of two octsolid binaries' mesh outputs from every road a
# mesh leaves by besides `export`'s OBJ: `shape`, `build`, `voxelize` and `offset`
# writing .obj, .stl, .ply and .3mf, and `export` writing .glb (smooth, simplified and
# the staircase) and .3mf of a y-up model in inches; also their stdout and stderr
# (the summaries and warnings). Prints one line a file and fails on the first
# difference. For refactors of the mesh writers that must not change what they write.
#
#   scripts/mesh-outputs-bytes.sh OLD_OCTSOLID NEW_OCTSOLID
set -euo pipefail
old=$(realpath "${1:?old octsolid binary}"); new=$(realpath "${2:?new octsolid binary}")
repo=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
export OCTSOLID_PROGRESS_SECONDS=1000000
mkdir -p "$work/old" "$work/new"
run() { # run NAME ARGS...: both binaries, in their own folders, outputs and messages kept
  local name=$1; shift
  for side in old new; do
    local bin=$old; [ "$side" = new ] && bin=$new
    (cd "$work/$side" && "$bin" "$@" > "$name.out" 2> "$name.err" || echo "exit $?" >> "$name.err")
  done
}
for ext in obj stl ply 3mf; do
  run "shape-$ext" shape sphere --depth 6 -o "ball.$ext"
  run "build-$ext" build "$repo/benches/peers/surface_classic.toml" --depth 6 -o "part.$ext"
  run "voxelize-$ext" voxelize "$repo/models/bunny-watertight.obj" --depth 6 -o "bunny.$ext"
done
run shape-oct shape sphere --radius 1 --depth 6 --domain -1.05,-1.05,-1.05,2.1 -o tight.oct
run offset-obj offset tight.oct --by 0.3 -o grown.obj
run offset-empty offset tight.oct --by -5 -o gone.oct
run shape-far shape sphere --domain 5,5,5,1 -o far.oct
run shape-cut shape sphere --domain 0,0,0,1 -o cut.oct
run spot voxelize "$repo/models/spot.obj" --depth 6 --units in -o spot.oct
run export-glb export spot.oct -o spot.glb
run export-glb-simplified export tight.oct -o tight.glb --tolerance 0.3
run export-glb-voxels export spot.oct -o spot-voxels.glb --surface voxels
run export-3mf export spot.oct -o spot.3mf
for f in $(cd "$work/old" && ls | sort); do
  # Timings differ from run to run: lines with a time are left out of the messages.
  if [[ "$f" == *.out || "$f" == *.err ]]; then
    if ! diff <(grep -v " ms\| s)\|in [0-9.]* s\b" "$work/old/$f") <(grep -v " ms\| s)\|in [0-9.]* s\b" "$work/new/$f") > /dev/null; then
      echo "DIFFERS $f"; diff <(grep -v " ms" "$work/old/$f") <(grep -v " ms" "$work/new/$f") | head; exit 1
    fi
  elif ! cmp -s "$work/old/$f" "$work/new/$f"; then
    echo "DIFFERS $f"; exit 1
  fi
  echo "same    $f"
done
