#!/usr/bin/env python3
"""The classic CSG part by manifold3d (PyPI), an exact mesh boolean of polygonal
primitives, written as a binary PLY for the surface-quality table (issue 38):

    part = (cube of side 2 & sphere of radius 1.3) - three cylinders of radius 0.6
           along x, y and z through the origin (3 long)

every circle a polygon of --segments sides (96 for the table's manifold3d row; 1024
for the "exact" mesh OpenVDB's level set is made from, surface_openvdb.py). One JSON
line: segments, triangles, the seconds of the boolean (from the primitives to the
evaluated mesh; manifold3d evaluates lazily and num_tri() forces it) and of the whole
script (imports and writing included, from its first line).

    target/peers-venv/bin/python benches/peers/surface_manifold.py --segments 96 -o manifold-96.ply
"""

import time

START = time.perf_counter()

import argparse  # noqa: E402
import json  # noqa: E402

import numpy as np  # noqa: E402


def classic(M, OpType, segments):
    """The part as manifold_plate.py builds it (the same primitives, one batch)."""
    body = M.cube((2.0, 2.0, 2.0), center=True) ^ M.sphere(1.3, circular_segments=segments)
    bore = M.cylinder(3.0, 0.6, circular_segments=segments, center=True)  # along z
    bores = [bore, bore.rotate((90.0, 0.0, 0.0)), bore.rotate((0.0, 90.0, 0.0))]
    return M.batch_boolean([body] + bores, OpType.Subtract)


def write_ply(path, points, triangles):
    """Binary little-endian PLY: float32 x y z, faces as uchar 3 + three int32."""
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
    ap.add_argument("--segments", type=int, default=96)
    ap.add_argument("-o", "--output", required=True, help="the mesh, .ply")
    args = ap.parse_args()
    from importlib.metadata import version

    from manifold3d import Manifold as M
    from manifold3d import OpType

    start = time.perf_counter()
    part = classic(M, OpType, args.segments)
    triangles = part.num_tri()
    boolean_s = time.perf_counter() - start
    mesh = part.to_mesh()
    write_ply(args.output, np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts))
    print(
        json.dumps(
            {
                "peer": "manifold3d",
                "version": version("manifold3d"),
                "segments": args.segments,
                "triangles": triangles,
                "boolean_s": round(boolean_s, 6),
                "process_s": round(time.perf_counter() - START, 6),
                "output": args.output,
            }
        ),
        flush=True,
    )


if __name__ == "__main__":
    main()
