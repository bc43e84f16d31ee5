"""Shapes and voxelize against `octsolid shape` and `octsolid build`: the same
files byte for byte, the same node counts and volumes, and volumes within the voxel
shell of the analytic ones."""

import math

import numpy as np
import pytest

import octsolid as o
from conftest import cli, summary_value

# Each primitive as Python makes it, the `octsolid shape` flags that make it, and its
# analytic volume.
PRIMITIVES = [
    (lambda: o.Sphere((0.1, 0, 0), 0.8), ["sphere", "--radius", 0.8, "--center", "0.1,0,0"], 4 / 3 * math.pi * 0.8**3),
    (
        lambda: o.Ellipsoid((0, 0, 0), (1.0, 0.6, 0.4)),
        ["ellipsoid", "--size", "2,1.2,0.8"],
        4 / 3 * math.pi * 1.0 * 0.6 * 0.4,
    ),
    (lambda: o.Box((0, 0, 0), (1.0, 0.5, 0.7)), ["box", "--size", "1,0.5,0.7"], 1.0 * 0.5 * 0.7),
    (
        lambda: o.Cylinder((0, 0, 0.2), "y", 0.4, 1.5),
        ["cylinder", "--axis", "y", "--radius", 0.4, "--height", 1.5, "--center", "0,0,0.2"],
        math.pi * 0.4**2 * 1.5,
    ),
    (
        lambda: o.Cone((0, 0, 0), "z", 0.5, 1.2),
        ["cone", "--radius", 0.5, "--height", 1.2],
        math.pi * 0.5**2 * 1.2 / 3,
    ),
    (
        lambda: o.Torus((0, 0, 0), "x", 0.7, 0.2),
        ["torus", "--axis", "x", "--radius", 0.7, "--tube", 0.2],
        2 * math.pi**2 * 0.7 * 0.2**2,
    ),
]


@pytest.mark.parametrize("make, flags, exact", PRIMITIVES, ids=[p[1][0] for p in PRIMITIVES])
def test_primitive_matches_the_cli(tmp_path, make, flags, exact):
    depth = 6
    shape = make()
    assert isinstance(shape, o.Shape)
    solid = o.voxelize(shape, depth)
    py_file, cli_file = tmp_path / "py.oct", tmp_path / "cli.oct"
    solid.save(py_file)
    out = cli("shape", *flags, "--depth", depth, "-o", cli_file)
    assert py_file.read_bytes() == cli_file.read_bytes()
    assert solid.node_count == summary_value(out, "nodes")
    assert solid.voxel_count == summary_value(out, "voxels")
    assert solid.volume == pytest.approx(summary_value(out, "volume"), abs=1e-6)
    # Independent of the CLI: within the shell of boundary voxels of the exact volume.
    h = solid.voxel_size
    area = solid.measure()["area"]
    assert abs(solid.volume - exact) < area * h
    assert shape.volume == pytest.approx(exact, rel=1e-12)
    assert solid.depth == depth


SCENE = """
[domain]
min = [-1.5, -1.5, -1.5]
edge = 3.0
depth = 6

[[solid]]
name = "part"
shape = {{ {spec} }}
"""

# Shape trees: Python's operators, moves and patterns against the same tree written
# in a scene file and voxelized by `octsolid build`.
TREES = [
    (
        lambda: (o.Box((0, 0, 0), 2) & o.Sphere((0, 0, 0), 1.3)) - o.Cylinder((0, 0, 0), "x", 0.6, 3),
        'difference = [ { intersection = [ { box = { center = [0, 0, 0], size = [2, 2, 2] } }, '
        '{ sphere = { center = [0, 0, 0], radius = 1.3 } } ] }, '
        '{ cylinder = { center = [0, 0, 0], axis = "x", radius = 0.6, height = 3 } } ]',
    ),
    (
        lambda: o.Sphere((0, 0, 0), 1) ^ o.Box((0.5, 0, 0), (1, 1, 1)),
        "xor = [ { sphere = { center = [0, 0, 0], radius = 1 } }, { box = { center = [0.5, 0, 0], size = [1, 1, 1] } } ]",
    ),
    (
        lambda: o.Box((0, 0, 0), (1, 0.4, 0.2)).scale(1.5).rotate("z", 30).translate((0.1, 0.2, 0.3)),
        "transform = { shape = { box = { center = [0, 0, 0], size = [1, 0.4, 0.2] } }, scale = [1.5, 1.5, 1.5], "
        "rotate_axis = [0, 0, 1], rotate_degrees = 30, translate = [0.1, 0.2, 0.3] }",
    ),
    (
        lambda: o.linear_array(o.Sphere((-1, -1, 0), 0.3), (3, 2, 1), (0.8, 0.9, 0)),
        "array = { shape = { sphere = { center = [-1, -1, 0], radius = 0.3 } }, count = [3, 2, 1], step = [0.8, 0.9, 0] }",
    ),
    (
        lambda: o.Cylinder((0, 0, 0), "z", 1.2, 0.3) - o.polar_array(o.Cylinder((0.8, 0, 0), "z", 0.15, 1), "z", (0, 0, 0), 6),
        'difference = [ { cylinder = { center = [0, 0, 0], axis = "z", radius = 1.2, height = 0.3 } }, '
        '{ polar = { shape = { cylinder = { center = [0.8, 0, 0], axis = "z", radius = 0.15, height = 1 } }, '
        'count = 6, axis = "z", center = [0, 0, 0] } } ]',
    ),
    (
        lambda: o.Sphere((0, 0, 0), 1.2) & ~o.HalfSpace((0, 0, 1), 0.25),
        "intersection = [ { sphere = { center = [0, 0, 0], radius = 1.2 } }, "
        "{ complement = { half_space = { normal = [0, 0, 1], offset = 0.25 } } } ]",
    ),
    (
        lambda: o.Box((0, 0, 0), (1.6, 1.2, 1.0)).shell(0.3).round(0.1) | o.Sphere((0.8, 0, 0), 0.4),
        "union = [ { round = { solid = { shell = { solid = { box = { center = [0, 0, 0], size = [1.6, 1.2, 1.0] } }, "
        "thickness = 0.3 } }, radius = 0.1 } }, { sphere = { center = [0.8, 0, 0], radius = 0.4 } } ]",
    ),
]


