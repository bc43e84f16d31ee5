#!/usr/bin/env bash
# Renders the pictures of docs/CHAPTER.md, one (or three) a section of the seed chapter,
# into docs/images/chapter-*.png. Run it after a change that alters what octsolid draws,
# then look at each picture. tests/chapter.rs runs it at a tiny size so the commands
# keep working.
#
# Environment (all optional): OCTSOLID, the binary (default: built here, release);
# OUT, the folder (default docs/images); SIZE, the pictures' WIDTHxHEIGHT (default
# 320x240); PATCH, radiosity's patch size (default: the scene's eighth).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
if [[ -z "${OCTSOLID:-}" ]]; then
    cargo build --release --quiet -p octsolid-cli
    OCTSOLID="$root/target/release/octsolid"
fi
out=${OUT:-docs/images}
size=${SIZE:-320x240}
patch=()
if [[ -n "${PATCH:-}" ]]; then patch=(--patch-size "$PATCH"); fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
run() { echo "+ octsolid $*"; "$OCTSOLID" "$@" >/dev/null; }
render() { run render "$@" --size "$size"; }

# 2. Colour models: one colour as RGB, CMY and HSI.
render scenes/chapter-colours.toml --no-cache -o "$out/chapter-colours.png"
# 3. Polygon tables (vertex, edge and polygon tables; plane equations).
run mesh-info models/spot.obj
render models/stanford-bunny.obj --shading flat -o "$out/chapter-polygons.png"
# 3. Quadrics, with their analytic normals.
render scenes/chapter-quadrics.toml --no-cache -o "$out/chapter-quadrics.png"
# 3. Parametric (spline) surfaces: bicubic Bezier patches, tessellated.
render models/teapot.patches --shading phong -o "$out/chapter-splines.png"
# 3. Octrees: the classic CSG part, every voxel face with its axis normal.
render scenes/classic.toml --no-cache -o "$out/chapter-octree.png"
# 4. Depth sort (painter's algorithm) over a triangle mesh.
render models/spot.obj --shading gouraud --method painter -o "$out/chapter-painter.png"
# 4. Z-buffer over a triangle mesh.
render models/bunny-watertight.obj --shading gouraud --method zbuffer -o "$out/chapter-zbuffer.png"
# 4. Scan-line Z-buffer over an octree's faces.
render scenes/classic.toml --no-cache --method scanline -o "$out/chapter-scanline.png"
# 5. Lighting: ambient, Lambert and Phong's specular term, with shadows.
render scenes/teapot.toml --no-cache -o "$out/chapter-lighting.png"
# 5. Transparency: refraction by Snell's law through glass.
render scenes/whitted.toml --no-cache -o "$out/chapter-transparency.png"
# 5. Whitted's global model: mirror and glass traced recursively.
render scenes/whitted-classic.toml --no-cache -o "$out/chapter-whitted.png"
# 5. Textures: colour and bump maps.
render scenes/textures.toml --no-cache -o "$out/chapter-textures.png"
# 6. Flat, Gouraud and Phong shading of one mesh.
for s in flat gouraud phong; do
    render models/spot.obj --shading "$s" -o "$out/chapter-$s.png"
done
# 7. Ray tracing, accelerated by the octree walk (empty cells skipped whole).
render scenes/gear.toml --no-cache --method trace -o "$out/chapter-raytracing.png"
# 8. Radiosity: the chapter's [F][B] = [E] gathered by Gauss-Seidel, then shown.
run radiosity scenes/cornell.toml --solver gathering "${patch[@]}" -o "$work/cornell.rad"
render scenes/cornell.toml --no-cache --radiosity "$work/cornell.rad" -o "$out/chapter-radiosity.png"
