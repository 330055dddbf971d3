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


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="one core")
def test_the_gil_is_released_during_a_run():
    # While one thread runs, another Python thread keeps running Python code: with the GIL
    # held for the whole run, the counter could not advance during it.
    import threading

    c = pcsim.Case(ROOT / "cases" / "slider_crank.toml", set={"solver.t_end": 5.0})
    ticks = 0
    done = threading.Event()

    def count():
        nonlocal ticks
        while not done.is_set():
            ticks += 1

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.01)
    start = ticks
    c.run()
    during = ticks - start
    done.set()
    t.join()
    assert during > 1000
