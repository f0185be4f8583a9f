#!/usr/bin/env python3
"""Guards the speed figures of shading and fitting against a recorded baseline.

Runs, on the shipped measured material (data/materials/ilm_l3_37_metallic_rgb.bsdf), a preview
conversion and `npf bench --against` the raw file, and a preview conversion of the brushed copper
recipe (195 wavelengths, anisotropic: the fitter's 16-lane passes, which the RGB file does not
reach), several times, and expresses every time as a ratio to the raw RGL evaluation of the same
run: this 2-core machine is shared and its speed
varies by tens of per cent, while ratios measured side by side hold. A measure is reported
slower when its median ratio exceeds the baseline's by more than the noise (the larger of the
two runs' spreads, at least 5 %); the exit status is then 1.

  python3 bench/check.py [--npf build/tools/npf/npf] [--repeats 3] [--baseline FILE] [--update]

--update records this run as the baseline (bench/baseline.json; commit it with the change that
moved it).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
BASELINE = os.path.join(HERE, "baseline.json")
MATERIAL = os.path.join(ROOT, "data", "materials", "ilm_l3_37_metallic_rgb.bsdf")
SPECTRAL_RECIPE = os.path.join(ROOT, "configs", "materials", "brushed_copper.yaml")
# The npf bench fields guarded, each as a ratio to eval_raw_ns of the same run.
SHADING = ["eval_memory_ns", "eval_batch_ns", "eval_batch_float_ns", "eval_texture_ns", "sample_ns", "sample_batch_ns",
           "pdf_ns", "pdf_batch_ns"]
MIN_NOISE = 0.05


def run_once(npf, folder):
    texture = os.path.join(folder, "ilm.exr")
    start = time.monotonic()
    subprocess.run([npf, "convert", MATERIAL, "-o", texture, "--preset", "preview", "--quiet"], check=True,
                   stdout=subprocess.DEVNULL)
    convert_s = time.monotonic() - start
    start = time.monotonic()
    subprocess.run([npf, "convert", SPECTRAL_RECIPE, "-o", os.path.join(folder, "copper.exr"), "--preset", "preview",
                    "--quiet"], check=True, stdout=subprocess.DEVNULL)
    spectral_s = time.monotonic() - start
    out = subprocess.run([npf, "bench", texture, "--against", MATERIAL, "--json", "--seconds", "0.3"],
                         check=True, capture_output=True, text=True).stdout
    bench = json.loads(out)
    raw = bench["eval_raw_ns"]
    ratios = {key: bench[key] / raw for key in SHADING if bench.get(key) is not None}
    # The conversion's seconds per raw-evaluation microsecond: both scale with the machine's speed.
    ratios["convert_preview_s"] = convert_s / (raw * 1e-3)
    ratios["convert_copper_preview_s"] = spectral_s / (raw * 1e-3)
    return ratios, bench


def spread(values):
    m = statistics.median(values)
    return (max(values) - min(values)) / m if m > 0 else 0.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--npf", default=os.path.join(ROOT, "build", "tools", "npf", "npf"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--baseline", default=BASELINE)
    parser.add_argument("--update", action="store_true")
    args = parser.parse_args()
    if not os.access(args.npf, os.X_OK):
        sys.exit(f"bench/check.py: {args.npf}: not an executable (build npf first, or pass --npf)")
    if args.repeats < 2:
        sys.exit("bench/check.py: --repeats must be at least 2 (the noise is the spread between runs)")

    baseline = None
    if not args.update:  # read before the minutes of timing, so that a bad baseline fails at once
        try:
            with open(args.baseline) as f:
                baseline = json.load(f)
        except (OSError, ValueError) as e:
            sys.exit(f"bench/check.py: {args.baseline}: cannot read the baseline ({e}); record one with --update")

    runs = []
    with tempfile.TemporaryDirectory(prefix="npf-bench-check-") as folder:
        for k in range(args.repeats):
            print(f"bench/check.py: run {k + 1} of {args.repeats} ...", file=sys.stderr, flush=True)
            runs.append(run_once(args.npf, folder))
    keys = list(runs[0][0].keys())
    now = {key: statistics.median(r[0][key] for r in runs) for key in keys}
    noise = {key: spread([r[0][key] for r in runs]) for key in keys}
    isa = runs[0][1].get("batch_isa", "")

    if args.update:
        record = {"material": os.path.relpath(MATERIAL, ROOT), "repeats": args.repeats, "batch_isa": isa,
                  "unit": "ratio to eval_raw_ns of the same run (convert_*_s: seconds per raw-eval microsecond)",
                  "ratios": {k: round(v, 5) for k, v in now.items()},
                  "noise": {k: round(v, 4) for k, v in noise.items()}}
        with open(args.baseline + ".tmp", "w") as f:
            json.dump(record, f, indent=1, sort_keys=True)
            f.write("\n")
        os.replace(args.baseline + ".tmp", args.baseline)  # never a half-written baseline
        print(f"bench/check.py: wrote {args.baseline}")
        return 0

    slower = []
    print(f"{'measure':22} {'baseline':>10} {'now':>10} {'change':>8} {'noise':>7}  verdict")
    for key in keys:
        base = baseline["ratios"].get(key)
        if base is None:
            print(f"{key:22} {'-':>10} {now[key]:10.4f} {'':>8} {'':>7}  new (no baseline)")
            continue
        change = now[key] / base - 1.0
        allowed = max(MIN_NOISE, noise[key], baseline.get("noise", {}).get(key, 0.0))
        verdict = "slower" if change > allowed else ("faster" if change < -allowed else "ok")
        if verdict == "slower":
            slower.append(key)
        print(f"{key:22} {base:10.4f} {now[key]:10.4f} {100 * change:+7.1f}% {100 * allowed:6.1f}%  {verdict}")
    if baseline.get("batch_isa") and isa and baseline["batch_isa"] != isa:
        print(f"note: the baseline's batched calls ran with {baseline['batch_isa']}, these with {isa}")
    if slower:
        print("bench/check.py: slower than the baseline beyond the noise: " + ", ".join(slower))
        return 1
    print("bench/check.py: no measure slower than the baseline beyond the noise")
    return 0


if __name__ == "__main__":
    sys.exit(main())
