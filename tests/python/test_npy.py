# output.format = "npy" (issue 23: a binary time series for large runs). numpy.load reads
# timeseries.npy as a structured array whose fields are the CSV's columns, and its values equal
# the Python run's in-memory array bit for bit (int64 bit patterns, NaNs included, which the CSV
# writes as empty fields); a switching run's mode columns hold the label texts. The run writes no
# timeseries.csv then, and its summary is the CSV run's.
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import pcsim

ROOT = pathlib.Path(__file__).resolve().parents[2]
SANITIZED = bool(os.environ.get("PCSIM_SANITIZED"))


@pytest.mark.parametrize("name", ["coin_skid.toml", "bouncing_ball.toml"])
def test_npy_time_series_equals_the_run_bit_for_bit(name, tmp_path, pcsim_exe):
    overrides = {"solver.t_end": 0.05} if SANITIZED else {}
    sets = [a for k, v in overrides.items() for a in ("--set", f"{k}={v!r}")]
    out = tmp_path / "npy"
    proc = subprocess.run([pcsim_exe, "run", str(ROOT / "cases" / name), *sets, "--set", "output.format=npy",
                           "--out", str(out)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert not (out / "timeseries.csv").exists()
    a = np.load(out / "timeseries.npy")
    res = pcsim.Case(ROOT / "cases" / name, set=overrides).run()
    assert list(a.dtype.names) == res.columns
    assert a.shape == (res.data.shape[0],)
    for j, col in enumerate(res.columns):
        if col.startswith("mode_"):
            assert [x.decode() for x in a[col]] == [res.mode_labels[int(v)] for v in res.data[:, j]]
        else:
            got = np.ascontiguousarray(a[col]).view(np.int64)
            want = np.ascontiguousarray(res.data[:, j]).view(np.int64)
            assert np.array_equal(got, want), f"{col}: {np.count_nonzero(got != want)} values differ in some bit"
    def without_wall(summary):
        s = json.loads(json.dumps(summary))
        s["stats"].pop("wall_seconds")
        return s

    assert without_wall(json.loads((out / "summary.json").read_text())) == without_wall(res.summary)
