# 10,000 short runs in one process do not grow its memory: the resident set (RSS, from
# /proc/self/statm) after 10,000 more runs stays within a small bound of what it was after a
# warm-up (allocator pools and Python's own caches settle in the warm-up). A leak of even one
# result per run (its table, its summary dict) would add several MB. Exceptions count too:
# failed loads and failed runs in between.
import gc
import os

import numpy as np
import pytest

import pcsim

RUNS = 10_000


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(bool(os.environ.get("PCSIM_SANITIZED")),
                    reason="under AddressSanitizer freed memory stays resident (its quarantine), so "
                           "RSS measures nothing there; the Release build runs this test")
def test_many_short_runs_do_not_grow_memory(pendulum, tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text('[solver]\nrtol = "x"\n')

    def one(i):
        res = pendulum.run()
        assert res.data.shape == (6, len(res.columns))
        s = res.summary["extremes"]["tension"]["max"]
        if i % 50 == 0:
            with pytest.raises(pcsim.InputError):
                pcsim.Case(f)
            with pytest.raises(ValueError):
                pendulum.model.evaluate([1.0])
        return s

    for i in range(max(RUNS // 10, 200)):  # warm-up
        one(i)
    gc.collect()
    before = rss_bytes()
    first = None
    for i in range(RUNS):
        s = one(i)
        first = s if first is None else first
        assert s == first  # every run the same
    gc.collect()
    growth = rss_bytes() - before
    # 10,000 results of ~6 x 11 doubles and a summary each would be > 20 MB if kept.
    assert growth < 2 * 1024 * 1024, f"RSS grew by {growth / 1e6:.2f} MB over {RUNS} runs"
