"""The examples of examples/python run, at small depths, and say what they made."""

import subprocess
import sys

import pytest

import octsolid as o
from conftest import EXAMPLES, read_png


def run(name, *args):
    done = subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_importing_octsolid_and_the_classic_part_never_import_numpy(tmp_path):
    # Start-up: numpy is imported only when an array is made (it costs more than the
    # interpreter's own start), and the classic part makes none.
    script = EXAMPLES / "classic_part.py"
    code = (
        "import runpy, sys\n"
        "import octsolid\n"
        "assert 'numpy' not in sys.modules, 'import octsolid imported numpy'\n"
        f"sys.argv = [{str(script)!r}, {str(tmp_path)!r}, '--depth', '5']\n"
        "runpy.run_path(sys.argv[0], run_name='__main__')\n"
        "assert 'numpy' not in sys.modules, 'the classic part imported numpy'\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "classic_part.png").stat().st_size > 0


def test_classic_part(tmp_path):
    out = run("classic_part.py", tmp_path, "--depth", 6)
    assert "analytic" in out
    solid = o.load(tmp_path / "classic_part.oct")
    # The analytic volume, within the voxel shell.
    sys.path.insert(0, str(EXAMPLES))
    from classic_part import analytic_volume

    assert abs(solid.volume - analytic_volume()) < solid.measure()["area"] * solid.voxel_size


def test_bracket_exports_a_closed_stl(tmp_path):
    import trimesh

    run("bracket.py", tmp_path, "--depth", 6)
    mesh = trimesh.load(tmp_path / "bracket.stl", force="mesh")
    solid = o.load(tmp_path / "bracket.oct")
    assert mesh.is_watertight
    assert mesh.volume == pytest.approx(solid.volume, rel=0.03)
    assert solid.measure()["components"] == 1


def test_bunny_from_trimesh(tmp_path):
    out = run("bunny_trimesh.py", tmp_path, "--depth", 6)
    assert "watertight True" in out
    assert (tmp_path / "bunny.ply").stat().st_size > 0


def test_turntable(tmp_path):
    run("turntable.py", tmp_path, "--depth", 5, "--frames", 3, "--size", 32)
    sheet = read_png(tmp_path / "turntable.png")
    assert sheet.shape == (32, 96, 3)
    # Three different views.
    frames = [sheet[:, 32 * i : 32 * (i + 1)] for i in range(3)]
    assert not (frames[0] == frames[1]).all() and not (frames[1] == frames[2]).all()


def test_classic_part_writes_the_rust_examples_files(tmp_path):
    # The Rust example's .oct (no surface section) and slice, byte for byte: the same
    # library calls.
    import numpy as np

    from conftest import cli

    run("classic_part.py", tmp_path, "--depth", 6)
    solid = o.voxelize(
        (o.Box((0, 0, 0), 2) & o.Sphere((0, 0, 0), 1.3))
        - o.Cylinder((0, 0, 0), "x", 0.6, 3)
        - o.Cylinder((0, 0, 0), "y", 0.6, 3)
        - o.Cylinder((0, 0, 0), "z", 0.6, 3),
        6,
        ((-1, -1, -1), 2.0),
    )
    assert np.array_equal(o.load(tmp_path / "classic_part.oct").keys(), solid.keys())
    with_surface = tmp_path / "with.oct"
    solid.save(with_surface)
    assert with_surface.stat().st_size > (tmp_path / "classic_part.oct").stat().st_size
    cli("slice", tmp_path / "classic_part.oct", "--axis", "z", "--at", 0.8, "-o", tmp_path / "cli.png")
    assert (tmp_path / "cli.png").read_bytes() == (tmp_path / "classic_part.png").read_bytes()
