# Threads: run, sweep and model evaluation from several Python threads at once (the long calls
# release the GIL) give the same results as one after the other, and the threads overlap (the
# runs take less wall time together than one after the other would, when there are 2 cores).
import concurrent.futures as cf
import os
import pathlib
import time

import numpy as np
import pytest

import pcsim

ROOT = pathlib.Path(__file__).resolve().parents[2]


def case(e):
    return pcsim.Case(ROOT / "cases" / "slider_crank.toml",
                      set={"solver.t_end": 0.5, "parameters.m2": e})


def test_threads_give_the_serial_results():
    values = [0.5, 0.8, 1.1, 1.4, 1.7, 2.0]
    serial = [case(v).run() for v in values]
    shared = case(1.0)
    with cf.ThreadPoolExecutor(4) as pool:
        parallel = list(pool.map(lambda v: case(v).run(), values))
        # the same Case object run from several threads at once
        same = list(pool.map(lambda _: shared.run(), range(4)))
    for a, b in zip(serial, parallel):
        assert np.array_equal(a.data, b.data, equal_nan=True)
        sa, sb = dict(a.summary), dict(b.summary)
        sa["stats"].pop("wall_seconds"), sb["stats"].pop("wall_seconds")
        assert sa == sb
    for r in same[1:]:
        assert np.array_equal(r.data, same[0].data, equal_nan=True)


def test_sweeps_on_threads_agree():
    base = case(1.0)
    one = base.sweep("parameters.m2=0.5:2:4", jobs=1)
    two = base.sweep("parameters.m2=0.5:2:4", jobs=2)
    drop = [j for j, c in enumerate(one.columns) if c == "stats.wall_seconds"]
    assert not drop  # the table leaves the clock out: it is identical whatever the jobs
    assert np.array_equal(one.data, two.data, equal_nan=True)


def test_the_gil_is_released_during_a_run():
    # A worker thread runs the case a few times, noting when each run starts and ends; the main
    # thread meanwhile notes the time in a loop. With the GIL held by the run, the main thread
    # could run no Python inside it; with the GIL released it keeps running throughout.
    import threading

    sanitized = bool(os.environ.get("PCSIM_SANITIZED"))  # ~20 times slower runs there
    c = pcsim.Case(ROOT / "cases" / "slider_crank.toml",
                   set={"solver.t_end": 8.0 if sanitized else 60.0})
    spans = []

    def work():
        for _ in range(1 if sanitized else 3):
            t0 = time.perf_counter()
            c.run()
            spans.append((t0, time.perf_counter()))

    worker = threading.Thread(target=work)
    notes = []
    worker.start()
    while worker.is_alive():
        notes.append(time.perf_counter())
    worker.join()
    # the longest stretch of a run in which the main thread noted nothing: with the GIL held it
    # would be nearly the whole run (all but a switch interval, 5 ms)
    for a, b in spans:
        inside = [a] + [t for t in notes if a < t < b] + [b]
        gap = max(y - x for x, y in zip(inside, inside[1:]))
        assert gap < 0.5 * (b - a), f"the main thread stood still {gap:.3f} s of a {b - a:.3f} s run"
