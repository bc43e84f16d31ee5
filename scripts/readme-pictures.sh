#!/usr/bin/env bash
# Renders the pictures README.md shows, with the current defaults, into docs/images/.
# Run it after a change that alters what octsolid draws, then look at each picture.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
cargo build --release --quiet -p octsolid-cli
bin="$root/target/release/octsolid"
out=docs/images
"$bin" demo -o "$out/demo.png"
"$bin" render scenes/whitted.toml --size 800x600 -o "$out/whitted.png"
"$bin" render scenes/teapot.toml --size 800x600 -o "$out/teapot.png"
"$bin" render scenes/displaced.toml --size 400x400 --normals axis -o "$out/displaced-axis.png"
"$bin" render scenes/displaced.toml --size 400x400 --normals octree -o "$out/displaced-smooth.png"
"$bin" render scenes/menger.toml --size 640x480 -o "$out/menger.png"
"$bin" render scenes/textures.toml --size 768x512 -o "$out/textures.png"
