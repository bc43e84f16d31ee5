"""Solids against the CLI on the same input: set operations (`octsolid csg`), files
(`-o`, `export`), moves (`transform`), offsets (`offset`, `shell`, `round`),
measures (`info --json`), loaders (`voxelize`), and the arrays against independent
counts."""

import numpy as np
import pytest
import trimesh

import octsolid as o
from conftest import MODELS, cli, cli_info, summary_value


def same_names(tmp_path, name):
    """Two paths of one file name (formats that record the file's stem: .vdb, .glb),
    in folders py/ and cli/."""
    (tmp_path / "py").mkdir()
    (tmp_path / "cli").mkdir()
    return tmp_path / "py" / name, tmp_path / "cli" / name


@pytest.fixture
def two_files(tmp_path):
    """A ball and a box voxelized over one domain, and a box over another (coarser,
    shifted) domain, saved as .oct files."""
    d = ((-1, -1, -1), 2.0)
    ball = o.voxelize(o.Sphere((0, 0, 0), 0.8), 6, d)
    box = o.voxelize(o.Box((0.5, 0.3, 0.1), (1.0, 0.9, 0.7)), 6, d)
    other = o.voxelize(o.Box((0.9, 0, 0), (0.8, 0.8, 0.8)), 5)
    paths = [tmp_path / n for n in ("ball.oct", "box.oct", "other.oct")]
    for solid, path in zip((ball, box, other), paths):
        solid.save(path)
    return paths


@pytest.mark.parametrize("op, name", [("__or__", "union"), ("__and__", "intersect"), ("__sub__", "difference"), ("__xor__", "xor")])
def test_set_operations_match_csg(tmp_path, two_files, op, name):
    ball, box, other = two_files
    for a, b in [(ball, box), (ball, other)]:
        result = getattr(o.load(a), op)(o.load(b))
        py_file, cli_file = tmp_path / "py.oct", tmp_path / "cli.oct"
        result.save(py_file)
        out = cli("csg", name, a, b, "-o", cli_file)
        assert py_file.read_bytes() == cli_file.read_bytes(), f"{name} of {a.name} and {b.name}"
        assert result.node_count == summary_value(out, "nodes")


def test_set_operations_count_like_dense_grids(two_files):
    ball, box = o.load(two_files[0]), o.load(two_files[1])
    a, b = ball.to_numpy(), box.to_numpy()
    for result, dense in [(ball | box, a | b), (ball & box, a & b), (ball - box, a & ~b), (ball ^ box, a ^ b)]:
        assert result.voxel_count == dense.sum()
        assert np.array_equal(result.to_numpy(), dense)


@pytest.mark.parametrize("ext", ["oct", "vox", "binvox", "vdb", "obj", "stl", "ply", "glb"])
def test_save_writes_the_cli_bytes(tmp_path, ext):
    solid = o.voxelize(o.Torus((0, 0, 0), "z", 0.7, 0.25), 5)
    py_file, cli_file = same_names(tmp_path, f"ring.{ext}")
    size = solid.save(py_file)
    cli("shape", "torus", "--radius", 0.7, "--tube", 0.25, "--depth", 5, "-o", cli_file)
    assert size == py_file.stat().st_size
    assert py_file.read_bytes() == cli_file.read_bytes()
    if ext in ("oct", "binvox", "vdb"):
        assert o.load(py_file).voxel_count == solid.voxel_count


@pytest.mark.parametrize(
    "ext, flags",
    [("stl", []), ("obj", []), ("ply", ["--surface", "voxels"]), ("glb", []), ("glb", ["--surface", "voxels"])],
)
def test_export_writes_the_cli_bytes(tmp_path, ext, flags):
    source = tmp_path / "ring.oct"
    o.voxelize(o.Torus((0, 0, 0), "y", 0.6, 0.3), 5).save(source)
    py_file, cli_file = same_names(tmp_path, f"ring.{ext}")
    surface = "voxels" if flags else "smooth"
    o.load(source).export(py_file, surface=surface)
    cli("export", source, "-o", cli_file, *flags)
    assert py_file.read_bytes() == cli_file.read_bytes()


def test_export_with_a_normal_tolerance_writes_the_cli_bytes(tmp_path):
    source = tmp_path / "ball.oct"
    o.voxelize(o.Sphere((0.01, -0.02, 0.03), 0.8), 6).save(source)
    py_file, cli_file = same_names(tmp_path, "ball.obj")
    o.load(source).export(py_file, tolerance=0.2, normal_tolerance=1.5)
    cli("export", source, "-o", cli_file, "--tolerance", 0.2, "--normal-tolerance", 1.5)
    assert py_file.read_bytes() == cli_file.read_bytes()


