"""Reference files for tests/formats.rs, written by independent tools.

    make_reference_files.py vdb OUT_DIR      # needs pyopenvdb (Debian python3-openvdb)
    make_reference_files.py binvox OUT_DIR   # needs the PyPI `binvox` and `trimesh` packages, numpy >= 2

Each set gets a `shapes.json` with the analytic shapes and transforms the tests
rebuild the expected occupancy from; the files themselves are what the tools wrote.
"""

import json
import math
import os
import sys


def write_vdb(out):
    import pyopenvdb as vdb

    shapes = {"library_version": list(vdb.LIBRARY_VERSION)}

    # A narrow-band level set sphere: inside where the signed distance is negative.
    sphere = {"center": [1.25, -0.5, 2.0], "radius": 6.3, "voxel_size": 0.5, "half_width": 3.0}
    for name, half in [("sphere.vdb", False), ("sphere_half.vdb", True)]:
        g = vdb.createLevelSetSphere(
            radius=sphere["radius"],
            center=tuple(sphere["center"]),
            voxelSize=sphere["voxel_size"],
            halfWidth=sphere["half_width"],
        )
        g.name = "sphere"
        g.saveFloatAsHalf = half
        vdb.write(os.path.join(out, name), grids=[g])
    shapes["sphere"] = sphere

    # A fog volume: a box of 1s (filled as tiles where the tree allows), a few voxels
    # changed, on a scaled and translated transform.
    box = {"min": [-10, -3, -1], "max": [130, 128, 135]}
    voxels = [
        [[0, 0, 0], 0.2],
        [[64, 70, 100], 0.2],
        [[130, 128, 135], 0.2],
        [[100, 100, 50], 0.6],
        [[200, 0, 0], 0.7],
        [[-50, -50, -50], 0.9],
        [[150, 10, 10], 0.4],
    ]
    h, t = 0.25, [1.5, -2.0, 0.75]
    density = vdb.FloatGrid(0.0)
    density.name = "density"
    density.gridClass = vdb.GridClass.FOG_VOLUME
    density.transform = vdb.createLinearTransform(
        [[h, 0, 0, 0], [0, h, 0, 0], [0, 0, h, 0], [t[0], t[1], t[2], 1]]
    )
    density.fill(tuple(box["min"]), tuple(box["max"]), 1.0, True)
    acc = density.getAccessor()
    for ijk, v in voxels:
        acc.setValueOn(tuple(ijk), v)

    # A bool grid: a 64^3 block and a ball of voxels beside it.
    mask_box = {"min": [0, 0, 0], "max": [63, 63, 63]}
    ball = {"center": [100, 20, 20], "radius": 7.5}
    mask = vdb.BoolGrid(False)
    mask.name = "mask"
    mask.fill(tuple(mask_box["min"]), tuple(mask_box["max"]), True, True)
    acc = mask.getAccessor()
    r = int(math.ceil(ball["radius"]))
    c = ball["center"]
    for x in range(c[0] - r, c[0] + r + 1):
        for y in range(c[1] - r, c[1] + r + 1):
            for z in range(c[2] - r, c[2] + r + 1):
                if (x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2 < ball["radius"] ** 2:
                    acc.setValueOn((x, y, z), True)
    vdb.write(os.path.join(out, "fog_and_mask.vdb"), grids=[density, mask])
    shapes["density"] = {"box": box, "voxels": voxels, "voxel_size": h, "translation": t}
    shapes["mask"] = {"box": mask_box, "ball": ball}
    for name in ["sphere.vdb", "sphere_half.vdb", "fog_and_mask.vdb"]:
        meta = vdb.readAllGridMetadata(os.path.join(out, name))
        shapes.setdefault("grids", {})[name] = [
            {"name": g.name, "type": g.valueTypeName, "active_voxels": g.metadata.get("file_voxel_count")}
            for g in meta
        ]
    with open(os.path.join(out, "shapes.json"), "w") as f:
        json.dump(shapes, f, indent=1, sort_keys=True)


def write_binvox(out):
    import numpy as np
    from binvox import Binvox

    shapes = {}
    # A torus around z, shifted along x so that x and y differ, in a 64^3 grid.
    torus = {
        "dim": 64,
        "translate": [-1.5, 0.25, 2.0],
        "scale": 3.0,
        "center": [0.2, 1.75, 3.5],
        "major": 1.0,
        "minor": 0.35,
    }
    # An ellipsoid with three different semi-axes in a 50^3 grid (padded to 64).
    ellipsoid = {"dim": 50, "translate": [0.0, 0.0, 0.0], "scale": 1.0, "center": [0.5, 0.5, 0.5],
                 "semi_axes": [0.45, 0.3, 0.15]}
    for name, shape, inside in [
        ("torus64.binvox", torus, lambda p, s: (math.hypot(p[0], p[1]) - s["major"]) ** 2 + p[2] ** 2 < s["minor"] ** 2),
        ("ellipsoid50.binvox", ellipsoid,
         lambda p, s: sum((p[a] / s["semi_axes"][a]) ** 2 for a in range(3)) < 1.0),
    ]:
        d = shape["dim"]
        data = np.zeros((d, d, d), dtype=bool)
        for i in range(d):
            for j in range(d):
                for k in range(d):
                    p = [shape["translate"][a] + shape["scale"] * (ijk + 0.5) / d - shape["center"][a]
                         for a, ijk in enumerate((i, j, k))]
                    data[i, j, k] = inside(p, shape)
        Binvox(data, [d, d, d], shape["translate"], shape["scale"], "xyz", "dense").write(os.path.join(out, name))
        shape["voxels"] = int(data.sum())
        shapes[name] = shape
    shapes.update(write_trimesh_binvox(out))
    with open(os.path.join(out, "shapes.json"), "w") as f:
        json.dump(shapes, f, indent=1, sort_keys=True)


def write_trimesh_binvox(out):
    """A ball written by trimesh's own binvox writer, which adds a comment line to the
    header and records its grid its own way: `translate` the first voxel's centre,
    `scale` the distance between the first and last centres (`pitch (n - 1)`)."""
    import numpy as np
    import trimesh
    from trimesh.exchange.binvox import export_binvox

    ball = {"dim": 40, "pitch": 0.05, "first_centre": [-1.0, -0.5, 0.25], "radius": 0.83,
            "writer": "trimesh " + trimesh.__version__}
    d, pitch = ball["dim"], ball["pitch"]
    ball["center"] = [c + pitch * (d - 1) / 2 for c in ball["first_centre"]]
    idx = np.indices((d, d, d)).reshape(3, -1).T
    centres = np.array(ball["first_centre"]) + pitch * idx
    filled = (np.linalg.norm(centres - np.array(ball["center"]), axis=1) < ball["radius"]).reshape(d, d, d)
    transform = trimesh.transformations.scale_and_translate(scale=pitch, translate=ball["first_centre"])
    grid = trimesh.voxel.VoxelGrid(trimesh.voxel.encoding.DenseEncoding(filled), transform=transform)
    with open(os.path.join(out, "ball40-trimesh.binvox"), "wb") as f:
        f.write(export_binvox(grid))
    ball["voxels"] = int(filled.sum())
    return {"ball40-trimesh.binvox": ball}


if __name__ == "__main__":
    kind, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    {"vdb": write_vdb, "binvox": write_binvox}[kind](out)
