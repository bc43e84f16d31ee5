#!/usr/bin/env bash
# Builds embree3_rays.c against Debian's Embree 3 (benches/peers/setup.sh installs it)
# and traces the rays that embree_rays.py --dump wrote:
#
#   benches/peers/embree3_rays.sh MODEL.obj RAYS_DIR [RUNS]
#
# Prints one JSON line (see embree3_rays.c).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
bin="$root/target/peers/embree3_rays"
if [ ! -x "$bin" ] || [ "$here/embree3_rays.c" -nt "$bin" ]; then
    mkdir -p "$(dirname "$bin")"
    cc -O2 -march=native -std=c11 -Wall -Wextra -o "$bin" "$here/embree3_rays.c" -lembree3 -lpthread -lm
fi
exec "$bin" "$@"
