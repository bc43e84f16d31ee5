"""`memory_budget=` as `octsolid --memory-budget`: bytes or a size string parsed as the
CLI parses it; a job over it is refused before it starts with `octsolid.BudgetError`
(a `MemoryError`) carrying the library's message, the CLI's words; a generous budget
changes nothing of the result."""

import subprocess

import numpy as np
import pytest

import octsolid as o
from conftest import MODELS, SCENES, binary

PART = (o.Box((0, 0, 0), 2) & o.Sphere((0, 0, 0), 1.3)) - o.Cylinder((0, 0, 0), "z", 0.6, 3)
PLENTY = "64GiB"


def refused(call, budget, kind=o.BudgetError):
    """The BudgetError `call(memory_budget=budget)` raises, as its message."""
    with pytest.raises(kind) as caught:
        call(memory_budget=budget)
    e = caught.value
    assert isinstance(e, o.Error) and (kind is not o.BudgetError or isinstance(e, MemoryError))
    return str(e)


def cli_refusal(*args):
    """The message `octsolid --memory-budget ...` fails with."""
    done = subprocess.run([str(binary()), *map(str, args)], capture_output=True, text=True)
    assert done.returncode != 0
    return done.stderr


def test_a_tiny_budget_refuses_voxelizing_with_the_cli_message(tmp_path):
    message = refused(lambda **kw: o.voxelize(o.Sphere((0, 0, 0), 1), 9, **kw), "4KiB")
    assert "needs an estimated" in message and "the memory budget is 4.0 KiB" in message, message
    # The CLI refuses the same job with the same words.
    cli = cli_refusal("--memory-budget", "4KiB", "shape", "sphere", "--radius", "1", "--depth", "9", "-o", tmp_path / "x.oct")
    assert message in cli, (message, cli)
    # Bytes as an int and the same size as a string are one budget.
    assert refused(lambda **kw: o.voxelize(o.Sphere((0, 0, 0), 1), 9, **kw), 4096) == message


def test_every_budgeted_call_refuses_a_tiny_budget(tmp_path):
    solid = o.voxelize(PART, 6)
    other = o.voxelize(o.Sphere((0.5, 0, 0), 1), 7)
    solid.save(tmp_path / "part.oct")
    vertices, faces = solid.mesh()
    calls = {
        "from_mesh": lambda **kw: o.from_mesh(vertices, faces, 6, **kw),
        "load_mesh": lambda **kw: o.load_mesh(MODELS / "bunny-watertight.obj", 6, **kw),
        "load": lambda **kw: o.load(tmp_path / "part.oct", **kw),
        "union": lambda **kw: solid.union(other, **kw),
        "intersection": lambda **kw: solid.intersection(other, **kw),
        "difference": lambda **kw: solid.difference(other, **kw),
        "symmetric_difference": lambda **kw: solid.symmetric_difference(other, **kw),
        "transform": lambda **kw: solid.transform(rotate=[("z", 30)], **kw),
        "offset": lambda **kw: solid.offset(0.1, **kw),
        "shell": lambda **kw: solid.shell(0.1, **kw),
        "round": lambda **kw: solid.round(0.1, **kw),
        "save": lambda **kw: solid.save(tmp_path / "part.stl", **kw),
        "export": lambda **kw: solid.export(tmp_path / "part.obj", **kw),
        "mesh": lambda **kw: solid.mesh(**kw),
        "render": lambda **kw: o.render(solid, size=(64, 48), **kw),
        "radiosity": lambda **kw: o.radiosity(SCENES / "cornell.toml", max_shots=5, **kw),
    }
    for name, call in calls.items():
        message = refused(call, 64)
        assert "the memory budget is 64 B" in message, (name, message)


def test_a_mesh_file_over_the_budget_is_a_budget_error_naming_it(tmp_path):
    """`save` to a mesh format meshes the solid's true surface first: over the budget it is
    refused as a `BudgetError` (not a file that cannot be written) naming the file, and
    `octsolid convert` refuses the same file with the same words, writing nothing."""
    solid = o.voxelize(PART, 6)
    solid.save(tmp_path / "part.oct", surface=False)
    # Enough to read the file back (8 bytes a node), far too little for its mesh.
    budget = 8 * solid.node_count + 1024
    for ext in ["stl", "obj", "ply"]:
        path = tmp_path / f"part.{ext}"
        # Without the solid's surface data, as the .oct file holds it: both estimate
        # the surface from the voxels (the estimate depends on the crossings).
        message = refused(lambda **kw: solid.save(path, surface=False, **kw), budget)
        assert f"writing {path} (the surface of" in message, message
        assert not path.exists(), path
        cli = cli_refusal("--memory-budget", budget, "convert", tmp_path / "part.oct", path)
        assert message in cli, (message, cli)
        assert not path.exists(), path


def test_a_generous_budget_changes_nothing(tmp_path):
    default = o.voxelize(PART, 6)
    given = o.voxelize(PART, 6, memory_budget=PLENTY)
    assert np.array_equal(default.keys(), given.keys())
    assert np.array_equal(
        (default - o.voxelize(o.Sphere((1, 1, 1), 0.5), 5)).keys(),
        default.difference(o.voxelize(o.Sphere((1, 1, 1), 0.5), 5), memory_budget=2**36).keys(),
    )
    assert np.array_equal(default.offset(0.1).keys(), default.offset(0.1, memory_budget=PLENTY).keys())
    assert default.save(tmp_path / "a.oct") == given.save(tmp_path / "b.oct", memory_budget=PLENTY)
    assert (tmp_path / "a.oct").read_bytes() == (tmp_path / "b.oct").read_bytes()
    assert np.array_equal(o.render(default, size=(48, 36)), o.render(given, size=(48, 36), memory_budget=PLENTY))


@pytest.mark.parametrize("bad", ["lots", "3 parsecs", -1, 1.5, [1]])
def test_a_budget_that_is_no_size_is_an_argument_error(bad):
    with pytest.raises(o.ArgumentError) as caught:
        o.voxelize(o.Sphere((0, 0, 0), 1), 4, memory_budget=bad)
    assert "memory_budget" in str(caught.value)
