#!/usr/bin/env bash
# The bytes of every bundled scene that uses a pattern (`array`, `polar`, `mirror`),
# and of one written here with each kind nested in the others and under a transform:
# each scene rendered (smooth normals from the shape's surface, and the octree's) and
# its solids built to .oct, by the octsolid binary BIN, into OUT_DIR with
# OUT_DIR/SHA256SUMS. A change
# to CSG trees or patterns must leave the sums unchanged:
#
#   scripts/pattern-scenes.sh OLD_BIN /tmp/before
#   scripts/pattern-scenes.sh target/release/octsolid /tmp/after
#   diff /tmp/before/SHA256SUMS /tmp/after/SHA256SUMS
#
# Neither reads nor writes the scenes' solid caches (--no-cache).
set -euo pipefail
bin=$(realpath "${1:?usage: scripts/pattern-scenes.sh BIN OUT_DIR}")
out=$(realpath -m "${2:?usage: scripts/pattern-scenes.sh BIN OUT_DIR}")
root=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$out"
mkdir -p "$out"
export OCTSOLID_PROGRESS_SECONDS=1000000
mkdir -p "$out/scenes"
cat >"$out/scenes/nested.toml" <<'SCENE'
[image]
size = [480, 360]

[domain]
min = [-2, -2, -2]
edge = 4
depth = 8

[[solid]]
name = "plate"
material = { color = [0.6, 0.7, 0.8], ks = 0.4, shininess = 32 }
shape = { difference = [
    { box = { center = [0, 0, -0.1], size = [3, 3, 0.2] } },
    { array = { count = [12, 12, 1], step = [0.25, 0.25, 0], shape = {
        cylinder = { center = [-1.375, -1.375, -0.1], axis = "z", radius = 0.06, height = 0.4 } } } },
] }

[[solid]]
name = "studs"
material = { color = [0.8, 0.5, 0.3] }
shape = { transform = { rotate_axis = [1, 1, 0], rotate_degrees = 12, translate = [0.05, 0, 0.3], shape = {
    mirror = { normal = [1, 0.3, 0], point = [0.1, 0, 0], shape = {
        array = { count = [3, 1, 2], step = [0.3, 0, 0.35], shape = {
            polar = { count = 7, axis = "z", center = [0.6, 0.6, 0], step_degrees = 40, shape = {
                difference = [
                    { cone = { base = [0.9, 0.6, 0], axis = "z", radius = 0.12, height = 0.3 } },
                    { sphere = { center = [0.9, 0.6, 0.3], radius = 0.08 } },
                ] } } } } } } } } }
SCENE
scenes="$(grep -lE '\b(array|polar|mirror) = \{' "$root"/scenes/*.toml) $out/scenes/nested.toml"
for scene in $scenes; do
  name=$(basename "$scene" .toml)
  "$bin" render "$scene" --no-cache -o "$out/$name.png" >/dev/null
  "$bin" render "$scene" --no-cache --size 320x240 --normals octree -o "$out/$name-flat.png" >/dev/null
  "$bin" build "$scene" --output "$out/$name.oct" >/dev/null
done
(cd "$out" && sha256sum -- *.png *.oct >SHA256SUMS && cat SHA256SUMS)
