"""Benchmark: several pcsim runs on Python threads against the same runs one after the other.

The long calls (Case.run, steady, response, sweep) release the GIL, so N threads can keep N
cores busy. Prints the wall times and the speed-up ratio. Usage, from the repository's root:
    PYTHONPATH=build/python /usr/bin/python3 examples/python/bench_threads.py [RUNS] [THREADS] [T_END]
"""
import concurrent.futures as cf
import os
import sys
import time

import pcsim

runs = int(sys.argv[1]) if len(sys.argv) > 1 else 24
threads = int(sys.argv[2]) if len(sys.argv) > 2 else min(2, os.cpu_count() or 1)
t_end = float(sys.argv[3]) if len(sys.argv) > 3 else 10.0
cases = [pcsim.Case("cases/sieve_1995.toml",
                    set={"parameters.e": 0.006 + 0.001 * (i % 7), "solver.t_end": t_end})
         for i in range(runs)]
cases[0].run()  # warm-up (first-use initialisation)

t0, c0 = time.perf_counter(), time.process_time()
serial = [c.run() for c in cases]
t_serial = time.perf_counter() - t0
cpu_serial = time.process_time() - c0

t0, c0 = time.perf_counter(), time.process_time()
with cf.ThreadPoolExecutor(max_workers=threads) as pool:
    parallel = list(pool.map(lambda c: c.run(), cases))
t_threads = time.perf_counter() - t0
cpu_threads = time.process_time() - c0

same = all((a.data == b.data).all() for a, b in zip(serial, parallel))
print(f"{runs} runs of cases/sieve_1995.toml: one after the other {t_serial:.2f} s, "
      f"on {threads} threads {t_threads:.2f} s: speed-up {t_serial / t_threads:.2f}x "
      f"({os.cpu_count()} cores; CPU time / wall time {cpu_serial / t_serial:.2f} alone, "
      f"{cpu_threads / t_threads:.2f} on threads; "
      f"identical results: {same})")

# A control that needs no pcsim: hashing 100 MB blocks (hashlib releases the GIL too). Where it
# shows no speed-up either, the machine is not giving this process a second core (other work,
# or a CPU quota), and the ratio above says nothing about pcsim.
import hashlib  # noqa: E402

block = b"x" * (100 << 20)
t0 = time.perf_counter()
for _ in range(2 * threads):
    hashlib.sha256(block).digest()
t_serial = time.perf_counter() - t0
t0 = time.perf_counter()
with cf.ThreadPoolExecutor(max_workers=threads) as pool:
    list(pool.map(lambda _: hashlib.sha256(block).digest(), range(2 * threads)))
t_threads = time.perf_counter() - t0
print(f"control (hashlib, releases the GIL too): speed-up {t_serial / t_threads:.2f}x on {threads} threads")
