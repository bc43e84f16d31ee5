#!/usr/bin/env python3
"""manifold3d (PyPI) on two CSG models, exact mesh booleans:

  plate:   a 200 x 200 x 10 plate minus a 20 x 20 grid of through-holes of radius 3
           at (5 + 10 i, 5 + 10 j), each a cylinder of 96 segments, all subtracted in
           one Manifold.batch_boolean(..., OpType.Subtract);
  classic: the classic CSG part, a cube of side 2 & a sphere of radius 1.3 minus three
           cylinders of radius 0.6 along x, y and z (96 segments).

Each model is timed from the primitives to the evaluated result (manifold3d
evaluates lazily; num_tri() forces it), on 1 core and on 2 (manifold3d's wheel
runs TBB inside; the 1-core run pins the process to one CPU before TBB starts).
One JSON line a model and core count: median seconds over --runs runs after a
warm-up, triangles, volume, and the relative error against the analytic volume of
the smooth solid (the plate: 400000 - 36000 pi) and, for the plate, against the
exact volume of the 96-gon prisms the mesh really has.

    target/peers-venv/bin/python benches/peers/manifold_plate.py [--runs 5] [--grid 20]
"""

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time


def polygon_area(radius, segments):
    """Area of the regular polygon inscribed in the circle (manifold3d's cylinder)."""
    return 0.5 * segments * radius * radius * math.sin(2.0 * math.pi / segments)


def plate(M, OpType, grid, segments):
    size, thick, pitch, r = 10.0 * grid, 10.0, 10.0, 3.0
    slab = M.cube((size, size, thick))
    holes = [
        M.cylinder(thick + 2.0, r, circular_segments=segments).translate((5.0 + pitch * i, 5.0 + pitch * j, -1.0))
        for i in range(grid)
        for j in range(grid)
    ]
    return M.batch_boolean([slab] + holes, OpType.Subtract)


def plate_volumes(grid, segments):
    size, thick, r = 10.0 * grid, 10.0, 3.0
    n = grid * grid
    return size * size * thick - n * math.pi * r * r * thick, size * size * thick - n * polygon_area(r, segments) * thick


def classic(M, OpType, segments):
    body = M.cube((2.0, 2.0, 2.0), center=True) ^ M.sphere(1.3, circular_segments=segments)
    bore = M.cylinder(3.0, 0.6, circular_segments=segments, center=True)  # along z
    bores = [bore, bore.rotate((90.0, 0.0, 0.0)), bore.rotate((0.0, 90.0, 0.0))]
    return M.batch_boolean([body] + bores, OpType.Subtract)


def classic_volume():
    """The smooth part's volume (as examples/classic_csg.rs): the ball clipped by the
    cube loses six caps of height R - 1; the three bores lie inside it and their union
    is 3 V_cyl - 3 V_bicylinder + V_tricylinder (Steinmetz solids)."""
    rb, rc = 1.3, 0.6
    h = rb - 1.0
    clipped = 4.0 / 3.0 * math.pi * rb**3 - 6.0 * math.pi * h * h * (3.0 * rb - h) / 3.0
    bores = 3.0 * math.pi * rc**2 * 2.0 - 3.0 * 16.0 / 3.0 * rc**3 + 8.0 * (2.0 - math.sqrt(2.0)) * rc**3
    return clipped - bores


def measure(args, cores):
    from importlib.metadata import version

    from manifold3d import Manifold as M
    from manifold3d import OpType

    models = [
        ("plate", lambda: plate(M, OpType, args.grid, args.segments), plate_volumes(args.grid, args.segments)),
        ("classic", lambda: classic(M, OpType, args.segments), (classic_volume(), None)),
    ]
    for name, make, (analytic, polygonal) in models:
        times, result = [], None
        for run in range(args.runs + 1):
            start = time.perf_counter()
            result = make()
            tris = result.num_tri()  # forces the lazy booleans
            if run:
                times.append(time.perf_counter() - start)
        vol = result.volume()
        line = {
            "peer": "manifold3d",
            "version": version("manifold3d"),
            "model": name,
            "cores": cores,
            "segments": args.segments,
            "median_s": round(statistics.median(times), 6),
            "runs": args.runs,
            "triangles": tris,
            "genus": result.genus(),
            "volume": vol,
            "analytic_volume": analytic,
            "rel_error_vs_analytic": (vol - analytic) / analytic,
        }
        if name == "plate":
            line["holes"] = args.grid * args.grid
            line["polygonal_volume"] = polygonal
            line["rel_error_vs_polygonal"] = (vol - polygonal) / polygonal
        print(json.dumps(line), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--grid", type=int, default=20, help="holes a side (the plate is 10 x grid wide)")
    ap.add_argument("--segments", type=int, default=96)
    ap.add_argument("--cores", choices=["1", "2", "both"], default="both")
    args = ap.parse_args()
    if args.cores == "both":
        # One fresh process a core count: TBB fixes its thread count when it starts.
        for cores in ("1", "2"):
            cmd = [sys.executable, os.path.abspath(__file__), "--cores", cores, "--runs", str(args.runs),
                   "--grid", str(args.grid), "--segments", str(args.segments)]
            subprocess.run(cmd, check=True)
        return
    cpus = sorted(os.sched_getaffinity(0))
    if len(cpus) < int(args.cores):
        sys.exit(f"manifold_plate: {args.cores} cores asked, {len(cpus)} available")
    os.sched_setaffinity(0, cpus[: int(args.cores)])
    measure(args, int(args.cores))


if __name__ == "__main__":
    main()
