"""Small .vdb seeds for the fuzz corpus, written by OpenVDB itself (octsolid's reader
must also read what it never writes: half floats, fog and bool grids, several grids,
vector grids it skips, grid metadata).

    /usr/bin/python3 fuzz/make_vdb_seeds.py fuzz/corpus/vdb   # needs pyopenvdb (Debian python3-openvdb)

Each file is a few kilobytes, so a mutated case reads in well under a millisecond.
"""

import os
import sys

import pyopenvdb as vdb


def main(out):
    os.makedirs(out, exist_ok=True)

    # A narrow-band level set sphere, as float and as half float.
    for name, half in [("openvdb-sphere.vdb", False), ("openvdb-sphere-half.vdb", True)]:
        g = vdb.createLevelSetSphere(radius=2.0, center=(0.25, -0.5, 1.0), voxelSize=0.5, halfWidth=2.0)
        g.name = "sphere"
        g.saveFloatAsHalf = half
        vdb.write(os.path.join(out, name), grids=[g])

    # A fog volume on a scaled, translated transform (a box of tiles and voxels, a few
    # values below and above the threshold), a bool mask grid and a vector grid in one
    # file.
    h = 0.25
    fog = vdb.FloatGrid(0.0)
    fog.name = "density"
    fog.gridClass = vdb.GridClass.FOG_VOLUME
    fog.transform = vdb.createLinearTransform([[h, 0, 0, 0], [0, h, 0, 0], [0, 0, h, 0], [1.5, -2.0, 0.75, 1]])
    fog.fill((-3, -2, -1), (9, 10, 12), 1.0, True)
    acc = fog.getAccessor()
    for ijk, v in [((0, 0, 0), 0.2), ((4, 5, 6), 0.6), ((20, 0, 0), 0.7), ((-9, -9, -9), 0.9)]:
        acc.setValueOn(ijk, v)
    fog["comment"] = "made by fuzz/make_vdb_seeds.py"
    mask = vdb.BoolGrid(False)
    mask.name = "mask"
    mask.fill((0, 0, 0), (7, 7, 7), True, True)
    mask.getAccessor().setValueOn((12, 3, 3), True)
    velocity = vdb.Vec3SGrid((0.0, 0.0, 0.0))
    velocity.name = "velocity"
    velocity.getAccessor().setValueOn((1, 2, 3), (1.0, 0.0, 0.0))
    vdb.write(os.path.join(out, "openvdb-fog-mask-vector.vdb"), grids=[velocity, fog, mask])


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "fuzz/corpus/vdb")