def test_a_normal_tolerance_turns_the_faces_less_from_the_sphere():
    # The oracle: the sphere's exact normal, the direction from its centre to each
    # face's centroid.
    centre = np.array((0.01, -0.02, 0.03))
    solid = o.voxelize(o.Sphere(tuple(centre), 0.8), 6)

    def faces_and_turns(normal_tolerance):
        vertices, faces = solid.mesh(tolerance=0.5, normal_tolerance=normal_tolerance)
        corners = vertices[faces]
        normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        radial = corners.mean(axis=1) - centre
        lengths = np.linalg.norm(normals, axis=1)
        cosines = np.einsum("ij,ij->i", normals, radial) / lengths / np.linalg.norm(radial, axis=1)
        turns = np.degrees(np.arccos(np.clip(cosines, -1, 1)))
        # The share of the area turning more than 5 degrees: by area, because a few
        # slivers the bound leaves alone (the same faces in both meshes, under 0.01% of
        # the area) turn far whatever it is.
        return len(faces), np.median(turns), lengths[turns > 5].sum() / lengths.sum()

    loose_count, loose_median, loose_beyond = faces_and_turns(None)
    tight_count, tight_median, tight_beyond = faces_and_turns(1.0)
    assert tight_count > loose_count
    assert tight_median < loose_median and tight_beyond < loose_beyond / 2
    with pytest.raises(ValueError, match="normal_tolerance"):
        solid.mesh(tolerance=0.1, normal_tolerance=-1.0)


def test_mesh_arrays_are_the_exported_mesh(tmp_path):
    solid = o.voxelize(o.Sphere((0, 0, 0), 0.9), 5)
    vertices, faces = solid.mesh()
    assert vertices.dtype == np.float64 and vertices.shape[1] == 3
    assert faces.dtype == np.uint32 and faces.shape[1] == 3
    solid.export(tmp_path / "s.obj")
    exported = trimesh.load(tmp_path / "s.obj", force="mesh", process=False)
    assert np.allclose(exported.vertices, vertices)
    assert np.array_equal(exported.faces, faces)
    mesh = solid.to_trimesh()
    assert mesh.is_watertight
    # The smooth surface encloses the ball's volume about as well as the voxels do.
    assert mesh.volume == pytest.approx(4 / 3 * np.pi * 0.9**3, rel=0.02)
    # The staircase's vertices are lattice points.
    boxy, _ = solid.mesh(surface="voxels")
    (lo, _), h = solid.domain, solid.voxel_size
    steps = (boxy - np.array(lo)) / h
    assert np.allclose(steps, np.round(steps), atol=1e-9)


def test_keys_share_memory_and_count_the_voxels():
    solid = o.voxelize(o.Sphere((0, 0, 0), 0.8), 6)
    keys = solid.keys()
    assert keys.dtype == np.uint64 and len(keys) == solid.node_count == len(solid)
    assert not keys.flags.writeable and not keys.flags.owndata
    assert np.all(keys[1:] > keys[:-1])
    # A key's lowest set bit is at 3k: its node covers 8^k voxels.
    k = np.array([(int(key) & -int(key)).bit_length() - 1 for key in keys]) // 3
    assert (8 ** k).sum() == solid.voxel_count == solid.to_numpy().sum()
    with pytest.raises(ValueError):
        keys[0] = 1
    del solid  # the array keeps the solid's memory alive
    assert int(keys[-1]) > 0


def test_to_numpy_places_voxels_and_refuses_large_grids():
    d = ((0, 0, 0), 8.0)
    solid = o.voxelize(o.Box((1.5, 2.5, 4.5), (1, 1, 1)), 3, d)
    grid = solid.to_numpy()
    assert grid.shape == (8, 8, 8) and grid.sum() == 1 and grid[1, 2, 4]
    assert solid.contains((1.5, 2.5, 4.5)) and not solid.contains((2.5, 2.5, 4.5))
    with pytest.raises(o.ArgumentError, match="max_voxels"):
        solid.to_numpy(max_voxels=100)


def test_measure_matches_info(tmp_path):
    path = tmp_path / "e.oct"
    solid = o.voxelize(o.Ellipsoid((0.2, 0, 0), (0.9, 0.5, 0.4)), 6)
    solid.save(path)
    info, m = cli_info(path), solid.measure()
    assert m["volume"] == pytest.approx(info["volume"], rel=1e-12)
    assert m["area"] == pytest.approx(info["voxel_estimate_area"], rel=1e-12)
    assert m["voxel_face_area"] == pytest.approx(info["voxel_face_area"], rel=1e-12)
    assert m["centroid"] == pytest.approx(info["centre_of_mass"], abs=1e-12)
    assert np.allclose(m["inertia"], info["inertia"], rtol=1e-12, atol=1e-15)
    assert m["components"] == info["components"] == 1
    assert solid.node_count == info["nodes"] and solid.depth == info["depth"]
    (lo, hi) = solid.bounds
    assert lo == pytest.approx(info["bounds"]["min"]) and hi == pytest.approx(info["bounds"]["max"])
    # Independent: the centroid is the ellipsoid's centre, the inertia about x is
    # m (b^2 + c^2) / 5.
    assert m["centroid"] == pytest.approx([0.2, 0, 0], abs=solid.voxel_size / 4)
    assert m["inertia"][0, 0] == pytest.approx(m["volume"] * (0.5**2 + 0.4**2) / 5, rel=0.03)


