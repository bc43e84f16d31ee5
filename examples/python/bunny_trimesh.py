"""The Stanford bunny from a trimesh mesh: the watertight bunny of models/ read by
trimesh, its vertex and face arrays voxelized by octsolid, a tunnel bored through
it, and the result handed back to trimesh as a mesh.

Run: python examples/python/bunny_trimesh.py [OUT_FOLDER] [--depth D]
(writes bunny.oct and bunny.ply into OUT_FOLDER, default example-output/python/).
"""

import pathlib

import trimesh

import octsolid as o
from command_line import command_line

MODEL = pathlib.Path(__file__).resolve().parents[2] / "models" / "bunny-watertight.obj"


def main():
    args = command_line(__doc__, depth=7)
    out = args.out

    mesh = trimesh.load(MODEL, force="mesh", process=False)
    bunny = o.from_mesh(mesh.vertices, mesh.faces, args.depth)
    print(f"trimesh: {len(mesh.faces)} faces, volume {mesh.volume:.6f}")
    print(f"octsolid at depth {args.depth}: {bunny.node_count} nodes, volume {bunny.volume:.6f}")

    # A tunnel through the body along x, voxelized in the bunny's own domain.
    (lo, hi) = bunny.bounds
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    tunnel = o.voxelize(o.Cylinder(centre, "x", 0.15 * (hi[2] - lo[2]), 2 * (hi[0] - lo[0])), args.depth, bunny.domain)
    bored = bunny - tunnel
    bored.save(out / "bunny.oct")
    back = bored.to_trimesh()
    back.export(out / "bunny.ply")
    print(f"bored: volume {bored.volume:.6f}; back in trimesh: {len(back.faces)} faces, watertight {back.is_watertight}")


if __name__ == "__main__":
    main()
