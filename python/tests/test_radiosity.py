"""`octsolid.radiosity` against `octsolid radiosity` on the same scene: the same `.rad`
bytes and the same `--json` summary; the energy book closes; bad arguments raise."""

import json

import pytest

import octsolid as o
from conftest import SCENES, cli


def test_radiosity_writes_the_clis_solution_and_summary(tmp_path):
    scene = SCENES / "cornell.toml"
    stats = o.radiosity(scene, tmp_path / "py.rad", max_shots=40)
    out = cli("radiosity", scene, "-o", tmp_path / "cli.rad", "--max-shots", 40, "--json")
    want = json.loads(out)
    assert (tmp_path / "py.rad").read_bytes() == (tmp_path / "cli.rad").read_bytes()
    assert stats["bytes"] == (tmp_path / "cli.rad").stat().st_size
    for key in ["solver", "patches", "elements", "shots", "unshot_fraction", "iterations", "residual"]:
        assert stats[key] == want[key], key
    # Emitted = absorbed + escaped + unshot.
    unshot = stats["unshot_fraction"] * stats["emitted"]
    assert abs(stats["absorbed"] + stats["escaped"] + unshot - stats["emitted"]) < 1e-9 * stats["emitted"]
    assert o.radiosity(scene, max_shots=40)["bytes"] == 0


def test_radiosity_refuses_bad_arguments_and_names_a_missing_scene(tmp_path):
    scene = SCENES / "cornell.toml"
    with pytest.raises(o.ArgumentError, match="solver"):
        o.radiosity(scene, solver="jacobi")
    with pytest.raises(o.ArgumentError, match="until"):
        o.radiosity(scene, until=1.5)
    with pytest.raises(o.ArgumentError, match="tolerance"):
        o.radiosity(scene, solver="gathering", tolerance=0)
    with pytest.raises(o.FileError) as caught:
        o.radiosity(tmp_path / "missing.toml")
    assert "missing.toml" in str(caught.value)
