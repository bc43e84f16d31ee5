"""The GIL is released while the library works: a Python thread keeps counting while
another voxelizes and renders."""

import threading
import time

import octsolid as o


def test_a_thread_runs_while_another_voxelizes():
    part = (o.Box((0, 0, 0), 2) & o.Sphere((0, 0, 0), 1.3)) - o.Cylinder((0, 0, 0), "z", 0.6, 3)
    counts = []
    done = threading.Event()

    def work():
        started = time.perf_counter()
        solid = o.voxelize(part, 9, domain=((-1, -1, -1), 2.0))
        o.render(solid, size=(160, 120))
        counts.append(time.perf_counter() - started)
        done.set()

    ticks = 0
    worker = threading.Thread(target=work)
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    # Held GIL: the counter would stall for the whole job (one tick at most). Released:
    # it ticks about once a millisecond of the job.
    assert counts and ticks > 10, f"{ticks} ticks in {counts[0]:.3f} s"
    assert ticks > counts[0] * 1000 / 20
