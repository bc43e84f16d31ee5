"""Bad input raises octsolid.Error (of the kind that fits: OSError, ValueError,
MemoryError) with the library's message naming the file and place; it never crashes
the interpreter."""

import errno
import os
import warnings

import numpy as np
import pytest

import octsolid as o
from conftest import SCENES


def test_a_missing_file_is_a_file_error(tmp_path):
    missing = tmp_path / "missing.oct"
    with pytest.raises(o.FileError) as caught:
        o.load(missing)
    e = caught.value
    assert isinstance(e, o.Error) and isinstance(e, OSError)
    assert str(missing) in str(e) and e.filename == str(missing)
    assert e.errno == errno.ENOENT and e.strerror == os.strerror(errno.ENOENT), (e.errno, e.strerror)
    with pytest.raises(OSError):
        o.load_mesh(tmp_path / "missing.stl")


def test_a_malformed_file_names_the_file_and_place(tmp_path):
    bad = tmp_path / "bad.oct"
    bad.write_bytes(b"OCTS" + bytes(range(60)))
    with pytest.raises(o.FormatError) as caught:
        o.load(bad)
    assert isinstance(caught.value, ValueError) and str(bad) in str(caught.value)
    obj = tmp_path / "bad.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 nine\n")
    with pytest.raises(o.Error) as caught:
        o.load_mesh(obj, depth=4)
    assert str(obj) in str(caught.value) and "line 4" in str(caught.value)
    scene = tmp_path / "bad.toml"
    scene.write_text('[[solid]]\nshape = { sphere = { center = [0, 0, 0], radius = -1 } }\n')
    with pytest.raises(o.Error) as caught:
        o.render(scene)
    assert f"{scene}:2:" in str(caught.value)


def test_unknown_extensions_are_refused(tmp_path):
    solid = o.voxelize(o.Sphere((0, 0, 0), 1), 3)
    with pytest.raises(o.FormatError, match="use"):
        solid.save(tmp_path / "x.docx")
    with pytest.raises(o.FormatError):
        solid.export(tmp_path / "x.oct")
    with pytest.raises(o.FileError):
        solid.save(tmp_path / "no-such-folder" / "x.oct")


def test_bad_arguments_are_value_errors():
    with pytest.raises(o.ArgumentError, match="radius"):
        o.Sphere((0, 0, 0), -1)
    with pytest.raises(ValueError):
        o.Cylinder((0, 0, 0), "w", 1, 1)
    with pytest.raises(o.ArgumentError, match="depth"):
        o.voxelize(o.Sphere((0, 0, 0), 1), 40)
    # A depth no byte holds, or no integer at all, is named as the library names one.
    with pytest.raises(o.ArgumentError, match=r"invalid depth: 300 is outside 1\.\.=21"):
        o.voxelize(o.Sphere((0, 0, 0), 1), 300)
    with pytest.raises(o.ArgumentError, match=r"invalid depth: -1 is outside"):
        o.from_mesh(np.zeros((3, 3)), np.array([[0, 1, 2]]), -1)
    with pytest.raises(o.ArgumentError, match=r"invalid depth: 'a' is not an integer"):
        o.voxelize(o.Sphere((0, 0, 0), 1), "a")
    with pytest.raises(o.ArgumentError, match=r"invalid depth: 2\.5 is not an integer"):
        o.voxelize(o.Sphere((0, 0, 0), 1), 2.5)
    with pytest.raises(o.ArgumentError, match=r"invalid depth: \d{61} is outside"):
        o.voxelize(o.Sphere((0, 0, 0), 1), 2**200)
    assert o.voxelize(o.Sphere((0, 0, 0), 1), 3).transform(scale=2.0, depth=None).voxel_count > 0
    # So is every other integer argument: the one the type holds but the library refuses
    # and the one the type cannot hold read alike.
    ball = o.voxelize(o.Sphere((0, 0, 0), 1), 3)
    for size in [(0, 5), (-1, 5), (5, 2**70)]:
        w, h = size
        with pytest.raises(o.ArgumentError, match=rf"invalid image size: {w}x{h} is outside 1\.\.=16384 a side"):
            o.render(ball, size=size)
    with pytest.raises(o.ArgumentError, match=r"invalid image size: \(5, 2\.5\) is not \(width, height\)"):
        o.render(ball, size=(5, 2.5))
    for spp in [17, -1]:
        with pytest.raises(o.ArgumentError, match=rf"invalid samples: {spp} a side is outside 1\.\.=16"):
            o.render(ball, spp=spp)
    for size in [0, -3]:
        with pytest.raises(o.ArgumentError, match=rf"invalid size: {size} pixels is outside 1\.\.=16384"):
            ball.slice("z", size=size)
    for count in [0, -2]:
        with pytest.raises(o.ArgumentError, match=rf"invalid count: {count} makes {count} copies; a pattern makes 1"):
            o.polar_array(o.Sphere((1, 0, 0), 0.1), "z", (0, 0, 0), count)
    with pytest.raises(o.ArgumentError, match=r"invalid image size: 10{40}x5 is outside"):
        o.render(ball, size=(10**40, 5))
    # numpy's integers are integers (by `__index__`); its floats are not.
    assert o.render(ball, size=(np.int64(8), np.uint16(6)), spp=np.int32(1)).shape == (6, 8, 3)
    with pytest.raises(o.ArgumentError, match=r"invalid samples: .* is not an integer"):
        o.render(ball, spp=np.float64(2.0))
    with pytest.raises(o.ArgumentError, match=r"invalid max shots: -1 is outside 0\.\.="):
        o.radiosity(SCENES / "cornell.toml", max_shots=-1)
    with pytest.raises(o.ArgumentError, match=r"invalid max elements: 'many' is not an integer"):
        o.radiosity(SCENES / "cornell.toml", max_elements="many")
    with pytest.raises(o.ArgumentError, match="vertex 7"):
        o.from_mesh(np.zeros((3, 3)), np.array([[0, 1, 7]]), 4)
    with pytest.raises(o.ArgumentError, match=r"\(n, 3\)"):
        o.from_mesh(np.zeros((3, 2)), np.array([[0, 1, 2]]), 4)
    with pytest.raises(o.ArgumentError, match="method"):
        o.render(o.voxelize(o.Sphere((0, 0, 0), 1), 3), method="magic")
    with pytest.raises(o.ArgumentError):
        o.voxelize(o.Sphere((0, 0, 0), 1), 3).shell(-1)
    with pytest.raises(TypeError):
        o.Sphere((0, 0, 0), 1) | 3


