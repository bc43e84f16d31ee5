"""`progress=True` draws a bar on the standard error when it is a terminal (a
pseudo-terminal here) and nothing otherwise; the result is the same either way. A
callable `progress=f` is called with `(done, total)`, `done` growing to `total`."""

import os
import pty
import signal
import subprocess
import sys
import threading

import numpy as np
import pytest

import octsolid as o
from conftest import MODELS, SCENES

CODE = (
    "import octsolid as o, tempfile, os\n"
    "s = o.voxelize(o.Sphere((0, 0, 0), 1), 5, progress=True)\n"
    "d = tempfile.TemporaryDirectory()\n"
    "s.export(os.path.join(d.name, 'ball.obj'), progress=True)\n"
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
    for label in ("voxelizing", "meshing", "render", "radiosity"):
        assert f"{label}: 100%" in shown, shown
    piped = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True)
    assert piped.returncode == 0 and piped.stderr == "", piped.stderr


def test_progress_changes_nothing_of_the_result():
    solid = o.voxelize(o.Sphere((0, 0, 0), 1), 5)
    with_bar = o.render(solid, size=(32, 24), progress=True)
    assert np.array_equal(with_bar, o.render(solid, size=(32, 24)))


class Calls:
    """A `progress=` callable that records its calls."""

    def __init__(self):
        self.calls = []

    def __call__(self, done, total):
        self.calls.append((done, total))

    def check(self, stages=1):
        """Called; within each stage `done` grows from 0 to `total`, never backwards."""
        assert self.calls, "never called"
        starts = [i for i, (done, _) in enumerate(self.calls) if done == 0]
        assert starts and starts[0] == 0 and len(starts) <= stages + 1, self.calls
        for i, (done, total) in enumerate(self.calls):
            assert 0 <= done <= total and total > 0, self.calls
            if i > 0 and done != 0:
                before, before_total = self.calls[i - 1]
                assert total == before_total and done > before, self.calls
        assert self.calls[-1][0] == self.calls[-1][1], self.calls


def test_a_callable_sees_every_call_grow_to_its_total(tmp_path):
    part = (o.Box((0, 0, 0), 2) & o.Sphere((0, 0, 0), 1.3)) - o.Cylinder((0, 0, 0), "z", 0.6, 3)
    f = Calls()
    solid = o.voxelize(part, 6, progress=f)
    f.check()
    assert np.array_equal(solid.keys(), o.voxelize(part, 6).keys())
    vertices, faces = solid.mesh()
    calls = {
        "from_mesh": lambda p: o.from_mesh(vertices, faces, 6, progress=p),
        "load_mesh": lambda p: o.load_mesh(MODELS / "bunny-watertight.obj", 6, progress=p),
        "save .stl": lambda p: solid.save(tmp_path / "part.stl", progress=p),
        "save .oct": lambda p: solid.save(tmp_path / "part.oct", progress=p),
        "export": lambda p: solid.export(tmp_path / "part.obj", progress=p),
        "export .glb": lambda p: solid.export(tmp_path / "part.glb", progress=p),
        "offset": lambda p: solid.offset(0.05, progress=p),
        # Three stages: the voxels resampled, the surface data moved, the voxels again
        # from the moved surface.
        "transform": lambda p: solid.transform(rotate=[("z", 30)], progress=p),
        "render": lambda p: o.render(solid, size=(64, 48), progress=p),
        "radiosity": lambda p: o.radiosity(SCENES / "cornell.toml", max_shots=20, progress=p),
    }
    for name, call in calls.items():
        f = Calls()
        call(f)
        try:
            f.check(stages=3 if name == "transform" else 1)
        except AssertionError as e:
            raise AssertionError(f"{name}: {e}") from None


def test_a_callable_that_raises_raises_from_the_call_and_stops_the_work(tmp_path):
    def broken(done, total):
        raise KeyError("stop")

    with pytest.raises(KeyError, match="stop"):
        o.voxelize(o.Sphere((0, 0, 0), 1), 7, progress=broken)
    with pytest.raises(o.ArgumentError, match="progress"):
        o.voxelize(o.Sphere((0, 0, 0), 1), 4, progress="yes")
    # It stops the work too: a radiosity solution to a millionth unshot, asked to stop
    # at its first shots, writes no file (the work would write it before the raise).
    seen = []

    def stop_once_started(done, total):
        seen.append((done, total))
        if done > 0:
            raise KeyError("enough")

    solution = tmp_path / "cornell.rad"
    with pytest.raises(KeyError, match="enough"):
        o.radiosity(SCENES / "cornell.toml", output=solution, until=1e-6, progress=stop_once_started)
    assert not solution.exists()
    # Called until it raised, never again (no (total, total) at the end).
    assert len(seen) == 2 and seen[0] == (0, 1000) and 0 < seen[1][0] < 1000, seen


def test_ctrl_c_stops_a_long_call_and_raises_keyboard_interrupt():
    """Ctrl-C while the library works: the call stops at the library's next poll (a row
    of pixels here) and raises KeyboardInterrupt. The oracle of "stopped" is the
    progress callable: it never sees the last row."""
    solid = o.voxelize(o.Sphere((0, 0, 0), 1), 7)
    seen = []
    # The library's threads may call it at once: the interrupt is sent exactly once.
    once = threading.Lock()

    def interrupt_once_started(done, total):
        seen.append((done, total))
        if done > 0 and once.acquire(blocking=False):
            os.kill(os.getpid(), signal.SIGINT)

    # Python's own handler, as an interactive session has it, whatever this process
    # was started with (the suite run in the background by `nohup` did not raise here).
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            o.render(solid, size=(3000, 3000), spp=3, progress=interrupt_once_started)
    finally:
        signal.signal(signal.SIGINT, before)
    total = seen[0][1]
    assert seen[0] == (0, total) and total == 3000
    assert max(done for done, _ in seen) < total, seen
    # The package works on after it: the same call, smaller, runs to its end.
    calls = []
    o.render(solid, size=(64, 64), progress=lambda done, total: calls.append((done, total)))
    assert calls[-1] == (64, 64)
