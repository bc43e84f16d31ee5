"""`progress=True` draws a bar on the standard error when it is a terminal (a
pseudo-terminal here) and nothing otherwise; the result is the same either way."""

import os
import pty
import subprocess
import sys

import numpy as np

import octsolid as o
from conftest import SCENES

CODE = (
    "import octsolid as o\n"
    "o.render(o.voxelize(o.Sphere((0, 0, 0), 1), 5), size=(32, 24), progress=True)\n"
    f"o.radiosity({str(SCENES / 'cornell.toml')!r}, max_shots=20, progress=True)\n"
)


def stderr_on_a_terminal(code):
    """What `python -c code` writes to its standard error when that is a terminal."""
    main, side = pty.openpty()
    done = subprocess.run([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=side)
    os.close(side)
    seen = b""
    while True:
        try:
            chunk = os.read(main, 1 << 16)
        except OSError:  # the other end closed
            break
        if not chunk:
            break
        seen += chunk
    os.close(main)
    assert done.returncode == 0, seen.decode(errors="replace")
    return seen.decode(errors="replace")


def test_progress_draws_a_bar_on_a_terminal_only():
    shown = stderr_on_a_terminal(CODE)
    assert "render: 100%" in shown and "radiosity: 100%" in shown, shown
    piped = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True)
    assert piped.returncode == 0 and piped.stderr == "", piped.stderr


def test_progress_changes_nothing_of_the_result():
    solid = o.voxelize(o.Sphere((0, 0, 0), 1), 5)
    with_bar = o.render(solid, size=(32, 24), progress=True)
    assert np.array_equal(with_bar, o.render(solid, size=(32, 24)))
