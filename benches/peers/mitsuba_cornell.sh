#!/usr/bin/env bash
# Radiosity against Mitsuba 3 (issue 42): Mitsuba's built-in Cornell box path traced by
# Mitsuba (the reference, rendered once and kept while its views, samples and Mitsuba's
# version are unchanged) and solved by `octsolid radiosity` on scenes/cornell-mitsuba.toml, the
# same nine regions and the bleeding ratio measured in both (mitsuba_cornell.py).
#
#   benches/peers/mitsuba_cornell.sh                 # writes target/mitsuba-cornell/
#   SPP=256 benches/peers/mitsuba_cornell.sh         # a quicker, noisier reference
#   RADIOSITY_ARGS="--until 0.001" benches/peers/mitsuba_cornell.sh
#
# Prints the comparison table and saves it (comparison.md, comparison.json) with
# side-by-side pictures of each view, the regions outlined (side-by-side-*.png: Mitsuba
# on the left). Needs `cargo build --release -p octsolid-cli`. Mitsuba (PyPI `mitsuba`,
# pinned below) goes into the peers venv of setup.sh.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
venv="${PEERS_VENV:-$root/target/peers-venv}"
out="${OUT:-$root/target/mitsuba-cornell}"
spp="${SPP:-2048}"
octsolid="$root/target/release/octsolid"
mitsuba_version=3.9.1

PEERS_NO_APT=1 "$here/setup.sh" >/dev/null
if ! "$venv/bin/python" -c "import mitsuba, sys; sys.exit(mitsuba.__version__ != '$mitsuba_version')" 2>/dev/null; then
    echo "venv: installing mitsuba==$mitsuba_version"
    "$venv/bin/python" -m pip install -q --disable-pip-version-check "mitsuba==$mitsuba_version"
fi
[ -x "$octsolid" ] || { echo "missing $octsolid: cargo build --release -p octsolid-cli" >&2; exit 1; }
mkdir -p "$out"

# The reference, unless one of these views, samples and Mitsuba is there.
stamp="$out/mitsuba.stamp"
want="$("$venv/bin/python" "$here/mitsuba_cornell.py" params) spp=$spp"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
    echo "mitsuba: rendering the reference at $spp samples a pixel (minutes)"
    "$venv/bin/python" "$here/mitsuba_cornell.py" render --out "$out" --spp "$spp"
    echo "$want" >"$stamp"
fi

# octsolid: one solution, both views (the cameras of mitsuba_cornell.py).
scene="$root/scenes/cornell-mitsuba.toml"
# shellcheck disable=SC2086
"$octsolid" radiosity "$scene" -o "$out/octsolid.rad" ${RADIOSITY_ARGS:-}
"$octsolid" render "$scene" --radiosity "$out/octsolid.rad" --size 256x256 -o "$out/octsolid-front.exr" >/dev/null
"$octsolid" render "$scene" --radiosity "$out/octsolid.rad" --size 128x128 \
    --eye=0,0.95,0 --target=0,-1,0 --up=0,0,-1 --fov 65 -o "$out/octsolid-top.exr" >/dev/null

"$venv/bin/python" "$here/mitsuba_cornell.py" compare --out "$out" \
    --octsolid-front "$out/octsolid-front.exr" --octsolid-top "$out/octsolid-top.exr" \
    --json "$out/comparison.json" --masks | tee "$out/comparison.md"
