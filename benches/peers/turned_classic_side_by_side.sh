#!/usr/bin/env bash
# The turned classic (turned_classic.toml and turned_classic.pov: the Whitted classic
# as a new user rewrote it, the part turned over a large floor of its own domain, the
# eye inside that domain) by octsolid and POV-Ray 3.7 in one sitting, one sample a
# pixel at 800x600: octsolid's default front-to-back display and the ray walk (the
# display fell 2,500x behind here once: it must stay near the walk), POV-Ray -A; the
# wall seconds of each, as JSON lines, and how alike the pictures are (their
# differences x4 in OUT_DIR/turned-diff.png: self-shadowing and speckles show there).
#
#   benches/peers/turned_classic_side_by_side.sh [OUT_DIR=target/peers]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=$(realpath -m "${1:-$root/target/peers}")
mkdir -p "$out"
bin="$root/target/release/octsolid"
[ -x "$bin" ] || { echo "turned_classic_side_by_side: build first: cargo build --release" >&2; exit 1; }
command -v povray >/dev/null || { echo "turned_classic_side_by_side: povray is missing (benches/peers/setup.sh)" >&2; exit 1; }
export OCTSOLID_PROGRESS_SECONDS=1000000

cp "$here/turned_classic.toml" "$out/turned_classic.toml"
"$bin" shape box --size 40,40,0.2 --center 0,0,-1.1 --depth 10 --domain -20,-20,-21,40 \
    -o "$out/turned-floor.oct" >/dev/null

seconds() { # command...: wall seconds
    local start
    start=$(date +%s%N)
    "$@" >/dev/null 2>&1 || { echo "turned_classic_side_by_side: $1 failed" >&2; exit 1; }
    local ms=$(( ($(date +%s%N) - start) / 1000000 ))
    printf '%d.%03d' $((ms / 1000)) $((ms % 1000))
}

# The first render voxelizes the part into the scene's cache; the timed ones read it.
"$bin" render "$out/turned_classic.toml" --spp 1 --size 80x60 -o "$out/turned-warm.png" >/dev/null 2>&1
for method in front-to-back trace; do
    s=$(seconds "$bin" render "$out/turned_classic.toml" --spp 1 --method "$method" -o "$out/octsolid-turned-$method.png")
    printf '{"peer": "octsolid", "scene": "turned_classic.toml", "size": [800, 600], "spp": 1, "method": "%s", "wall_s": %s, "image": "%s"}\n' \
        "$method" "$s" "$out/octsolid-turned-$method.png"
done
s=$(seconds povray "+I$here/turned_classic.pov" "+L$here" "+O$out/povray-turned.png" +FN +W800 +H600 +WT2 -D -V -A)
printf '{"peer": "povray", "scene": "turned_classic.pov", "size": [800, 600], "aa": "-A", "wall_s": %s, "image": "%s"}\n' \
    "$s" "$out/povray-turned.png"

py="$root/target/peers-venv/bin/python"
if [ -x "$py" ]; then
    "$py" "$here/compare_images.py" "$out/octsolid-turned-front-to-back.png" "$out/povray-turned.png" \
        --diff "$out/turned-diff.png"
fi
