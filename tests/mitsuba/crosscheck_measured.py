#!/usr/bin/env python3
"""Opt-in cross-check of npf's RGL reader against Mitsuba 3's `measured` plugin, an independent
reader of the same format (pip install mitsuba). Compares f_r cos(theta_o) and the pdf on random,
grazing, near-normal and mirror direction pairs, for the real files and for synthetic
anisotropic (reductions 1, 2, 4) and spectral files.

usage: crosscheck_measured.py NPF_TOOL SYNTH_TOOL [--recipes DIR] [RGL_FILE...]
With --recipes, every configs/materials recipe is also written by `npf synth` (at a reduced grid)
and checked: Mitsuba reading what our writer wrote.
Exit status 0 when every file agrees, 1 otherwise, 77 (skipped) when mitsuba is missing.
"""
import math
import os
import random
import subprocess
import sys
import tempfile

try:
    import mitsuba as mi
except ImportError:
    print("SKIP: the Python package 'mitsuba' is not installed (pip install mitsuba)")
    sys.exit(77)

REL_TOL = 2e-3      # both readers compute in float32; sampling-table rounding differs slightly
ABS_TOL = 1e-5      # relative to the file's largest value
WAVELENGTHS = [(412.0, 487.5, 550.0, 633.3), (400.0, 500.0, 600.0, 700.0), (380.0, 455.0, 640.0, 720.0)]


def direction_pairs(count, seed):
    rng = random.Random(seed)

    def hemisphere(z_min=0.0):
        z = rng.uniform(z_min, 1.0)
        phi = rng.uniform(-math.pi, math.pi)
        r = math.sqrt(max(0.0, 1.0 - z * z))
        return (r * math.cos(phi), r * math.sin(phi), z)

    pairs = []
    for i in range(count):
        kind = i % 10
        if kind == 0:                       # near-mirror pair (the specular peak)
            # Not the exact mirror: there the half vector is the pole, its azimuth undefined, and
            # the two readers differ by design (Mitsuba normalises with a reciprocal square root,
            # which moves wh off the pole by an ulp; npf and powitacq divide and stay on it).
            wi = hemisphere(0.05)
            d = [rng.uniform(-1, 1) * 3e-3 for _ in range(3)]
            wo = (-wi[0] + d[0], -wi[1] + d[1], wi[2] + d[2])
            n = math.sqrt(sum(v * v for v in wo))
            wo = tuple(v / n for v in wo)
        elif kind == 1:                     # grazing outgoing direction
            wi = hemisphere()
            phi = rng.uniform(-math.pi, math.pi)
            z = rng.uniform(1e-4, 1e-2)
            r = math.sqrt(1 - z * z)
            wo = (r * math.cos(phi), r * math.sin(phi), z)
        elif kind == 2:                     # near-normal incidence
            wi = hemisphere(0.999)
            wo = hemisphere()
        else:
            wi, wo = hemisphere(), hemisphere()
        pairs.append((wi, wo))
    return pairs


def npf_values(npf_tool, path, pairs, extra):
    text = "".join("%.9g %.9g %.9g %.9g %.9g %.9g\n" % (*wi, *wo) for wi, wo in pairs)
    out = subprocess.run([npf_tool, "eval", path, "--cos", "--pdf"] + extra, input=text,
                         capture_output=True, text=True, check=True).stdout
    return [list(map(float, line.split())) for line in out.splitlines() if not line.startswith("#")]


def mitsuba_values(path, pairs, wavelengths):
    bsdf = mi.load_dict({"type": "measured", "filename": path})
    ctx = mi.BSDFContext()
    rows = []
    for wi, wo in pairs:
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*wi)
        if wavelengths is not None:
            si.wavelengths = mi.Spectrum(wavelengths)
        value = bsdf.eval(ctx, si, mi.Vector3f(*wo))
        pdf = bsdf.pdf(ctx, si, mi.Vector3f(*wo))
        rows.append([float(value[k]) for k in range(len(value))] + [float(pdf)])
    return rows


def compare(name, ours, theirs):
    """Per column (each channel, then the pdf): relative error where the value is above
    ABS_TOL times that column's largest value, absolute below."""
    columns = len(theirs[0])
    scale = [max(abs(row[c]) for row in theirs) or 1.0 for c in range(columns)]
    worst, bad, compared = 0.0, 0, 0
    for a_row, b_row in zip(ours, theirs):
        for c, (a, b) in enumerate(zip(a_row, b_row)):
            if max(abs(a), abs(b)) <= ABS_TOL * scale[c]:
                continue
            compared += 1
            rel = abs(a - b) / max(abs(a), abs(b))
            worst = max(worst, rel)
            if rel > REL_TOL:
                bad += 1
    status = "ok" if bad <= compared * 1e-3 else "MISMATCH"
    print("%-40s compared %6d  max rel %.2e  beyond %.0e: %d  %s" % (name, compared, worst, REL_TOL, bad, status))
    return status == "ok"


def kind_of(npf_tool, path):
    info = subprocess.run([npf_tool, "info", path], capture_output=True, text=True, check=True).stdout
    return "spectral" if "channels: spectral" in info else "rgb"


def check_one(npf_tool, path, kind):
    """Compares one file; run in a fresh process per file because Mitsuba 3 leaves its
    reduction factor uninitialised for isotropic files (mitsuba3 PR #1850): after an
    anisotropic file was loaded, an isotropic one can inherit its folding."""
    pairs = direction_pairs(3000, 11)
    name = os.path.basename(path)
    ok = True
    if kind == "rgb":
        mi.set_variant("scalar_rgb")
        # Mitsuba's RGB path does not clamp negative channels; compare unclamped.
        ok &= compare(name, npf_values(npf_tool, path, pairs, ["--raw"]), mitsuba_values(path, pairs, None))
    else:
        mi.set_variant("scalar_spectral")
        for wl in WAVELENGTHS:
            ours = npf_values(npf_tool, path, pairs, ["--raw", "--wavelengths", ",".join(map(str, wl))])
            ok &= compare("%s @%s" % (name, "/".join("%g" % w for w in wl)), ours, mitsuba_values(path, pairs, wl))
    return ok


def main():
    if len(sys.argv) == 5 and sys.argv[1] == "--one":
        return 0 if check_one(sys.argv[2], sys.argv[3], sys.argv[4]) else 1
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    npf_tool, synth_tool = sys.argv[1], sys.argv[2]
    rest = sys.argv[3:]
    recipes = None
    if len(rest) >= 2 and rest[0] == "--recipes":
        recipes, rest = rest[1], rest[2:]
    files = [(p, kind_of(npf_tool, p)) for p in rest]
    folder = tempfile.mkdtemp(prefix="npf-mitsuba-")
    if recipes:
        for name in sorted(os.listdir(recipes)):
            if not name.endswith(".yaml"):
                continue
            out = os.path.join(folder, name[:-5] + ".bsdf")
            subprocess.run([npf_tool, "synth", "--recipe", os.path.join(recipes, name), "-o", out, "--quiet",
                            "--phi", "12", "--vndf", "64", "--data", "16"], check=True, capture_output=True)
            files.append((out, kind_of(npf_tool, out)))
    listing = subprocess.run([synth_tool, folder], capture_output=True, text=True, check=True).stdout
    files += [tuple(line.split()) for line in listing.splitlines()]
    ok = True
    for path, kind in files:
        sys.stdout.flush()
        ok &= subprocess.run([sys.executable, __file__, "--one", npf_tool, path, kind]).returncode == 0
    print("agree" if ok else "DISAGREE")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
