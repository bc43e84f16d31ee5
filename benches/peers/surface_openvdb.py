#!/usr/bin/python3
"""OpenVDB's volumeToMesh (Debian's python3-openvdb, run by Debian's /usr/bin/python3)
on the classic CSG part, for the surface-quality table (issue 38).

Reads an exact mesh of the part (the 1024-segment manifold3d mesh that
surface_manifold.py writes, binary PLY; or any closed triangle OBJ), makes a narrow-band level set of it with
`FloatGrid.createLevelSetFromPolygons` at the voxel size --voxel (default 2.2 / 512:
octsolid's depth 9 in the cube [-1.1, 1.1]^3; half-width 3 voxels, OpenVDB's
default), and meshes its zero level with `convertToPolygons` (volumeToMesh) at
--adaptivity; quads are split into two triangles. Writes a binary PLY and prints one
JSON line: triangles, seconds of the level set, of the meshing, and of the whole
script (imports, reading and writing included, from its first line).

    /usr/bin/python3 benches/peers/surface_openvdb.py exact-1024.ply --adaptivity 0.1 -o vdb-0.1.ply
"""

import time

START = time.perf_counter()

import argparse  # noqa: E402
import json  # noqa: E402

import numpy as np  # noqa: E402
import pyopenvdb as vdb  # noqa: E402


def read_ply(path):
    """The binary PLY surface_manifold.py writes (float32 points, uchar-3 int32 faces)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().split("\n")
    counts = {line.split()[1]: int(line.split()[2]) for line in header if line.startswith("element")}
    nv, nf = counts["vertex"], counts["face"]
    points = np.frombuffer(data, dtype="<f4", count=3 * nv, offset=end).reshape(nv, 3)
    faces = np.frombuffer(data, dtype=[("n", "u1"), ("v", "<i4", (3,))], count=nf, offset=end + 12 * nv)
    assert (faces["n"] == 3).all(), "triangles only"
    return points.astype(np.float64), faces["v"].astype(np.int32)


def read_obj(path):
    """A triangle OBJ's `v` and `f` lines (1-based indices, `f a/b/c` forms allowed)."""
    points, triangles = [], []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if not fields:
                continue
            if fields[0] == "v":
                points.append([float(x) for x in fields[1:4]])
            elif fields[0] == "f":
                corners = [int(x.split("/")[0]) - 1 for x in fields[1:]]
                assert len(corners) == 3, "triangles only"
                triangles.append(corners)
    return np.array(points, dtype=np.float64), np.array(triangles, dtype=np.int32)


def write_ply(path, points, triangles):
    points = np.ascontiguousarray(points, dtype="<f4")
    faces = np.empty(len(triangles), dtype=[("n", "u1"), ("v", "<i4", (3,))])
    faces["n"] = 3
    faces["v"] = triangles
    with open(path, "wb") as f:
        f.write(
            (
                "ply\nformat binary_little_endian 1.0\n"
                f"element vertex {len(points)}\nproperty float x\nproperty float y\nproperty float z\n"
                f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
            ).encode()
        )
        f.write(points.tobytes())
        f.write(faces.tobytes())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("input", help="the exact mesh: binary PLY (surface_manifold.py --segments 1024) or a triangle OBJ")
    ap.add_argument("--voxel", type=float, default=2.2 / 512)
    ap.add_argument("--adaptivity", type=float, default=0.0)
    ap.add_argument("-o", "--output", required=True, help="the mesh, .ply")
    args = ap.parse_args()
    points, triangles = read_obj(args.input) if args.input.endswith(".obj") else read_ply(args.input)
    start = time.perf_counter()
    grid = vdb.FloatGrid.createLevelSetFromPolygons(
        points, triangles=triangles, transform=vdb.createLinearTransform(voxelSize=args.voxel)
    )
    level_set_s = time.perf_counter() - start
    start = time.perf_counter()
    out_points, tris, quads = grid.convertToPolygons(isovalue=0.0, adaptivity=args.adaptivity)
    meshing_s = time.perf_counter() - start
    tris = np.asarray(tris, dtype=np.int32).reshape(-1, 3)
    quads = np.asarray(quads, dtype=np.int32).reshape(-1, 4)
    # OpenVDB winds its polygons clockwise seen from outside (its level sets are negative
    # inside); the table's normals are compared as written, so they are reversed here.
    all_tris = np.concatenate([tris, quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])[:, ::-1]
    write_ply(args.output, out_points, all_tris)
    print(
        json.dumps(
            {
                "peer": "openvdb",
                "version": "%d.%d.%d" % vdb.LIBRARY_VERSION,
                "voxel": args.voxel,
                "adaptivity": args.adaptivity,
                "active_voxels": grid.activeVoxelCount(),
                "triangles": len(all_tris),
                "level_set_s": round(level_set_s, 6),
                "meshing_s": round(meshing_s, 6),
                "process_s": round(time.perf_counter() - START, 6),
                "output": args.output,
            }
        ),
        flush=True,
    )


if __name__ == "__main__":
    main()