@pytest.mark.parametrize("make, spec", TREES, ids=["classic", "xor", "transform", "array", "polar", "complement", "offsets"])
def test_shape_tree_matches_a_scene_build(tmp_path, make, spec):
    scene = tmp_path / "tree.toml"
    scene.write_text(SCENE.format(spec=spec))
    cli_file, py_file = tmp_path / "cli.oct", tmp_path / "py.oct"
    cli("build", scene, "--solid", "part", "-o", cli_file)
    solid = o.voxelize(make(), 6, domain=((-1.5, -1.5, -1.5), 3.0))
    solid.save(py_file)
    assert py_file.read_bytes() == cli_file.read_bytes()


def test_offsets_by_another_metric_grow_by_its_unit_ball_over_the_voxels():
    # A voxelized box is a block of voxels: by the cube (Chebyshev) grown by 2 voxels it
    # is the block 4 voxels longer on each axis; by the octahedron (Manhattan) it lies
    # between the block and that cube.
    box = o.voxelize(o.Box((0, 0, 0), (1.2, 0.9, 0.7)), 6, ((-1, -1, -1), 2.0))
    (lo, hi), v = box.bounds, box.voxel_size
    sides = [round((b - a) / v) for a, b in zip(lo, hi)]
    assert box.voxel_count == sides[0] * sides[1] * sides[2]
    cube = box.offset(2, voxels=True, metric="chebyshev")
    assert cube.voxel_count == (sides[0] + 4) * (sides[1] + 4) * (sides[2] + 4)
    octahedron = box.offset(2, voxels=True, metric="manhattan")
    assert box.voxel_count < octahedron.voxel_count < cube.voxel_count
    assert box.round(0.1, metric="chebyshev").voxel_count == box.voxel_count
    with pytest.raises(o.ArgumentError, match="euclidean, manhattan or chebyshev"):
        box.shell(0.1, metric="l2")


def test_offset_nodes_are_the_solid_methods_on_the_voxelized_shape():
    # A node voxelizes its child on the lattice, with its crossings, and applies the
    # operation as the Solid's method does: the same voxels.
    box, domain = o.Box((0, 0, 0), (1.2, 0.9, 0.7)), ((-1, -1, -1), 2.0)
    solid = o.voxelize(box, 6, domain)
    for node, method in [
        (box.offset(0.1), solid.offset(0.1)),
        (box.offset(-2, voxels=True), solid.offset(-2, voxels=True)),
        (box.shell(0.2, outward=True), solid.shell(0.2, outward=True)),
        (box.round(0.15, convex=True), solid.round(0.15, convex=True)),
    ]:
        assert np.array_equal(o.voxelize(node, 6, domain).keys(), method.keys())
    with pytest.raises(o.ArgumentError):
        box.shell(-1)


def test_shape_operators_agree_with_solid_operators():
    # Voxels are sampled at their centres, so the voxels of a union are the union of
    # the voxels: the shape operators against the solid operators, key for key.
    a, b = o.Sphere((0, 0, 0), 0.9), o.Box((0.4, 0.2, 0), (1.0, 1.2, 0.8))
    domain = ((-1, -1, -1), 2.0)
    va, vb = o.voxelize(a, 6, domain), o.voxelize(b, 6, domain)
    for shape, solid in [(a | b, va | vb), (a & b, va & vb), (a - b, va - vb), (a ^ b, va ^ vb)]:
        assert np.array_equal(o.voxelize(shape, 6, domain).keys(), solid.keys())
    dense = o.voxelize(~b & o.Box((0, 0, 0), 2), 6, domain).to_numpy()
    assert np.array_equal(dense, ~vb.to_numpy())


def test_unbounded_shape_needs_a_domain():
    with pytest.raises(o.ArgumentError, match="unbounded"):
        o.voxelize(o.HalfSpace((0, 0, 1), 0), 5)
    half = o.voxelize(o.HalfSpace((0, 0, 1), 0), 5, domain=((-1, -1, -1), 2.0))
    assert half.volume == pytest.approx(4.0)


def test_keyword_arguments_and_axes():
    a = o.Cylinder(center=(0, 0, 0), axis=(0, 1, 0), radius=0.5, height=1.0)
    b = o.Cylinder((0, 0, 0), "Y", 0.5, 1.0)
    assert np.array_equal(o.voxelize(a, 5).keys(), o.voxelize(shape=b, depth=5).keys())
    assert o.Box((0, 0, 0), 1.0).bounds == ([-0.5] * 3, [0.5] * 3)
