#!/usr/bin/env python3
"""Embree (through PyPI's embreex, Embree 4) on the rays octsolid's benches trace.

Loads a triangle mesh, builds one Embree scene, and traces
  primary: one ray a pixel through the pixel centres of a pinhole camera,
  shadow:  from every primary hit towards a point light (occlusion queries),
  random:  from a sphere around the mesh's box through random points of the box,
on 1 and on 2 cores, and prints one JSON line: build time, hit counts and the median
rays a second of several runs. With --dump DIR it also writes the rays as raw
little-endian f64 records (origin xyz, unit direction xyz, t_max: 56 bytes a ray;
t_max is +inf for primary and random rays, the distance to the light for shadow rays)
to DIR/primary.rays, DIR/shadow.rays and DIR/random.rays, so octsolid can trace the
very same rays.

embreex's EmbreeScene.run traces one ray at a time (rtcIntersect1 / rtcOccluded1)
in a loop that holds the GIL, so threads do not run both cores: the 2-core figure
comes from 2 worker processes, each with its own copy of the scene, each tracing
half of the rays, timed from a common start to the last one's end.

    target/peers-venv/bin/python benches/peers/embree_rays.py models/bunny-watertight.obj
    ... --size 256x256 --random 65536 --runs 3      # a quick check
"""

import argparse
import ctypes
import json
import math
import multiprocessing as mp
import os
import statistics
import sys
import time
from importlib.metadata import version

import numpy as np
import trimesh
from embreex import mesh_construction, rtcore, rtcore_scene


def vec3(text):
    parts = [float(p) for p in text.split(",")]
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"expected X,Y,Z, got {text!r}")
    return np.array(parts)


def image_size(text):
    parts = text.lower().replace(",", "x").split("x")
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT, got {text!r}")
    return int(parts[0]), int(parts[1])


def now_ns():
    # CLOCK_MONOTONIC is one clock for every process, so worker times compare.
    return time.clock_gettime_ns(time.CLOCK_MONOTONIC)


def load_obj(path):
    """Vertices and triangles of an OBJ's `v` and `f` lines (polygons fanned; materials,
    normals and texture coordinates ignored)."""
    vertices, faces = [], []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                idx = [i - 1 if i > 0 else len(vertices) + i for i in idx]
                faces.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int32)


def read_mesh(path):
    if path.lower().endswith(".obj"):
        return load_obj(path)
    mesh = trimesh.read(path, force="mesh", process=False)
    return (np.ascontiguousarray(mesh.vertices, dtype=np.float64),
            np.ascontiguousarray(mesh.faces, dtype=np.int32))


def build_scene(vertices, faces, device=None, times=None):
    """An Embree scene of the mesh, committed (embreex commits on the first query).
    Appends (upload ms, commit ms) to `times`: the binding's copy of the mesh into
    Embree's buffers (a per-vertex loop in embreex), then Embree's BVH build."""
    t0 = now_ns()
    scene = rtcore_scene.EmbreeScene(device)
    mesh_construction.TriangleMesh(scene, vertices.astype(np.float32), faces)
    t1 = now_ns()
    probe = np.zeros((1, 3), dtype=np.float32)
    scene.run(probe, probe + np.float32(1.0))
    if times is not None:
        times.append(((t1 - t0) / 1e6, (now_ns() - t1) / 1e6))
    return scene


def trace(scene, kind, origins, dirs, tmax):
    """Hits (primary, random) or occluded rays (shadow) among the given rays."""
    if kind == "shadow":
        res = scene.run(origins, dirs, dists=tmax.copy(), query="OCCLUDED")
    else:
        res = scene.run(origins, dirs, dists=tmax.copy(), query="INTERSECT")
    return int(np.count_nonzero(res != -1))


