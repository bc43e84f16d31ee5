#!/usr/bin/env python3
"""The perforated plate by octsolid and manifold3d in one sitting, on the same machine.

The plate: 200 x 200 x 10 minus a 20 x 20 grid of through-holes of radius 3 at
(5 + 10 i, 5 + 10 j). manifold3d (PyPI, `manifold_plate.py`: one batch_boolean
Subtract of 96-segment cylinders, both cores); octsolid: `examples/perforated_plate.rs`
(one CSG tree of 401 shapes voxelized pruned, both cores), at the depths given,
with the domain of edge 204.8 whose lattice puts the plate's faces on voxel
boundaries. Alternates the two tools --rounds times (each a median of --runs runs
after a warm-up) and prints one JSON line a measurement, then a summary table:
median seconds, relative volume error, and octsolid's speed-up over manifold3d.

Installs manifold3d 3.5.4 into the venv target/peers-venv when it is missing
(python3 -m venv + pip; `setup.sh` does the same with every peer) and builds the
example with cargo.

    python3 benches/peers/plate_side_by_side.py [--depths 10 11 12] [--runs 3] [--rounds 2]
"""

import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
VENV = os.path.join(ROOT, "target", "peers-venv")
PY = os.path.join(VENV, "bin", "python")
EXAMPLE = os.path.join(ROOT, "target", "release", "examples", "perforated_plate")


def ensure_manifold():
    if not os.path.exists(PY):
        subprocess.run([sys.executable, "-m", "venv", VENV], check=True)
    probe = subprocess.run([PY, "-c", "import manifold3d"], capture_output=True)
    if probe.returncode != 0:
        subprocess.run([PY, "-m", "pip", "install", "--quiet", "manifold3d==3.5.4"], check=True)


def json_lines(cmd):
    # The example writes example-output/ where it runs: under target/, not the checkout.
    work = os.path.join(ROOT, "target", "plate-side-by-side")
    os.makedirs(work, exist_ok=True)
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=work).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--depths", type=int, nargs="+", default=[10, 11, 12])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=2)
    args = ap.parse_args()
    ensure_manifold()
    subprocess.run(["cargo", "build", "--release", "--example", "perforated_plate"], check=True, cwd=ROOT)
    manifold, octsolid = [], {d: [] for d in args.depths}
    for _ in range(args.rounds):
        for line in json_lines([PY, os.path.join(HERE, "manifold_plate.py"), "--cores", "2", "--runs", str(args.runs)]):
            print(json.dumps(line), flush=True)
            if line["model"] == "plate":
                manifold.append(line)
        cmd = [EXAMPLE, *map(str, args.depths), "--runs", str(args.runs), "--json"]
        for line in json_lines(cmd):
            print(json.dumps(line), flush=True)
            octsolid[line["depth"]].append(line)
    m = statistics.median(x["median_s"] for x in manifold)
    print()
    print("| tool | depth | median s | volume error | speed-up over manifold3d |")
    print("|---|---:|---:|---:|---:|")
    print(f"| manifold3d {manifold[0]['version']} (96 segments) | | {m:.3f} | "
          f"{100 * manifold[0]['rel_error_vs_analytic']:+.3f}% | 1 |")
    for depth, lines in octsolid.items():
        t = statistics.median(x["median_s"] for x in lines)
        err = lines[0]["rel_error_vs_analytic"]
        print(f"| octsolid | {depth} | {t:.3f} | {100 * err:+.3f}% | {m / t:.2f}x |")


if __name__ == "__main__":
    main()
