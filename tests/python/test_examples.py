# examples/python: the paper's case script (run, figure, e swept in a loop and on threads) and
# the threads benchmark, run as a user runs them from the repository's root (fast settings).
import os
import pathlib
import subprocess
import sys

import pytest

import pcsim

ROOT = pathlib.Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.skipif(not pcsim.with_sieve, reason="the examples run the sieve's case")


def run(*args):
    return subprocess.run([sys.executable, *map(str, args)], cwd=ROOT, env=dict(os.environ),
                          capture_output=True, text=True, timeout=120)


def test_the_paper_example(tmp_path):
    p = run(ROOT / "examples" / "python" / "sieve_paper.py", "--fast", "--out", tmp_path)
    assert p.returncode == 0, p.stderr
    png = tmp_path / "sieve_R_u_fstar.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    lines = p.stdout.splitlines()
    assert lines[0].startswith(f"wrote {png} (501 rows")
    rows = [l.split() for l in lines[2:6]]
    assert [r[0] for r in rows] == ["0.006", "0.008", "0.010", "0.012"]
    # a larger eccentricity shakes harder: the roller's least normal force falls, f* rises
    ru = [float(r[1]) for r in rows]
    fs = [float(r[2]) for r in rows]
    assert ru == sorted(ru, reverse=True) and fs == sorted(fs)
    assert "agree with the loop on 4 runs" in lines[-1]


def test_the_threads_benchmark():
    p = run(ROOT / "examples" / "python" / "bench_threads.py", "4", "2", "0.3")
    assert p.returncode == 0, p.stderr
    assert "speed-up" in p.stdout and "identical results: True" in p.stdout