def primary_rays(eye, target, up, fov_deg, width, height):
    """octsolid's pinhole camera: pixel centres, x right, y up, unit directions."""
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    up2 = np.cross(right, forward)
    half = math.tan(math.radians(fov_deg) / 2.0)
    aspect = width / height
    i = np.arange(width * height)
    x = 2.0 * ((i % width) + 0.5) / width - 1.0
    y = 1.0 - 2.0 * ((i // width) + 0.5) / height
    dirs = forward[None, :] + right[None, :] * (x * half * aspect)[:, None] + up2[None, :] * (y * half)[:, None]
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    origins = np.broadcast_to(eye, dirs.shape).copy()
    return origins, dirs, np.full(len(dirs), np.inf)


def shadow_rays(scene, primary, light, lift):
    """From each primary hit, moved back `lift` along the ray, towards the light."""
    o, d, tmax = primary
    t = scene.run(o.astype(np.float32), d.astype(np.float32), dists=tmax.astype(np.float32), query="DISTANCE")
    hit = t < 1e30
    t = t[hit].astype(np.float64)
    origins = o[hit] + d[hit] * (t - lift)[:, None]
    to = light[None, :] - origins
    dist = np.linalg.norm(to, axis=1)
    return origins, to / dist[:, None], dist


def random_rays(lo, hi, count, seed):
    """Origins uniform on the sphere of 1.5x the box's half-diagonal about its centre,
    aimed at uniform points of the box (numpy's PCG64, seeded)."""
    rng = np.random.default_rng(seed)
    centre, size = (lo + hi) / 2.0, hi - lo
    radius = 1.5 * 0.5 * np.linalg.norm(size)
    z = rng.uniform(-1.0, 1.0, count)
    phi = rng.uniform(0.0, 2.0 * math.pi, count)
    s = np.sqrt(1.0 - z * z)
    origins = centre + np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1) * radius
    targets = lo + size * rng.uniform(0.0, 1.0, (count, 3))
    dirs = targets - origins
    dirs /= np.linalg.norm(dirs, axis=1)[:, None]
    return origins, dirs, np.full(count, np.inf)


def as_f32(rays):
    o, d, tmax = rays
    return (np.ascontiguousarray(o, dtype=np.float32), np.ascontiguousarray(d, dtype=np.float32),
            np.ascontiguousarray(tmax, dtype=np.float32))


def dump(path, rays):
    o, d, tmax = rays
    records = np.concatenate([o, d, tmax[:, None]], axis=1).astype("<f8")
    records.tofile(path)


def worker(conn, vertices, faces, rays_by_kind, barrier):
    """One of the 2 processes: its own scene, its half of every kind's rays."""
    scene = build_scene(vertices, faces)
    conn.send("ready")
    while True:
        msg = conn.recv()
        if msg is None:
            return
        kind = msg
        o, d, tmax = rays_by_kind[kind]
        barrier.wait()
        start = now_ns()
        hits = trace(scene, kind, o, d, tmax)
        conn.send((start, now_ns(), hits))


def binding_overhead_ns(device, count=1 << 18):
    """What embreex's per-ray loop costs by itself: rays that all miss a scene of one
    far triangle (Embree culls them at the root), nanoseconds a ray, best of 3."""
    v = np.array([[1e3, 1e3, 1e3], [1e3 + 1, 1e3, 1e3], [1e3, 1e3 + 1, 1e3]], dtype=np.float32)
    scene = build_scene(v.astype(np.float64), np.array([[0, 1, 2]], dtype=np.int32), device)
    o = np.zeros((count, 3), dtype=np.float32)
    d = np.tile(np.array([[0.0, 0.0, -1.0]], dtype=np.float32), (count, 1))
    best = math.inf
    for _ in range(3):
        start = now_ns()
        scene.run(o, d)
        best = min(best, (now_ns() - start) / count)
    return round(best, 1)


def embree_version():
    """The bundled Embree's version number (RTC_DEVICE_PROPERTY_VERSION), if it can be read."""
    try:
        import embreex
        libs = os.path.join(os.path.dirname(os.path.dirname(embreex.__file__)), "embreex.libs")
        name = next(f for f in sorted(os.listdir(libs)) if f.startswith("libembree"))
        lib = ctypes.CDLL(os.path.join(libs, name))
        lib.rtcNewDevice.restype = ctypes.c_void_p
        lib.rtcGetDeviceProperty.restype = ctypes.c_ssize_t
        lib.rtcGetDeviceProperty.argtypes = [ctypes.c_void_p, ctypes.c_int]
        lib.rtcReleaseDevice.argtypes = [ctypes.c_void_p]
        dev = lib.rtcNewDevice(None)
        v = lib.rtcGetDeviceProperty(dev, 0)
        lib.rtcReleaseDevice(dev)
        return f"{v // 10000}.{v // 100 % 100}.{v % 100}"
    except Exception:  # noqa: BLE001 - informational only
        return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("model", help="OBJ, STL, PLY or anything trimesh loads")
    ap.add_argument("--eye", type=vec3, default=vec3("8,9,22"))
    ap.add_argument("--target", type=vec3, default=None, help="default: the bounding box's centre")
    ap.add_argument("--up", type=vec3, default=vec3("0,1,0"))
    ap.add_argument("--fov", type=float, default=30.0, help="vertical field of view, degrees")
    ap.add_argument("--size", type=image_size, default=(1024, 1024), help="WIDTHxHEIGHT primary rays")
    ap.add_argument("--light", type=vec3, default=None,
                    help="point light of the shadow rays; default centre + (2, 3, 4) x the box's diagonal "
                         "(as octsolid's BVH harness)")
    ap.add_argument("--random", type=int, default=1 << 20, help="number of random rays")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--runs", type=int, default=5, help="timed runs a case (median reported), after a warm-up")
    ap.add_argument("--dump", metavar="DIR", help="write primary.rays, shadow.rays, random.rays here")
    args = ap.parse_args()

    vertices, faces = read_mesh(args.model)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre, diag = (lo + hi) / 2.0, float(np.linalg.norm(hi - lo))
    target = centre if args.target is None else args.target
    light = centre + np.array([2.0, 3.0, 4.0]) * diag if args.light is None else args.light

    device = rtcore.EmbreeDevice()
    build_scene(vertices, faces, device)  # warm-up: Embree's thread pool starts
    builds = []
    for _ in range(max(1, args.runs)):
        scene = build_scene(vertices, faces, device, builds)

    width, height = args.size
    primary = primary_rays(args.eye, target, args.up, args.fov, width, height)
    rays = {
        "primary": primary,
        "shadow": shadow_rays(scene, primary, light, 1e-4 * diag),
        "random": random_rays(lo, hi, args.random, args.seed),
    }
    if args.dump:
        os.makedirs(args.dump, exist_ok=True)
        for kind, r in rays.items():
            dump(os.path.join(args.dump, f"{kind}.rays"), r)
    rays32 = {kind: as_f32(r) for kind, r in rays.items()}

    # Two worker processes, started fresh (spawn: no Embree state is forked).
    ctx = mp.get_context("spawn")
    barrier = ctx.Barrier(2)
    workers = []
    for part in range(2):
        halves = {}
        for kind, (o, d, t) in rays32.items():
            h = len(o) // 2
            sl = slice(0, h) if part == 0 else slice(h, None)
            halves[kind] = (o[sl], d[sl], t[sl])
        parent, child = ctx.Pipe()
        p = ctx.Process(target=worker, args=(child, vertices, faces, halves, barrier), daemon=True)
        p.start()
        workers.append((p, parent))
    for _, conn in workers:
        assert conn.recv() == "ready"

    result = {
        "peer": "embreex",
        "embreex": version("embreex"),
        "embree": embree_version(),
        "model": os.path.basename(args.model),
        "triangles": int(len(faces)),
        "build_ms": round(statistics.median(b[1] for b in builds), 3),
        "upload_ms": round(statistics.median(b[0] for b in builds), 3),
        "build_note": "medians of --runs builds on a warm device: build = rtcCommitScene (Embree's BVH "
                      "builder, all threads, quality high as embreex sets it); upload = embreex copying "
                      "the mesh into Embree's buffers",
        "camera": {"eye": args.eye.tolist(), "target": target.tolist(), "up": args.up.tolist(),
                   "fov": args.fov, "size": [width, height]},
        "light": light.tolist(),
        "random_seed": args.seed,
        "binding_overhead_ns_per_ray": binding_overhead_ns(device),
        "parallel": "2 processes, each its own scene and half the rays (embreex holds the GIL)",
        "runs": args.runs,
    }
    for kind, (o, d, t) in rays32.items():
        n = len(o)
        single, hits1 = [], None
        for run in range(args.runs + 1):
            start = now_ns()
            hits1 = trace(scene, kind, o, d, t)
            if run:
                single.append((now_ns() - start) / 1e9)
        double, hits2 = [], None
        for run in range(args.runs + 1):
            for _, conn in workers:
                conn.send(kind)
            replies = [conn.recv() for _, conn in workers]
            hits2 = sum(r[2] for r in replies)
            if run:
                double.append((max(r[1] for r in replies) - min(r[0] for r in replies)) / 1e9)
        if hits1 != hits2:
            sys.exit(f"embree_rays: {kind}: 1 core found {hits1} hits, 2 processes {hits2}")
        result[kind] = {
            "rays": n,
            "occluded" if kind == "shadow" else "hits": hits1,
            "mrays_per_s_1": round(n / statistics.median(single) / 1e6, 4),
            "mrays_per_s_2": round(n / statistics.median(double) / 1e6, 4),
        }
    for p, conn in workers:
        conn.send(None)
        p.join()
    print(json.dumps(result))


if __name__ == "__main__":
    main()
