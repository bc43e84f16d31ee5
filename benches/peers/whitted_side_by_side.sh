#!/usr/bin/env bash
# The Whitted classic rendered by octsolid and by POV-Ray 3.7 in one sitting, same
# size, camera, lights and materials (scenes/whitted-classic.toml and
# whitted_classic.pov): median wall seconds of RUNS renders each, as JSON lines, and
# a side-by-side picture (octsolid adaptive | POV-Ray +A0.3 +R3) in OUT_DIR.
#
# octsolid: 3x3 samples in every pixel (uniform), 3x3 where neighbours differ by 0.3
# (--aa adaptive, POV-Ray's +A0.3 +R3), corner samples split where they differ by 0.3
# up to 3 times (--aa recursive, POV-Ray's +A0.3 +AM2 +R3 -J), and one sample a pixel
# (POV-Ray's -A). The recursive pictures are compared too.
#
#   benches/peers/whitted_side_by_side.sh [RUNS=3] [OUT_DIR=target/peers]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
runs=${1:-3}
out=${2:-$root/target/peers}
mkdir -p "$out"
bin="$root/target/release/octsolid"
[ -x "$bin" ] || { echo "whitted_side_by_side: build first: cargo build --release" >&2; exit 1; }
export OCTSOLID_PROGRESS_SECONDS=1000000

octsolid() { # name, flags...
    local name=$1
    shift
    local times=()
    for _ in $(seq "$runs"); do
        local start
        start=$(date +%s%N)
        "$bin" render "$root/scenes/whitted-classic.toml" --size 800x600 "$@" -o "$out/octsolid-$name.png" >"$out/octsolid-$name.log"
        times+=($(( ($(date +%s%N) - start) / 1000000 )))
    done
    local median
    median=$(printf '%s\n' "${times[@]}" | sort -n | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR+1)/2] : int((a[NR/2] + a[NR/2+1]) / 2)}')
    local rendered
    rendered=$(grep -m1 '^rendered' "$out/octsolid-$name.log" | sed 's/"/\\"/g')
    printf '{"peer": "octsolid", "scene": "whitted-classic.toml", "size": [800, 600], "threads": 2, "aa": "%s", "runs": %d, "median_wall_s": %d.%03d, "rendered": "%s", "image": "%s"}\n' \
        "$*" "$runs" $((median / 1000)) $((median % 1000)) "$rendered" "$out/octsolid-$name.png"
}

octsolid uniform --spp 3
octsolid adaptive --spp 3 --aa adaptive --aa-threshold 0.3
octsolid recursive --aa recursive --aa-threshold 0.3 --aa-depth 3
octsolid one --spp 1
"$here/povray_whitted.sh" "$runs" "$out"

py="$root/target/peers-venv/bin/python"
if [ -x "$py" ]; then
    "$py" "$here/compare_images.py" "$out/octsolid-adaptive.png" "$out/povray-aa.png"
    "$py" "$here/compare_images.py" "$out/octsolid-recursive.png" "$out/povray-am2.png"
    "$py" - "$out" <<'EOF'
import sys
from PIL import Image, ImageDraw
out = sys.argv[1]
a, b = Image.open(f"{out}/octsolid-adaptive.png"), Image.open(f"{out}/povray-aa.png")
pair = Image.new("RGB", (a.width + b.width + 8, a.height), (255, 255, 255))
pair.paste(a, (0, 0))
pair.paste(b, (a.width + 8, 0))
pair.save(f"{out}/whitted-side-by-side.png")
EOF
    echo "{\"picture\": \"$out/whitted-side-by-side.png\"}"
fi
