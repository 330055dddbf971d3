# The same answers: every case in cases/ run through Python and through the pcsim executable
# gives identical summaries and time series, bit for bit.
#
# How "bit for bit" is shown: the CLI writes numbers as shortest round-trip decimals (std::to_chars
# in timeseries.csv and events.csv, nlohmann::json's round-trip output in summary.json), which
# Python's float() and json.load parse back to the very same doubles. So (1) the CLI's
# timeseries.csv, parsed, equals Python's array bit for bit (compared as int64 bit patterns; an
# empty field is an undefined value, nan in the array; a switching run's mode labels are the
# indices into mode_labels); (2) the CLI's summary.json, parsed, equals Python's summary dict
# exactly; (3) the files Python writes with run(out=...) are byte-identical to the CLI's. The one
# field that differs between two runs, stats.wall_seconds (a clock), is left out of (2) and (3).
import json
import math
import os
import pathlib
import subprocess
import tomllib

import numpy as np
import pytest

import pcsim

ROOT = pathlib.Path(__file__).resolve().parents[2]
SANITIZED = bool(os.environ.get("PCSIM_SANITIZED"))
CASES = sorted(p.name for p in (ROOT / "cases").glob("*.toml"))


def needs_sieve(name):
    with open(ROOT / "cases" / name, "rb") as f:
        return tomllib.load(f).get("model", "sieve") == "sieve"  # the default model is the sieve


def without_wall(summary):
    s = json.loads(json.dumps(summary))
    s["stats"].pop("wall_seconds")
    return s


def parse_csv(path):
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:]]
    return header, rows


def test_there_are_cases():
    assert len(CASES) >= 8


@pytest.mark.parametrize("name", CASES)
def test_python_equals_cli(name, tmp_path, pcsim_exe):
    if needs_sieve(name) and not pcsim.with_sieve:
        pytest.skip("a sieve case; this build has no sieve (PCSIM_WITH_SIEVE=OFF)")
    cli_dir = tmp_path / "cli"
    py_dir = tmp_path / "py"
    # Under the sanitizers (the Debug build, ~20 times slower) the sieve's 10 s cases run their
    # first 0.5 s, the same override on both sides; the Release build runs every case whole.
    # Every other case runs at most its first 0.1 s there (the spatial and redundant models
    # cost milliseconds per evaluation under ASan). What is compared (bit-equal files and
    # arrays) does not depend on the length; the sanitizers look at the same code either way.
    overrides = {}
    if SANITIZED:
        with open(ROOT / "cases" / name, "rb") as f:
            t_end = tomllib.load(f).get("solver", {}).get("t_end", 10.0)
        limit = 0.5 if name.startswith("sieve") else 0.1
        if t_end > limit:
            overrides = {"solver.t_end": limit}
    sets = [a for k, v in overrides.items() for a in ("--set", f"{k}={v!r}")]
    proc = subprocess.run([pcsim_exe, "run", str(ROOT / "cases" / name), *sets,
                           "--out", str(cli_dir)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    case = pcsim.Case(ROOT / "cases" / name, set=overrides)
    res = case.run(out=py_dir)

    # (2) the summaries, parsed from the CLI's file, equal Python's dict exactly
    cli_summary = json.loads((cli_dir / "summary.json").read_text())
    assert without_wall(cli_summary) == without_wall(res.summary)

    # (1) the time series, parsed from the CLI's file, equal Python's array bit for bit
    header, rows = parse_csv(cli_dir / "timeseries.csv")
    assert header == res.columns
    assert res.data.shape == (len(rows), len(header))
    expected = np.empty(res.data.shape)
    for i, row in enumerate(rows):
        for j, field in enumerate(row):
            if header[j].startswith("mode_"):
                expected[i, j] = res.mode_labels.index(field)
            else:
                expected[i, j] = float(field) if field else math.nan
    undefined = np.isnan(expected)  # an empty field: the value is undefined (nan, any payload)
    assert np.array_equal(undefined, np.isnan(res.data))
    same = expected.view(np.int64) == res.data.view(np.int64)
    assert same[~undefined].all(), f"{np.count_nonzero(~same[~undefined])} values differ in some bit"
    assert res.complete == cli_summary["complete"]

    # events (contact.switching): the CLI's events.csv as Python's arrays
    if (cli_dir / "events.csv").exists():
        eh, erows = parse_csv(cli_dir / "events.csv")
        assert list(res.events) == eh
        for j, col in enumerate(eh):
            values = [r[j] for r in erows]
            got = res.events[col]
            if got.dtype.kind == "f":
                want = np.array([float(v) if v else math.nan for v in values])
                assert np.array_equal(np.isnan(want), np.isnan(got)), col
                ok = ~np.isnan(want)
                assert np.array_equal(want[ok].view(np.int64), got[ok].view(np.int64)), col
            else:
                assert list(got) == values, col
    else:
        assert res.events is None

    # (3) the files Python writes are the CLI's, byte for byte
    for f in sorted(p.name for p in cli_dir.iterdir()):
        if f == "summary.json":
            assert without_wall(json.loads((py_dir / f).read_text())) == without_wall(cli_summary)
            strip = lambda t: [l for l in t.splitlines() if '"wall_seconds"' not in l]
            assert strip((py_dir / f).read_text()) == strip((cli_dir / f).read_text())
        else:
            assert (py_dir / f).read_bytes() == (cli_dir / f).read_bytes(), f
