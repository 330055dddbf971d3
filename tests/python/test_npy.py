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


# pcsim animate and plot read the .npy through their own reader (sim/time_series_file.hpp): a
# file numpy.save writes of the same records (NumPy's own header, not pcsim's padded one) reads
# to the same rows, so animate writes the CSV run's page byte for byte; what numpy.save writes
# of other arrays (a plain 2-D float64 array without column names, big-endian fields, Fortran
# order, 4-byte floats) is refused with exit 2 naming the file, and no page is written.
def test_animate_reads_numpys_own_npy_and_refuses_other_arrays(tmp_path, pcsim_exe):
    case = ROOT / "cases" / "bouncing_ball.toml"
    sets = ["--set", "solver.t_end=0.3"]
    for fmt in ("csv", "npy"):
        proc = subprocess.run([pcsim_exe, "run", str(case), *sets, "--set", f"output.format={fmt}",
                               "--out", str(tmp_path / fmt)], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
    a = np.load(tmp_path / "npy" / "timeseries.npy")
    np.save(tmp_path / "npy" / "timeseries.npy", a)  # numpy's header for the same records
    for fmt in ("csv", "npy"):
        proc = subprocess.run([pcsim_exe, "animate", str(tmp_path / fmt)], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "npy" / "animation.html").read_bytes() == (tmp_path / "csv" / "animation.html").read_bytes()

    numbers = [n for n in a.dtype.names if not n.startswith("mode_")]
    plain = np.stack([a[n] for n in numbers], axis=1)
    others = {
        "a plain array has no column names": plain,
        "got '>f8'": a.astype([(n, ">f8" if n in numbers else a.dtype[n]) for n in a.dtype.names]),
        "got '<f4'": a.astype([(n, "<f4" if n in numbers else a.dtype[n]) for n in a.dtype.names]),
        "'fortran_order': False": np.asfortranarray(np.stack([a, a], axis=1)),  # the records in columns
        "one dimension (rows,)": np.stack([a, a]),
    }
    for expected, array in others.items():
        (tmp_path / "npy" / "animation.html").unlink(missing_ok=True)
        np.save(tmp_path / "npy" / "timeseries.npy", array)
        proc = subprocess.run([pcsim_exe, "animate", str(tmp_path / "npy")], capture_output=True, text=True)
        assert proc.returncode == 2, proc.stderr
        assert "timeseries.npy: " in proc.stderr and expected in proc.stderr, proc.stderr
        assert not (tmp_path / "npy" / "animation.html").exists()
