#!/usr/bin/env python3
"""Makes models/bunny-watertight.obj: a closed, manifold Stanford bunny of about
3,700 triangles, from models/stanford-bunny.obj (69,451 triangles, open at the base).

  1. octsolid voxelizes the bunny as a solid at depth 6 (64 voxels a side) with the
     winding rule, which closes the holes in the base (at depths 7 and 8 the solid
     has a one-voxel handle, genus 1; depth 6 has none);
  2. octsolid exports the octree's boundary, a closed manifold mesh (--unit-faces:
     two triangles a voxel face, so the next step has an even mesh to work on), and
     the shells of voxel-sized voids inside are dropped (the voids filled);
  3. Taubin smoothing (trimesh; no shrinking, topology unchanged) takes the voxel
     staircase off;
  4. quadric decimation (fast-simplification) brings it to --triangles, and an offset
     along the vertex normals gives back the volume the smoothing took (it rounds
     the staircase's corners off: about 4%);
  5. the result is checked with trimesh: watertight, consistently wound, outward
     (positive volume), one body of genus 0, no degenerate triangles; written scaled
     by --scale about the origin (y up, as the original); and voxelized by octsolid
     at depth 8 with the parity and the winding rule, which must give the same
     voxels (a surface that overlapped itself would not).

Deterministic: the same inputs and package versions give the same file.

    cargo build --release        # the octsolid binary
    target/peers-venv/bin/python benches/peers/make_small_bunny.py
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import fast_simplification
import numpy as np
import trimesh
import trimesh.smoothing

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def check(mesh, what):
    """Fails unless the mesh bounds one solid body of genus 0."""
    problems = []
    if not mesh.is_watertight:
        problems.append("not watertight")
    if not mesh.is_winding_consistent:
        problems.append("winding not consistent")
    if mesh.volume <= 0:
        problems.append(f"volume {mesh.volume} is not positive (faces inward?)")
    bodies = mesh.body_count
    if bodies != 1:
        problems.append(f"{bodies} bodies")
    if mesh.euler_number != 2:
        problems.append(f"Euler number {mesh.euler_number} (genus 0 has 2)")
    areas = mesh.area_faces
    if (areas <= 1e-12 * mesh.area).any():
        problems.append(f"{int((areas <= 1e-12 * mesh.area).sum())} degenerate triangles")
    if problems:
        sys.exit(f"make_small_bunny: {what}: " + "; ".join(problems))


def same_voxels(octsolid, path, depth=8):
    """Self-overlap shows as a difference between the parity and winding solids: octsolid
    voxelizes the written mesh both ways and the symmetric difference must be empty."""
    with tempfile.TemporaryDirectory() as tmp:
        solids = []
        for rule in ("parity", "winding"):
            solids.append(os.path.join(tmp, f"{rule}.oct"))
            subprocess.run([octsolid, "voxelize", path, "--depth", str(depth), "--inside", rule, "-o", solids[-1]],
                           check=True, stdout=subprocess.DEVNULL)
        xor = os.path.join(tmp, "xor.oct")
        subprocess.run([octsolid, "csg", "xor", *solids, "-o", xor], check=True, stdout=subprocess.DEVNULL)
        info = json.loads(subprocess.run([octsolid, "info", xor, "--json"], check=True, capture_output=True,
                                         text=True).stdout.strip().splitlines()[-1])
    if info["voxels"] != 0:
        sys.exit(f"make_small_bunny: {path}: parity and winding solids differ in {info['voxels']} voxels "
                 f"at depth {depth} (the surface overlaps itself)")


def write_obj(path, mesh, header):
    with open(path, "w", encoding="utf-8") as f:
        for line in header:
            f.write(f"# {line}\n")
        for v in mesh.vertices:
            f.write(f"v {v[0]:.6f} {v[1]:.6f} {v[2]:.6f}\n")
        for t in mesh.faces + 1:
            f.write(f"f {t[0]} {t[1]} {t[2]}\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--input", default=os.path.join(ROOT, "models", "stanford-bunny.obj"))
    ap.add_argument("--output", default=os.path.join(ROOT, "models", "bunny-watertight.obj"))
    ap.add_argument("--octsolid", default=os.path.join(ROOT, "target", "release", "octsolid"))
    ap.add_argument("--depth", type=int, default=6,
                    help="6: at depth 7 and 8 the winding solid has a handle (genus 1)")
    ap.add_argument("--smooth", type=int, default=20, help="Taubin smoothing iterations")
    ap.add_argument("--triangles", type=int, default=3700)
    ap.add_argument("--scale", type=float, default=64.0,
                    help="uniform scale about the origin (64: about 10 units tall, exact in binary)")
    args = ap.parse_args()
    if not os.path.exists(args.octsolid):
        sys.exit(f"make_small_bunny: no {args.octsolid}: run `cargo build --release` first")

    with tempfile.TemporaryDirectory() as tmp:
        oct_path, boundary = os.path.join(tmp, "bunny.oct"), os.path.join(tmp, "boundary.obj")
        subprocess.run([args.octsolid, "voxelize", args.input, "--depth", str(args.depth), "--inside", "winding",
                        "-o", oct_path], check=True, stdout=subprocess.DEVNULL)
        subprocess.run([args.octsolid, "export", oct_path, "--unit-faces", "-o", boundary], check=True,
                       stdout=subprocess.DEVNULL)
        # process=False: the export keeps apart the vertices where two voxels touch at
        # an edge or a corner only; merging them by position would make it non-manifold.
        exported = trimesh.read(boundary, force="mesh", process=False)
    # The winding solid can hold voxel-sized voids; their inward-facing shells are
    # separate bodies of negative volume: keep the outer shell (which fills them).
    bodies = sorted(exported.split(only_watertight=False), key=lambda b: -b.volume)
    if len(bodies) > 1 and any(b.volume >= 0 for b in bodies[1:]):
        sys.exit(f"make_small_bunny: the solid has {len(bodies)} separate parts, not one with voids")
    voxels = bodies[0]
    voids = len(bodies) - 1
    check(voxels, "the exported boundary")

    smooth = voxels.copy()
    trimesh.smoothing.filter_taubin(smooth, lamb=0.5, nu=-0.53, iterations=args.smooth)
    check(smooth, "the smoothed boundary")

    points, faces = fast_simplification.simplify(
        np.asarray(smooth.vertices, dtype=np.float64), np.asarray(smooth.faces, dtype=np.int32),
        target_count=args.triangles)
    small = trimesh.Trimesh(points, faces, process=True)
    small.remove_unreferenced_vertices()
    check(small, "the decimated mesh")
    shrunk = small.volume
    # Smoothing rounds the staircase's corners off and loses volume (about 4% at 20
    # iterations); move the surface out along its vertex normals until the volume is
    # the voxel solid's again (a few tenths of a voxel).
    for _ in range(4):
        delta = (voxels.volume - small.volume) / small.area
        small = trimesh.Trimesh(small.vertices + delta * small.vertex_normals, small.faces, process=False)
    check(small, "the offset mesh")
    small.apply_scale(args.scale)

    original = trimesh.read(args.input, force="mesh", process=True)
    header = [
        "Stanford bunny, closed and manifold (genus 0), "
        f"{len(small.vertices)} vertices, {len(small.faces)} triangles; y up.",
        "Made by benches/peers/make_small_bunny.py from models/stanford-bunny.obj: octsolid voxelize "
        f"--depth {args.depth} --inside winding, octsolid export --unit-faces (voids filled),",
        f"Taubin smoothing ({args.smooth} iterations, trimesh), quadric decimation (fast-simplification) to "
        f"{args.triangles} triangles, offset along its normals to the voxel solid's volume, scaled by "
        f"{args.scale:g} about the origin.",
        "Credit: Stanford Computer Graphics Laboratory, The Stanford 3D Scanning Repository.",
    ]
    write_obj(args.output, small, header)
    same_voxels(args.octsolid, args.output)
    lo, hi = small.bounds
    print(f"boundary at depth {args.depth}: {len(voxels.faces)} triangles ({voids} void(s) filled); decimated: {len(small.faces)} "
          f"triangles, {len(small.vertices)} vertices; watertight, genus 0, parity = winding solid")
    k3 = args.scale ** 3
    print(f"volume {small.volume:.6g} (smoothed and decimated {shrunk * k3:.6g}; the voxel solid "
          f"{voxels.volume * k3:.6g}; the open original's signed volume {original.volume * k3:.6g})")
    print(f"bounds {np.round(lo, 4).tolist()} .. {np.round(hi, 4).tolist()}")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
