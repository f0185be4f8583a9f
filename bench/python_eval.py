#!/usr/bin/env python3
"""The Python package's batched eval beside `npf bench`'s C++ batched eval, in one run.

  PYTHONPATH=build/python python3 bench/python_eval.py FACTORS.exr [--npf build/tools/npf/npf] [--rounds 2]

Times `npf.open(FACTORS).eval(wi, wo, threads=1)` per pair for N = 1 to 1,000,000 random pairs
over the hemisphere (4 hero wavelengths per pair on a spectral file, as npf bench; RGB files
their 3 channels), and `npf bench FACTORS --json --threads 1`'s eval_batch_ns (batches of 1,024;
its figure includes the pdf, which Python's eval does not compute), alternating, and prints the
ratio per N (issue 20: at most 1.5 for N >= 1000). Not a test: it times.
"""
import argparse
import json
import os
import subprocess
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # numpy's BLAS threads spin on a 2-core machine

import numpy as np  # noqa: E402

import npf  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def hemisphere(rng, n):
    a, b = rng.random(n), rng.random(n)
    s = np.sqrt(a)
    return np.stack([s * np.cos(2 * np.pi * b), s * np.sin(2 * np.pi * b), np.sqrt(1.0 - a)], axis=1)


def python_ns(m, n, rng, seconds=1.0):
    wi, wo = hemisphere(rng, n), hemisphere(rng, n)
    hero = None
    if not m.is_rgb:
        lo, hi = m.wavelengths[0], m.wavelengths[-1]
        first = lo + (hi - lo) * rng.random(n)
        hero = np.stack([(first + k * (hi - lo) / 4 - lo) % (hi - lo) + lo for k in range(4)], axis=1)
    m.eval(wi, wo, wavelengths=hero, threads=1)  # warm
    calls, start = 0, time.perf_counter()
    while True:
        m.eval(wi, wo, wavelengths=hero, threads=1)
        calls += 1
        elapsed = time.perf_counter() - start
        if elapsed >= seconds:
            return elapsed / (calls * n) * 1e9


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("factors")
    parser.add_argument("--npf", default=os.path.join(HERE, "..", "build", "tools", "npf", "npf"))
    parser.add_argument("--rounds", type=int, default=2)
    args = parser.parse_args()
    m = npf.open(args.factors)
    rng = np.random.default_rng(1)
    sizes = [1, 100, 1000, 10000, 100000, 1000000]
    for r in range(args.rounds):
        bench = json.loads(subprocess.run([args.npf, "bench", args.factors, "--json", "--seconds", "0.5", "--threads", "1"],
                                          check=True, capture_output=True, text=True).stdout)
        cpp = bench["eval_batch_ns"]
        row = {n: python_ns(m, n, rng) for n in sizes}
        print("round %d: npf bench eval_batch_ns %.1f; Python eval ns per pair (ratio): %s" % (
            r + 1, cpp, ", ".join("N=%d %.1f (%.2f)" % (n, t, t / cpp) for n, t in row.items())))


if __name__ == "__main__":
    main()
