"""The classic CSG part from Python: a cube of side 2 intersected with a ball of
radius 1.3, minus three cylinders of radius 0.6 along x, y and z, voxelized at depth
9 (512^3 voxels over [-1, 1]^3), as the Rust example examples/classic_csg.rs makes it.

Run: python examples/python/classic_part.py [OUT_FOLDER] [--depth D]
(writes classic_part.oct and classic_part.png, a slice at z = 0.8, into OUT_FOLDER,
default example-output/python/): the Rust example's work, step for step.
"""

import argparse
import math
import pathlib
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


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="example-output/python")
    parser.add_argument("--depth", type=int, default=9)
    parser.add_argument("--repeat", type=int, default=1, help="do the work this many times, timing each")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    for run in range(args.repeat):
        started = time.perf_counter()
        solid = o.voxelize(classic_part(), args.depth, domain=((-1, -1, -1), 2.0))
        # Without the surface section, as the Rust example's oct::write.
        solid.save(out / "classic_part.oct", surface=False)
        # Straight to the PNG, as the Rust example: no numpy array (nor numpy) needed.
        solid.save_slice(out / "classic_part.png", "z", 0.8, 768)
        seconds = time.perf_counter() - started
        if args.repeat > 1:
            print(f"run {run + 1}: {seconds:.3f} s")
    exact = analytic_volume()
    print(f"classic CSG part at depth {args.depth}: {solid.node_count} nodes, {solid.voxel_count} voxels")
    print(f"volume {solid.volume:.5f}, analytic {exact:.5f} ({100 * (solid.volume / exact - 1):+.3f}%)")
    print(f"voxelized and written in {seconds * 1e3:.1f} ms: {out / 'classic_part.oct'} and classic_part.png")


if __name__ == "__main__":
    main()
