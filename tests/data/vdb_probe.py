"""Reads a .vdb file with OpenVDB itself (pyopenvdb) and prints what it finds as JSON,
so tests can check octsolid's writer against the reference reader:

    /usr/bin/python3 vdb_probe.py FILE [I J K ...]

For each grid: name, value type, class, background, active voxel count (tiles
included), active bounding box, voxel size, the world position of index (0, 0, 0)
and the values at the given index coordinates.
"""

import json
import sys

import pyopenvdb as vdb

path, coords = sys.argv[1], [int(v) for v in sys.argv[2:]]
points = [tuple(coords[i:i + 3]) for i in range(0, len(coords), 3)]
out = []
for grid in vdb.readAll(path)[0]:
    acc = grid.getConstAccessor()
    lo, hi = grid.evalActiveVoxelBoundingBox()
    out.append({
        "name": grid.name,
        "type": grid.valueTypeName,
        "class": str(grid.gridClass),
        "background": grid.background,
        "active": grid.activeVoxelCount(),
        "leaves": grid.leafCount(),
        "bbox": [list(lo), list(hi)],
        "voxel_size": list(grid.transform.voxelSize()),
        "origin_world": list(grid.transform.indexToWorld((0, 0, 0))),
        "values": [acc.getValue(p) for p in points],
    })
print(json.dumps(out))
