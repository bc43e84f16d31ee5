#!/usr/bin/env python3
"""The worked large example: the classic CSG part built, combined and rendered as
sharded solids within a memory budget, at depths 10 to 15 (scenes/large_part.toml).

For each depth it runs, each step a process of its own, timed, with its peak
resident memory (the kernel's ru_maxrss of that process):

  octsolid build scenes/large_part.toml --solid body  --depth D -o body.octs
  octsolid build scenes/large_part.toml --solid bores --depth D -o bores.octs
  octsolid csg difference body.octs bores.octs -o part.octs
  octsolid render part.octs -o part-D.png

all with --memory-budget BUDGET, and writes one CSV row a step (depth, step,
seconds, peak bytes, the result's nodes and bytes on disk). Then it draws time and
memory against depth on log axes (harness example plot_large) next to the CSV.

  python3 benches/large/large_part.py --depths 10 11 12 13 14 15 --budget 2GiB \
      --work /some/scratch/folder --out benches/large

The work folder needs room for the depth-15 solids (about 12 GB); each depth's
solids are removed before the next depth starts.
"""

import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def run_step(cmd):
    """Runs `cmd`, returns (seconds, peak resident bytes); fails on a non-zero exit."""
    start = time.monotonic()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    output = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.monotonic() - start
    if status != 0:
        sys.exit(f"failed ({status}): {' '.join(map(str, cmd))}\n{output}")
    return seconds, usage.ru_maxrss * 1024


def folder_bytes(path):
    path = Path(path)
    if path.is_file():
        return path.stat().st_size
    return sum(f.stat().st_size for f in path.iterdir())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--depths", type=int, nargs="+", default=[10, 11, 12, 13, 14, 15])
    parser.add_argument("--budget", default="2GiB")
    parser.add_argument("--work", type=Path, required=True, help="scratch folder for the solids")
    parser.add_argument("--out", type=Path, default=REPO / "benches" / "large")
    parser.add_argument("--octsolid", type=Path, default=REPO / "target" / "release" / "octsolid")
    args = parser.parse_args()

    args.work.mkdir(parents=True, exist_ok=True)
    args.out.mkdir(parents=True, exist_ok=True)
    scene = REPO / "scenes" / "large_part.toml"
    exe, budget = str(args.octsolid), ["--memory-budget", args.budget]
    rows = []
    for depth in args.depths:
        body, bores, part = (args.work / f"{n}-{depth}.octs" for n in ("body", "bores", "part"))
        png = args.out / f"part-{depth}.png"
        steps = [
            ("build body", [exe, "build", scene, "--solid", "body", "--depth", depth, "-o", body], body),
            ("build bores", [exe, "build", scene, "--solid", "bores", "--depth", depth, "-o", bores], bores),
            ("difference", [exe, "csg", "difference", body, bores, "-o", part], part),
            ("render", [exe, "render", part, "-o", png, "--size", "800x600"], part),
        ]
        for name, cmd, result in steps:
            seconds, peak = run_step([str(c) for c in cmd] + budget)
            info = json.loads(subprocess.check_output([exe, "info", str(result), "--json"], text=True))
            row = {
                "depth": depth,
                "step": name,
                "seconds": round(seconds, 3),
                "peak_bytes": peak,
                "nodes": info["nodes"],
                "disk_bytes": folder_bytes(result),
            }
            rows.append(row)
            print(json.dumps(row), flush=True)
        for solid in (body, bores, part):
            shutil.rmtree(solid, ignore_errors=True)
    table = args.out / "large_part.csv"
    with open(table, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"wrote {table}")
    plot = args.out / "large_part.png"
    subprocess.check_call(
        ["cargo", "run", "--release", "-q", "-p", "octsolid-harness", "--example", "plot_large", "--", str(table), str(plot)],
        cwd=REPO,
    )
    print(f"wrote {plot}")


if __name__ == "__main__":
    main()