@pytest.mark.parametrize(
    "kwargs, flags",
    [
        ({"translate": (0.25, 0.0, -0.125)}, ["--translate", "0.25,0,-0.125"]),
        ({"rotate": [("z", 90), ("x", 180)]}, ["--rotate", "z,90", "--rotate", "x,180"]),
        ({"rotate": [("y", 30)], "scale": 1.2}, ["--rotate", "y,30", "--scale", "1.2"]),
        ({"translate": (0.1, 0.1, 0.1), "depth": 5}, ["--translate", "0.1,0.1,0.1", "--depth", "5"]),
    ],
)
def test_transform_matches_the_cli(tmp_path, kwargs, flags):
    source = tmp_path / "in.oct"
    o.voxelize(o.Box((0.2, 0, 0), (1.0, 0.6, 0.4)) | o.Sphere((-0.3, 0, 0), 0.4), 6).save(source)
    py_file, cli_file = tmp_path / "py.oct", tmp_path / "cli.oct"
    o.load(source).transform(**kwargs).save(py_file)
    cli("transform", source, "-o", cli_file, *flags)
    assert py_file.read_bytes() == cli_file.read_bytes()


@pytest.mark.parametrize(
    "method, args, flags",
    [
        ("offset", (0.1,), ["offset", "--by", 0.1]),
        ("offset", (-0.1,), ["offset", "--by", -0.1]),
        ("shell", (0.08,), ["shell", "--thickness", 0.08]),
        ("round", (0.15,), ["round", "--radius", 0.15]),
    ],
)
def test_offsets_match_the_cli(tmp_path, method, args, flags):
    source = tmp_path / "in.oct"
    o.voxelize(o.Box((0, 0, 0), (1.2, 0.8, 0.6)), 5).save(source)
    py_file, cli_file = tmp_path / "py.oct", tmp_path / "cli.oct"
    result = getattr(o.load(source), method)(*args)
    result.save(py_file)
    cli(flags[0], source, *flags[1:], "-o", cli_file)
    assert py_file.read_bytes() == cli_file.read_bytes()


def test_offset_of_a_box_grows_it_by_the_distance():
    # Independent: a box grown by r is the box, its faces' slabs, edges' quarter
    # cylinders and corners' eighth balls: V + A r + (pi/4) E r^2 + (4/3) pi r^3.
    (a, b, c), r = (1.0, 0.75, 0.5), 0.125
    box = o.voxelize(o.Box((0, 0, 0), (a, b, c)), 7, ((-1, -1, -1), 2.0))
    grown = box.offset(r)
    exact = a * b * c + 2 * (a * b + b * c + a * c) * r + np.pi * (a + b + c) * r * r + 4 / 3 * np.pi * r**3
    assert grown.volume == pytest.approx(exact, rel=0.02)


def test_load_mesh_and_from_mesh_match_voxelize(tmp_path):
    model = MODELS / "bunny-watertight.obj"
    py_file, cli_file, arrays_file = tmp_path / "py.oct", tmp_path / "cli.oct", tmp_path / "arrays.oct"
    solid = o.load_mesh(model, depth=6)
    solid.save(py_file)
    out = cli("voxelize", model, "--depth", 6, "-o", cli_file)
    assert py_file.read_bytes() == cli_file.read_bytes()
    assert solid.volume == pytest.approx(summary_value(out, "volume"), abs=1e-6)
    mesh = trimesh.load(model, force="mesh", process=False)
    from_arrays = o.from_mesh(mesh.vertices, mesh.faces, 6)
    assert np.array_equal(from_arrays.keys(), solid.keys())
    from_arrays.save(arrays_file)
    # The mesh's own volume, within the voxel shell.
    assert abs(solid.volume - mesh.volume) < solid.measure()["area"] * solid.voxel_size
    winding = o.from_mesh(vertices=mesh.vertices, faces=mesh.faces.astype(np.uint32), depth=6, inside="winding")
    assert winding.voxel_count == pytest.approx(solid.voxel_count, rel=0.01)


def test_load_reads_every_solid_format(tmp_path):
    solid = o.voxelize(o.Cone((0, 0, 0), "z", 0.5, 1.0), 5)
    for ext in ("oct", "binvox", "vdb", "octs"):
        path = tmp_path / f"c.{ext}"
        solid.save(path)
        back = o.load(path)
        assert back.voxel_count == solid.voxel_count, ext
    assert o.load(tmp_path / "c.oct").domain == solid.domain
