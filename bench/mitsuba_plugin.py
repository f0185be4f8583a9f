#!/usr/bin/env python3
"""Render time and peak memory of Mitsuba's `measured` on a raw RGL file against npf's traced
plugin (`npf`) on its conversion, both in Mitsuba's default (symbolic) mode, and optionally the
numpy fallback (`npf_numpy`, wavefront mode), on examples/python/sphere.xml (path tracer, depth
3, the studio map). Each render runs in a process of its own, so that its peak resident memory is
its own (wait4's ru_maxrss); the kinds alternate, round after round, so that the ratios come from
one run on a machine whose speed drifts. Each process renders twice: the first includes
compiling the kernels, the second is the time reported.

usage: bench/mitsuba_plugin.py RAW.bsdf CONVERTED.exr [--variant llvm_ad_rgb] [--size 256]
                               [--spp 256] [--rounds 2] [--numpy] [--json OUT]
Needs `pip install mitsuba` and the npf package on PYTHONPATH (build/python).
"""
import argparse
import json
import os
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(REPO, "examples", "python", "sphere.xml")


def child(kind, material, variant, size, spp):
    import drjit as dr
    import mitsuba as mi
    import npf.mitsuba
    npf.mitsuba.set_variant(variant)
    if kind == "npf":
        npf.mitsuba.register()
    elif kind == "npf_numpy":
        npf.mitsuba.register_numpy()
    times = []
    for _ in range(2):
        scene = mi.load_file(SCENE, material=material, bsdf=kind, size=size)
        start = time.perf_counter()
        image = mi.render(scene, spp=spp)
        dr.eval(image)
        dr.sync_thread()
        times.append(time.perf_counter() - start)
    import numpy as np
    print(json.dumps({"first_s": times[0], "seconds": times[1], "mean": float(np.mean(np.array(image)[..., :3]))}))


def run(kind, material, args):
    cmd = [sys.executable, os.path.abspath(__file__), "--child", kind, material, "--variant", args.variant, "--size",
           str(args.size), "--spp", str(args.spp)]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)
    _, status, usage = os.wait4(proc.pid, 0)
    out = proc.stdout.read()
    proc.stdout.close()
    if status != 0:
        sys.exit("{} failed (status {}): {}".format(kind, status, out))
    result = json.loads(out.strip().splitlines()[-1])
    result.update(kind=kind, peak_gib=usage.ru_maxrss / 2 ** 20)  # ru_maxrss in KiB
    return result


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("raw", nargs="?")
    ap.add_argument("converted", nargs="?")
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--numpy", action="store_true", help="also time the numpy fallback (last, once)")
    ap.add_argument("--json")
    ap.add_argument("--child", nargs=2, metavar=("KIND", "MATERIAL"))
    args = ap.parse_args()
    if args.child:
        return child(args.child[0], args.child[1], args.variant, args.size, args.spp)
    results = []
    for _ in range(args.rounds):
        results.append(run("measured", os.path.abspath(args.raw), args))
        results.append(run("npf", os.path.abspath(args.converted), args))
    if args.numpy:
        results.append(run("npf_numpy", os.path.abspath(args.converted), args))
    for r in results:
        print("{kind:10s} {seconds:7.2f} s (first {first_s:6.2f} s)  peak {peak_gib:5.2f} GiB  mean {mean:.5f}".format(**r))
    for kind in ("npf", "npf_numpy"):
        ours = [r for r in results if r["kind"] == kind]
        if not ours:
            continue
        base = [r for r in results if r["kind"] == "measured"]
        ratio = sum(r["seconds"] for r in ours) / len(ours) / (sum(r["seconds"] for r in base) / len(base))
        mem = max(r["peak_gib"] for r in ours) / max(r["peak_gib"] for r in base)
        print("{} / measured: time {:.2f}x, peak memory {:.2f}x".format(kind, ratio, mem))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
