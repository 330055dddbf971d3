#!/usr/bin/env python3
"""Validation of IFToMM A02 (the N-four-bar mechanism) outside ctest (issue 21): runs `pcsim run`
on A02 with the given N and rtols over 10 s, compares the crank angle with an independent
one-degree-of-freedom model (every crank turns by the same angle theta; I theta'' = -m g L c
cos(theta), I = m L^2 ((N+1)/3 + N), c = (N+1)/2 + N, RK4 with h = 1e-4 s), and reports the
largest angle error, the spread between the cranks, the energy drift, and the cost per
simulated second (summary.json's wall_seconds / 10).

Usage: a02_validate.py PCSIM N[,N...] RTOL[,RTOL...]   e.g. a02_validate.py build/pcsim 1,4 1e-6,1e-8
Plain Python 3, no packages. N = 40 (243 coordinates) takes minutes per run with the dense
engine: that is why it is not a ctest test.
"""
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import fourbar_a02_model  # noqa: E402


def oracle(N, times):
    I = (N + 1) / 3.0 + N
    c = (N + 1) / 2.0 + N
    g = 9.81

    def f(th, w):
        return w, -g * c / I * math.cos(th)

    th, w, t, out = math.pi / 2, -1.0, 0.0, []
    for T in times:
        while t < T - 1e-13:
            h = min(1e-4, T - t)
            k1 = f(th, w)
            k2 = f(th + h / 2 * k1[0], w + h / 2 * k1[1])
            k3 = f(th + h / 2 * k2[0], w + h / 2 * k2[1])
            k4 = f(th + h * k3[0], w + h * k3[1])
            th += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            w += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
            t += h
        out.append(th)
    return out


def run(pcsim, N, rtol, work):
    model = os.path.join(work, f"a02_N{N}.toml")
    with open(model, "w") as fh:
        fh.write(fourbar_a02_model.model(N, False))
    case = os.path.join(work, f"case_N{N}.toml")
    with open(case, "w") as fh:
        fh.write(f'model = "a02_N{N}.toml"\n')
        fh.write(fourbar_a02_model.initial(N, False))
        fh.write("[solver]\nt_end = 10.0\nrtol = %s\natol = 1.0e-10\n[output]\ndt = 0.01\n" % rtol)
    out = os.path.join(work, f"out_N{N}_{rtol}")
    p = subprocess.run([pcsim, "run", case, "--out", out], capture_output=True, text=True)
    if p.returncode != 0:
        return {"N": N, "rtol": rtol, "exit": p.returncode, "message": (p.stderr or p.stdout)[-300:]}
    with open(os.path.join(out, "timeseries.csv")) as fh:
        rows = list(csv.reader(fh))
    head, data = rows[0], [[float(x) for x in r] for r in rows[1:]]
    tc = [head.index(f"tc{k}") for k in range(N + 1)]
    e = head.index("energy")
    th = oracle(N, [r[0] for r in data])
    summary = json.load(open(os.path.join(out, "summary.json")))
    return {
        "N": N, "rtol": rtol, "exit": 0,
        "angle_error": max(abs(r[tc[0]] - o) for r, o in zip(data, th)),
        "crank_spread": max(abs(r[k] - r[tc[0]]) for r in data for k in tc),
        "energy_drift": max(abs(r[e] - data[0][e]) for r in data),
        "steps": summary["stats"]["steps"],
        "wall_per_simulated_second": summary["stats"]["wall_seconds"] / 10.0,
    }


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    pcsim = argv[1]
    with tempfile.TemporaryDirectory() as work:
        for N in [int(x) for x in argv[2].split(",")]:
            for rtol in argv[3].split(","):
                print(json.dumps(run(pcsim, N, rtol, work)), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
