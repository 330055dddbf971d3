import sys
import matplotlib; matplotlib.use("Agg")  # write PNG files, open no window
import matplotlib.pyplot as plt
import pcsim

fast = {"solver.t_end": 0.5} if "--fast" in sys.argv else {}
case = pcsim.Case("cases/sieve_1995.toml", set=fast)   # the paper's case (run from the repo root)
res = case.run()                                       # the time series as NumPy columns
fig, (top, bottom) = plt.subplots(2, sharex=True)
top.plot(res["t"], res["R_u"]); bottom.plot(res["t"], res["fstar"])

# ---- the rest of the example --------------------------------------------------------------
# The paper's vibration sieve (cases/sieve_1995.toml) from Python: the run above, its figure
# (the roller's normal reaction R_u and the friction coefficient f* it needs to roll), a sweep
# of the eccentricity e in a plain loop, and the same sweep on threads (the runs release the
# GIL, so threads use several cores). Usage, from the repository's root after the build:
#   PYTHONPATH=build/python /usr/bin/python3 examples/python/sieve_paper.py [--fast] [--out DIR]
import concurrent.futures as cf  # noqa: E402
import pathlib  # noqa: E402

out = pathlib.Path(sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else "out/python")
out.mkdir(parents=True, exist_ok=True)
top.set_ylabel("R_u / N")
top.axhline(0.0, color="k", lw=0.5)
bottom.set_ylabel("f* (needed to roll)")
bottom.axhline(case.model.parameters["f"]["value"], color="r", lw=0.5, label="f (available)")
bottom.set_xlabel("t / s")
bottom.legend(loc="upper right")
top.set_title(f"{case.name}: min R_u = {res.summary['R_u_min']:.4g} N, "
              f"max f* = {res.summary['fstar_max']:.3g}")
fig.tight_layout()
fig.savefig(out / "sieve_R_u_fstar.png", dpi=100)
print(f"wrote {out / 'sieve_R_u_fstar.png'} ({len(res)} rows, columns {', '.join(res.columns[:7])}, ...)")

# A sweep of the eccentricity in a loop: one case per value, the summary as a dict.
eccentricities = [0.006, 0.008, 0.010, 0.012]
print("     e     min R_u/N   max f*")
for e in eccentricities:
    s = case.with_set({"parameters.e": e}).run().summary
    print(f"  {e:.3f}  {s['R_u_min']:10.4g}  {s['fstar_max']:7.3g}")

# The same runs on two threads, and the built-in sweep (the grid on `jobs` threads).
with cf.ThreadPoolExecutor(max_workers=2) as pool:
    runs = list(pool.map(lambda e: case.with_set({"parameters.e": e}).run(), eccentricities))
sweep = case.sweep("parameters.e=0.006:0.012:4", jobs=2)
for e, r, row in zip(eccentricities, runs, sweep.summaries):
    assert r.summary["R_u_min"] == row["R_u_min"]  # threads give the loop's numbers
print(f"threads and sweep(jobs=2) agree with the loop on {len(runs)} runs; "
      f"sweep columns: {', '.join(sweep.columns[:4])}, ...")