def test_an_empty_solid_has_nothing_to_export_or_draw(tmp_path):
    ball = o.voxelize(o.Sphere((0, 0, 0), 1), 3)
    empty = ball - ball
    assert empty.volume == 0 and empty.bounds is None
    with pytest.raises(o.FileError, match="empty"):
        empty.export(tmp_path / "e.stl")
    with pytest.raises(o.Error, match="empty"):
        o.render(empty)


def test_mesh_arrays_may_be_lists_or_other_dtypes():
    # A tetrahedron as plain lists, integer coordinates: converted as numpy converts.
    v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    tet = o.from_mesh(v, f, 5)
    assert tet.volume == pytest.approx(1 / 6, rel=0.15)
    as_arrays = o.from_mesh(np.array(v, dtype=np.float32), np.array(f, dtype=np.uint16), 5)
    assert np.array_equal(tet.keys(), as_arrays.keys())
    with pytest.raises(o.ArgumentError, match="2-D"):
        o.from_mesh(np.zeros(9), f, 5)
    with pytest.raises(o.ArgumentError, match="vertices"):
        o.from_mesh([["a", "b", "c"]], f, 5)


def test_what_a_reader_read_past_is_a_warning_naming_the_file_and_line(tmp_path):
    """The CLI prints these as `warning: FILE: line N: ...`; Python warns the same text."""
    obj = tmp_path / "t.obj"
    obj.write_bytes(b"mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    with pytest.warns(o.InputWarning, match=rf"{obj}: line 1: material library 'gone.mtl'"):
        solid = o.load_mesh(obj, depth=4)
    assert solid.voxel_count > 0
    # A scene naming that mesh warns as it draws.
    scene = tmp_path / "s.toml"
    scene.write_text(f'[[solid]]\nmesh = "{obj.name}"\ndepth = 4\n')
    with pytest.warns(o.InputWarning, match="gone.mtl"):
        o.render(scene, size=(16, 16), cache=False)


def test_an_offset_past_the_domain_warns_that_it_is_cut_off():
    # A ball filling most of its domain, grown by more than the gap to its faces.
    ball = o.voxelize(o.Sphere((0, 0, 0), 0.9), 5, domain=((-1, -1, -1), 2.0))
    with pytest.warns(o.ClippedWarning, match=r"offset reaches the domain's -x, -y, -z, \+x, \+y, \+z faces"):
        grown = ball.offset(0.3)
    # Every face of the domain is reached: the grown ball's bounds are the domain's.
    assert grown.bounds == ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0])
    with pytest.warns(o.ClippedWarning, match="offset is empty"):
        ball.offset(-1.0)
    # Within the domain: no warning.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ball.offset(0.05)


def test_outputs_are_checked_before_anything_is_allocated_or_written(tmp_path):
    ball = o.voxelize(o.Sphere((0, 0, 0), 1), 5)
    # A dense array past the budget is refused (a larger max_voxels used to abort).
    with pytest.raises(o.BudgetError, match="dense array"):
        ball.to_numpy(max_voxels=2**64 - 1, memory_budget="16KiB")
    # A picture past the render's largest side, before its copy (an abort).
    huge = np.broadcast_to(np.zeros(3, np.uint8), (100000, 100000, 3))
    with pytest.raises(o.ArgumentError, match="100000x100000"):
        o.write_png(tmp_path / "x.png", huge)
    # A picture named as another file is refused, and the file kept.
    kept = tmp_path / "part.oct"
    ball.save(kept)
    before = kept.read_bytes()
    with pytest.raises(o.Error, match="extension"):
        ball.save_slice(kept)
    with pytest.raises(o.Error, match="extension"):
        o.write_png(kept, np.zeros((4, 4, 3), np.uint8))
    assert kept.read_bytes() == before
    # A tolerance that is not a distance (a NaN or negative one was taken as none).
    for tolerance in [float("nan"), -1.0]:
        with pytest.raises(o.ArgumentError, match="tolerance"):
            ball.export(tmp_path / "x.stl", tolerance=tolerance)
        with pytest.raises(o.ArgumentError, match="tolerance"):
            ball.mesh(tolerance=tolerance)
    # A solution named as its scene is refused before the solve, the scene kept.
    scene = tmp_path / "s.toml"
    scene.write_text('[[solid]]\nname = "b"\nshape = { sphere = { center = [0, 0, 0], radius = 1 } }\n')
    with pytest.raises(o.Error, match="extension"):
        o.radiosity(scene, output=scene, max_shots=1)
    assert scene.read_text().startswith("[[solid]]")
