#!/usr/bin/env bash
# Writes every picture, .oct file and mesh that octsolid's bundled scenes, examples
# and CLI commands make into OUT_DIR, and OUT_DIR/MANIFEST: one sha256 a file plus
# the commands' printed summaries with their timings masked. A refactor must leave
# the manifest unchanged:
#
#   scripts/snapshot.sh /tmp/before      # on the old commit
#   scripts/snapshot.sh /tmp/after       # on the new one
#   diff /tmp/before/MANIFEST /tmp/after/MANIFEST
#
# Takes a few minutes (the Menger scene alone about 40 s on two cores).
set -euo pipefail
out=$(realpath -m "${1:?usage: scripts/snapshot.sh OUT_DIR}")
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet --bins --examples
bin="$root/target/release/octsolid"
rm -rf "$out"
mkdir -p "$out/work"
cd "$out/work"
ln -s "$root/models" models
log="$out/log.txt"
# Progress lines off a terminal come every few seconds, a count that varies: none here.
export OCTSOLID_PROGRESS_SECONDS=1000000

# Timings and rates differ run to run; everything else printed must not.
mask() { sed -E 's/[0-9]+(\.[0-9]+)? ?(ms|s|M rays\/s|M samples\/s|M input nodes\/s|µs)\b/<t>/g; s/in <t>/in <t>/g'; }
run() { echo "\$ octsolid $*" >>"$log"; "$bin" "$@" 2>&1 | mask >>"$log" || echo "exit $?" >>"$log"; }

# The README walkthrough, then every command kind with every option that changes bytes.
run shape sphere --radius 1 --depth 9 -o ball.oct
run shape box --size 1.6,1.6,1.6 --depth 9 --domain -1.05,-1.05,-1.05,2.1 -o cube.oct
run shape sphere --radius 1 --depth 9 --domain -1.05,-1.05,-1.05,2.1 -o ball2.oct
run csg difference cube.oct ball2.oct -o hollow.oct
run csg union cube.oct ball2.oct -o union.oct
run csg intersect cube.oct ball2.oct -o inter.oct
run csg xor cube.oct ball2.oct -o xor.oct
for kind in ellipsoid cylinder cone torus; do run shape $kind --depth 7 -o $kind.oct; done
run info hollow.oct --json
run info hollow.oct
run slice hollow.oct --axis z --at 0.5 --size 768 -o hollow-slice.png
run slice hollow.oct --axis x --size 300 -o hollow-slice-x.png
run voxelize models/stanford-bunny.obj --depth 9 -o bunny.oct
run voxelize models/spot.obj --depth 8 --inside winding -o spot-winding.oct
run voxelize models/spot.obj --depth 8 --fill surface -o spot-surface.oct
run voxelize models/spot.obj --depth 8 --fill thin -o spot-thin.oct
run voxelize models/teapot.patches --depth 8 -o teapot.oct
run voxelize models/teapot.patches --depth 8 --fill surface -o teapot-surface.oct
run mesh-info models/stanford-bunny.obj
run mesh-info models/spot.obj --json
run mesh-info models/teapot.patches --json
# The bundled scenes' solid caches are cleared, so the first render of each voxelizes
# and the second render of the classic scene reads its solids from the cache.
rm -rf "$root/scenes/.octsolid-cache"
for scene in "$root"/scenes/*.toml; do
  name=$(basename "$scene" .toml)
  run render "$scene" --size 480x360 -o "scene-$name.png"
done
run render "$root/scenes/classic.toml" -o scene-classic-full.png
for method in trace front-to-back painter zbuffer; do
  run render hollow.oct --method $method --size 320x240 -o "hollow-$method.png"
done
run render hollow.oct --method scanline --size 160x120 --spp 1 -o hollow-scanline.png
run render hollow.oct --normals octree --size 320x240 -o hollow-octree-normals.png
run render hollow.oct --no-shadows --size 320x240 -o hollow-no-shadows.png
run render models/stanford-bunny.obj --depth 9 --spp 2 --size 480x360 -o bunny-render.png
run render models/spot.obj --depth 8 --up z --size 320x240 -o spot-up-z.png
for shading in flat gouraud phong; do
  run render models/spot.obj --shading $shading --size 320x240 -o "spot-$shading.png"
done
run render hollow.oct --shading gouraud --size 320x240 -o hollow-polygon.png
for fmt in obj stl ply; do run export hollow.oct -o "hollow.$fmt"; done
run export hollow.oct -o hollow-unit.obj --unit-faces
run export bunny.oct -o bunny.ply
run demo -o demo.png
run demo --depth 7 -o demo-d7.png
run radiosity "$root/scenes/cornell.toml" -o cornell.rad --until 0.05
run render "$root/scenes/cornell.toml" --radiosity cornell.rad --size 240x240 -o cornell-radiosity.png
run render "$root/scenes/cornell.toml" --radiosity cornell.rad --show-elements --size 240x240 -o cornell-elements.png

# The examples write into example-output/NAME/ under the current folder.
for ex in "$root"/examples/*.rs; do
  name=$(basename "$ex" .rs)
  echo "\$ example $name" >>"$log"
  "$root/target/release/examples/$name" 2>&1 | mask >>"$log" || echo "exit $?" >>"$log"
done

cd "$out/work"
{
  find . -type f | sort | xargs sha256sum
  echo "--- printed"
  # The checkout's and the output's folders differ between two snapshots: named, not spelt.
  sed -e "s#$root#<repo>#g" -e "s#$out#<out>#g" "$log"
} >"$out/MANIFEST"
echo "wrote $out/MANIFEST ($(find . -type f | wc -l) files)"
