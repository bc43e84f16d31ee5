"""The classic CSG part from Python: a cube of side 2 intersected with a ball of
radius 1.3, minus three cylinders of radius 0.6 along x, y and z, voxelized at depth
9 (512^3 voxels over [-1, 1]^3), as the Rust example examples/classic_csg.rs makes it.

Run: python examples/python/classic_part.py [OUT_FOLDER] [--depth D]
(writes classic_part.oct and classic_part.png, a slice at z = 0.8, into OUT_FOLDER,
default example-output/python/): the Rust example's work, step for step.
"""

import math
import os
import sys
import time

import octsolid as o


def classic_part():
    """The part as a shape: (cube & ball) minus three bores."""
    cube = o.Box((0, 0, 0), (2, 2, 2))
    ball = o.Sphere((0, 0, 0), 1.3)
    part = cube & ball
    for axis in "xyz":
        part = part - o.Cylinder((0, 0, 0), axis, 0.6, 3.0)
    return part


def analytic_volume(r_ball=1.3, r_bore=0.6):
    """The ball clipped by the cube loses six caps; the bores' union is
    3 V_cyl - 3 V_bicylinder + V_tricylinder (Steinmetz solids)."""
    h = r_ball - 1.0
    clipped = 4 / 3 * math.pi * r_ball**3 - 6 * math.pi * h * h * (3 * r_ball - h) / 3
    bores = 3 * math.pi * r_bore**2 * 2 - 3 * 16 / 3 * r_bore**3 + 8 * (2 - math.sqrt(2)) * r_bore**3
    return clipped - bores


def arguments(argv):
    """OUT_FOLDER, --depth D and --repeat N (times to do the work, timing each). Parsed
    by hand: importing argparse (and pathlib) takes a few percent of the work's time,
    which a one-shot script against the Rust example pays at every start."""
    out, options = "example-output/python", {"--depth": 9, "--repeat": 1}
    rest = list(argv)
    while rest:
        arg = rest.pop(0)
        if arg in options and rest:
            options[arg] = int(rest.pop(0))
        elif arg.startswith("-"):
            sys.exit(f"usage: classic_part.py [OUT_FOLDER] [--depth D] [--repeat N] (not {arg!r})")
        else:
            out = arg
    return out, options["--depth"], options["--repeat"]


def main():
    out, depth, repeat = arguments(sys.argv[1:])
    os.makedirs(out, exist_ok=True)
    oct_path, png_path = os.path.join(out, "classic_part.oct"), os.path.join(out, "classic_part.png")

    for run in range(repeat):
        started = time.perf_counter()
        solid = o.voxelize(classic_part(), depth, domain=((-1, -1, -1), 2.0))
        # Without the surface section, as the Rust example's oct::write.
        solid.save(oct_path, surface=False)
        # Straight to the PNG, as the Rust example: no numpy array (nor numpy) needed.
        solid.save_slice(png_path, "z", 0.8, 768)
        seconds = time.perf_counter() - started
        if repeat > 1:
            print(f"run {run + 1}: {seconds:.3f} s")
    exact = analytic_volume()
    print(f"classic CSG part at depth {depth}: {solid.node_count} nodes, {solid.voxel_count} voxels")
    print(f"volume {solid.volume:.5f}, analytic {exact:.5f} ({100 * (solid.volume / exact - 1):+.3f}%)")
    print(f"voxelized and written in {seconds * 1e3:.1f} ms: {oct_path} and classic_part.png")


if __name__ == "__main__":
    main()
