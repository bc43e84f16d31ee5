#!/usr/bin/env python3
"""Embree (through PyPI's embreex, Embree 4) on the source mesh, tracing ray files the
octsolid harness wrote (`octsolid bench --report --issue-rays` writes
target/issue-rays/{primary,bounce,shadow}.rays; harness/src/ray_file.rs).

A ray file is a bare array of 56-byte records of seven little-endian f64: origin xyz,
unit direction xyz, t_max (+inf for unbounded rays). `shadow.rays` is traced as
occlusion queries (rtcOccluded1), every other file as closest hits (rtcIntersect1).
Rays are handed to Embree in float32, tnear 0 (embreex's only choice).

One core: embreex's EmbreeScene.run loops over the rays one at a time holding the GIL.
Prints `embreex VERSION EMBREE_VERSION BUILD_MS`, then one line a file present:
`SET RAYS HITS SECONDS` (hits = closest hits found, or occluded rays; seconds = the
median of --runs runs after a warm-up, CPU time of the tracing thread, so other work
on a shared machine does not count).

    target/peers-venv/bin/python benches/peers/embreex_ray_files.py MODEL.obj RAYS_DIR [--runs 3]
"""

import argparse
import os
import statistics
import time
from importlib.metadata import version

import numpy as np

from embree_rays import build_scene, embree_version, read_mesh
from embreex import rtcore


def read_rays(path):
    """(origins, directions, t_max) of a ray file, as float32 arrays."""
    raw = np.fromfile(path, dtype="<f8")
    if raw.size % 7:
        raise SystemExit(f"{path}: {raw.size * 8} bytes is not a whole number of 56-byte ray records")
    rays = raw.reshape(-1, 7)
    return (np.ascontiguousarray(rays[:, 0:3], dtype=np.float32),
            np.ascontiguousarray(rays[:, 3:6], dtype=np.float32),
            np.ascontiguousarray(rays[:, 6], dtype=np.float32))


def trace(scene, occluded, origins, dirs, tmax):
    query = "OCCLUDED" if occluded else "INTERSECT"
    res = scene.run(origins, dirs, dists=tmax.copy(), query=query)
    return int(np.count_nonzero(res != -1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model", help="OBJ (or anything trimesh loads)")
    ap.add_argument("rays", help="folder of SET.rays files")
    ap.add_argument("--runs", type=int, default=3, help="timed runs a set (median reported), after a warm-up")
    args = ap.parse_args()

    vertices, faces = read_mesh(args.model)
    device = rtcore.EmbreeDevice()
    build_scene(vertices, faces, device)  # warm-up: Embree's thread pool starts
    builds = []
    for _ in range(max(1, args.runs)):
        scene = build_scene(vertices, faces, device, builds)
    print(f"embreex {version('embreex')} {embree_version() or '?'} {statistics.median(b[1] for b in builds):.3f}")
    for name in ("primary", "bounce", "shadow"):
        path = os.path.join(args.rays, f"{name}.rays")
        if not os.path.exists(path):
            continue
        o, d, t = read_rays(path)
        times, hits = [], 0
        for run in range(max(1, args.runs) + 1):
            start = time.thread_time()
            hits = trace(scene, name == "shadow", o, d, t)
            if run:
                times.append(time.thread_time() - start)
        print(f"{name} {len(o)} {hits} {statistics.median(times):.6f}")


if __name__ == "__main__":
    main()
