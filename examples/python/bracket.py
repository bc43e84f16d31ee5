"""An angle bracket with a bolt circle, exported to STL: a base plate with a ring of
six bolt holes around a centre bore, an upright wall with two holes, and a gusset,
then its smooth surface written as a closed STL mesh for a printer or a slicer.

Run: python examples/python/bracket.py [OUT_FOLDER] [--depth D]
(writes bracket.oct and bracket.stl into OUT_FOLDER, default example-output/python/).
"""

import octsolid as o
from command_line import command_line


def bracket():
    """The bracket as a shape, in millimetres, standing on z = 0."""
    plate = o.Box((0, 0, 4), (80, 80, 8))
    wall = o.Box((0, 36, 30), (80, 8, 60))
    # The gusset: the corner between plate and wall below the plane z - y = 18.
    gusset = o.Box((0, 11.5, 28.5), (6, 43, 43)) & o.HalfSpace((0, -1, 1), 18)
    body = plate | wall | gusset
    bore = o.Cylinder((0, -4, 4), "z", 12, 20)
    bolt = o.Cylinder((22, -4, 4), "z", 3.5, 20)
    bolts = o.polar_array(bolt, "z", (0, -4, 0), 6)
    wall_holes = o.linear_array(o.Cylinder((-20, 36, 40), "y", 4, 20), (2, 1, 1), (40, 0, 0))
    return body - bore - bolts - wall_holes


def main():
    args = command_line(__doc__, depth=8)
    out = args.out

    solid = o.voxelize(bracket(), args.depth)
    solid.save(out / "bracket.oct")
    size = solid.export(out / "bracket.stl")
    m = solid.measure()
    print(f"bracket at depth {args.depth}: {solid.node_count} nodes, volume {solid.volume:.1f} mm^3")
    print(f"{m['components']} component(s), boundary area {m['area']:.1f} mm^2")
    print(f"wrote {out / 'bracket.stl'} ({size} bytes)")


if __name__ == "__main__":
    main()
