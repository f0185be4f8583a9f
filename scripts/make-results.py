#!/usr/bin/env python3
"""Regenerates docs/results.md: the paper's Tables 1 and 2 on our data, the speed/accuracy
trade and side-by-side renders, by running the npf tool (convert, render, compare, bench).

    python3 scripts/make-results.py [--quick] [--work DIR] [--fresh]

Every step's output is kept in the work folder (default build/results-work) and reused on the
next run, so an interrupted run resumes; --fresh starts over. Images go to docs/results/.
Standard library only; the plot is drawn with oiiotool (OpenImageIO's tool, already a
dependency) and the DejaVu font (fonts-dejavu-core).
"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"

REAL = ["acrylic_felt_green_rgb", "cg_sunflower_rgb", "ilm_l3_37_metallic_rgb", "paper_white_rgb",
        "vch_golden_yellow_rgb"]
# Synthetic anisotropic spectral materials (analytic recipes, rendered exactly as reference).
# (red_plastic and thin_film_aluminium are left out to keep a run near half an hour on 2 cores:
# their D and G do not depend on wavelength, as brushed_copper's and satin_fabric's do not.)
SYNTHETIC = ["brushed_copper", "satin_fabric", "crossed_lobes_failure"]
FAILURE = "crossed_lobes_failure"
PCA_RATIOS = [None, (0.99, 0.99), (0.99, 0.95), (0.99, 0.90), (0.95, 0.95), (0.90, 0.90)]
RANKS = [1, 2, 4, 8, 16]


def log(msg):
    print(msg, file=sys.stderr, flush=True)


class Runner:
    def __init__(self, args):
        self.args = args
        self.npf = args.npf
        self.work = args.work
        os.makedirs(self.work, exist_ok=True)
        self.times_path = os.path.join(self.work, "times.json")
        self.times = json.load(open(self.times_path)) if os.path.exists(self.times_path) else {}

    def path(self, name):
        return os.path.join(self.work, name)

    def run(self, cmd, capture=False):
        log("  $ " + " ".join(cmd))
        r = subprocess.run(cmd, stdout=subprocess.PIPE if capture else subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            raise SystemExit("make-results: failed (%d): %s\n%s" % (r.returncode, " ".join(cmd), r.stderr))
        return r.stdout

    def timed(self, key, out, cmd):
        """Runs cmd unless `out` exists; remembers its wall time under `key`."""
        if not os.path.exists(out) or key not in self.times:
            start = time.monotonic()
            self.run(cmd)
            self.times[key] = time.monotonic() - start
            json.dump(self.times, open(self.times_path, "w"), indent=1)
        return self.times[key]

    # -- steps ---------------------------------------------------------------------------------

    def source(self, name):
        if name in SYNTHETIC:
            return os.path.join(ROOT, "configs", "materials", name + ".yaml")
        return os.path.join(self.args.shared, "rgl", name + ".bsdf")

    def wavelengths(self, name):
        # One quadrature for a material's reference and its conversions, so that colour
        # differences come from the fit alone.
        return None if name in REAL else self.args.render_wavelengths

    def render(self, material, tag, name, spp=None, seed=1):
        # Environment sampling alone: a material and its reference rendered at the same seed are
        # then estimated at the same light directions, and their difference is nearly free of
        # noise (the paired noise floor, docs/metrics.md). "env" in the name keeps a work folder
        # of earlier (MIS) runs from being reused.
        out = self.path("%s.%s.env%s.exr" % (name, tag, "" if seed == 1 else ".seed%d" % seed))
        cmd = [self.npf, "render", material, "-o", out, "--size", str(self.args.size), "--spp",
               str(spp or self.args.spp), "--seed", str(seed), "--sampling", "env", "--quiet"]
        if self.wavelengths(name):
            cmd += ["--wavelengths", self.wavelengths(name)]
        self.timed("render:" + out, out, cmd)
        return out

    def picture(self, material, tag, name):
        """A MIS render for the side-by-side figures: environment sampling alone, which the
        comparisons use, leaves bright speckles around glossy highlights (they cancel in a
        comparison at the same seed, not in a picture)."""
        out = self.path("%s.%s.mis.exr" % (name, tag))
        cmd = [self.npf, "render", material, "-o", out, "--png", out[:-4] + ".png", "--size", str(self.args.size),
               "--spp", str(self.args.spp), "--seed", "1", "--quiet"]
        if self.wavelengths(name):
            cmd += ["--wavelengths", self.wavelengths(name)]
        self.timed("render:" + out, out, cmd)
        return out[:-4] + ".png"

    def render_pair(self, material, tag, name, spp=None):
        """The material rendered at seeds 1 and 2: what compare_pair needs for the noise floor."""
        return (self.render(material, tag, name, spp, seed=1), self.render(material, tag, name, spp, seed=2))

    def convert(self, name, tag, extra):
        out = self.path("%s.%s.npf.exr" % (name, tag))
        cmd = [self.npf, "convert", self.source(name), "-o", out, "--quiet"] + extra
        if name in SYNTHETIC:
            cmd += ["--max-wavelengths", str(self.args.max_wavelengths)]
        seconds = self.timed("convert:" + out, out, cmd)
        return out, seconds

    def compare(self, ref, test, heatmap=None, floor=()):
        cmd = [self.npf, "compare", ref, test, "--json"]
        if heatmap:
            cmd += ["--heatmap", heatmap]
        if floor:
            cmd += ["--floor"] + list(floor)
        m = json.loads(self.run(cmd, capture=True))
        for k in ("PSNR", "SSIM", "relMSE", "MAPE", "noise_floor_db"):
            if k in m:
                v = m[k]
                m[k] = math.inf if v in ("inf", "Infinity") else float(v)
        return m

    def compare_pair(self, ref_pair, test_pair, heatmap=None):
        """Seed 1's metrics and the paired noise floor from seed 2 (npf compare --floor)."""
        return self.compare(ref_pair[0], test_pair[0], heatmap, floor=(ref_pair[1], test_pair[1]))

    def bench(self, material):
        out = json.loads(self.run([self.npf, "bench", material, "--json", "--seconds", "0.5", "--threads", "1"],
                                  capture=True))
        return out


def fmt_psnr(v):
    return "inf" if math.isinf(v) else "%.2f" % v


def fmt_psnr_judged(m):
    """The PSNR, starred when it is within 3 dB of its noise floor (it then measures noise)."""
    return fmt_psnr(m["PSNR"]) + (" *" if m.get("noise_limited") else "")


def metrics_cells(m):
    return ["%.2f %%" % (100 * m["MAPE"]), "%.5f" % m["relMSE"], fmt_psnr_judged(m), fmt_psnr(m["noise_floor_db"]),
            "%.4f" % m["SSIM"]]


FLOOR_NOTE = ("Floor: the PSNR's paired noise floor ([metrics.md](metrics.md), `npf compare --floor`), from the same "
              "two materials rendered again at seed 2; a PSNR within 3 dB of it (starred) measures Monte Carlo "
              "noise, not the fit.")


def file_mb(path):
    return os.path.getsize(path) / 1e6


# -- the plot ----------------------------------------------------------------------------------

def plot(path, panels, width=1000, height=420):
    """panels: list of dicts with title, xlabel, ylabel, logx, series [(label, colour, [(x, y)])].
    Drawn with oiiotool: axes, ticks, polylines, points, labels."""
    n = len(panels)
    pw = width // n
    cmd = ["oiiotool", "--create", "%dx%d" % (width, height), "3", "--fill:color=1,1,1", "%dx%d" % (width, height)]

    def text(x, y, s, size=14, color="0,0,0"):
        cmd.extend(["--text:x=%d:y=%d:size=%d:color=%s:font=%s" % (x, y, size, color, FONT), s])

    for i, p in enumerate(panels):
        x0, x1 = i * pw + 70, (i + 1) * pw - 20
        y0, y1 = height - 60, 40  # y grows downwards
        pts = [pt for s in p["series"] for pt in s[2]]
        fx = (lambda v: math.log10(v)) if p.get("logx") else (lambda v: v)
        xs = [fx(x) for x, _ in pts]
        ys = [y for _, y in pts]
        xlo, xhi = min(xs), max(xs)
        ylo, yhi = min(ys), max(ys)
        padx = (xhi - xlo) * 0.08 or 1.0
        pady = (yhi - ylo) * 0.1 or 1.0
        xlo, xhi, ylo, yhi = xlo - padx, xhi + padx, ylo - pady, yhi + pady

        def to_px(x, y):
            return (x0 + (fx(x) - xlo) / (xhi - xlo) * (x1 - x0), y0 - (y - ylo) / (yhi - ylo) * (y0 - y1))

        cmd.extend(["--line:color=0,0,0", "%d,%d,%d,%d,%d,%d" % (x0, y1, x0, y0, x1, y0)])
        for k in range(5):  # ticks
            vy = ylo + (yhi - ylo) * k / 4
            py = y0 - (y0 - y1) * k / 4
            cmd.extend(["--line:color=0.8,0.8,0.8", "%d,%d,%d,%d" % (x0 + 1, py, x1, py)])
            text(x0 - 62, int(py) + 5, "%.4g" % vy, 12)
            vx = xlo + (xhi - xlo) * k / 4
            px = x0 + (x1 - x0) * k / 4
            text(int(px) - 18, y0 + 18, "%.3g" % (10 ** vx if p.get("logx") else vx), 12)
        text(x0, y1 - 16, p["title"], 16)
        text((x0 + x1) // 2 - 60, height - 15, p["xlabel"], 13)
        text(x0 + 5, y1 + 14, p["ylabel"], 13)
        for j, (label, colour, series) in enumerate(p["series"]):
            if len(series) > 1:
                coords = []
                for x, y in sorted(series):
                    px, py = to_px(x, y)
                    coords += [int(px), int(py)]
                cmd.extend(["--line:color=%s" % colour, ",".join(map(str, coords))])
            for x, y in series:
                px, py = to_px(x, y)
                cmd.extend(["--box:color=%s:fill=1" % colour, "%d,%d,%d,%d" % (px - 3, py - 3, px + 3, py + 3)])
            text(x1 - 190, y1 + 20 + 18 * j, label, 13, colour)
    tmp = path + ".tmp.png"
    subprocess.run(cmd + ["-d", "uint8", "-o", tmp], check=True, stdout=subprocess.DEVNULL)
    os.replace(tmp, path)


def side_by_side(path, images, labels):
    cmd = ["oiiotool"]
    for img, label in zip(images, labels):
        cmd += [img, "--ch", "R,G,B", "--text:x=8:y=22:size=16:color=1,1,1:font=%s" % FONT, label]
    cmd += ["--mosaic", "%dx1" % len(images), "-d", "uint8", "-o", path + ".tmp.png"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    os.replace(path + ".tmp.png", path)


# -- the report --------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--npf", default=os.path.join(ROOT, "build", "tools", "npf", "npf"))
    ap.add_argument("--shared", default=os.path.join(os.path.dirname(ROOT), "shared", "data"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "results-work"))
    ap.add_argument("--docs", default=os.path.join(ROOT, "docs"))
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--converge", type=int, default=8,
                    help="the convergence check renders the real materials with this many times --spp")
    ap.add_argument("--max-wavelengths", type=int, default=41)
    ap.add_argument("--render-wavelengths", default="380:780:41")
    ap.add_argument("--quick", action="store_true", help="small renders, two materials: checks the pipeline")
    ap.add_argument("--fresh", action="store_true", help="discard the work folder first")
    args = ap.parse_args()
    global REAL, SYNTHETIC
    if args.quick:
        args.size, args.spp, args.max_wavelengths = 64, 16, 8
        REAL, SYNTHETIC = REAL[2:3], [FAILURE]
        args.work += "-quick"
    if args.fresh and os.path.isdir(args.work):
        shutil.rmtree(args.work)
    r = Runner(args)
    # --quick must not overwrite the committed figures: its images go to a folder of their own.
    image_folder = "results-quick" if args.quick else "results"
    images = os.path.join(args.docs, image_folder)
    os.makedirs(images, exist_ok=True)
    md = []

    # Table 1: the paper's weight against Bagher's, render metrics against the reference.
    log("Table 1")
    t1 = []
    for name in REAL + SYNTHETIC:
        ref = r.render_pair(r.source(name), "reference", name)
        row = {"name": name}
        for tag, extra in (("ours", ["--preset", "production"]),
                           ("bagher", ["--preset", "production", "--volume-weight", "three-angle"])):
            fitted, seconds = r.convert(name, tag, extra)
            img = r.render_pair(fitted, tag, name)
            heat = r.path("%s.%s.heat.png" % (name, tag))
            row[tag] = r.compare_pair(ref, img, heat)
            row[tag + "_fit_s"] = seconds
            row[tag + "_mb"] = file_mb(fitted)
        t1.append(row)
    # Energy: directional albedo of each real conversion against its raw file (npf albedo),
    # mean over the channels of the relative difference, at a few view angles.
    log("Energy")
    albedo_thetas = [0, 30, 60, 75, 85, 89]
    energy = {}
    for name in REAL:
        out = r.run([args.npf, "albedo", r.path("%s.ours.npf.exr" % name), "--against", r.source(name), "--theta",
                     ",".join(str(t) for t in albedo_thetas), "--json"], capture=True)
        rows = json.loads(out)["rows"]
        energy[name] = [sum(row[-1]) / len(row[-1]) for row in rows]

    # Convergence: Table 1's real comparisons again with `converge` times the samples. If the PSNR
    # barely moves, the fit's error, not Monte Carlo noise, is what Table 1 measures: a check of
    # the floors.
    log("Convergence")
    converged = {}
    high_spp = args.spp * args.converge
    for name in REAL:
        ref_hi = r.render_pair(r.source(name), "reference-%dspp" % high_spp, name, spp=high_spp)
        ours_hi = r.render_pair(r.path("%s.ours.npf.exr" % name), "ours-%dspp" % high_spp, name, spp=high_spp)
        converged[name] = {"ours": r.compare_pair(ref_hi, ours_hi)}

    # Table 2: PCA ratios on a spectrally varying material.
    log("Table 2")
    # The one recipe whose D and G change with wavelength: two lobes with different Fresnel
    # (gold and silver) and so different weights per wavelength.
    pca_material = FAILURE
    ref = r.render_pair(r.source(pca_material), "reference", pca_material)  # Table 1's, when it ran
    # One lossless fit; every ratio and rank below is a re-compression of it (`npf edit
    # --compress-pca/--compress-rank`), which equals a conversion at that ratio from the same fit.
    lossless, lossless_s = r.convert(pca_material, "pca-none", ["--preset", "production", "--pca", "1,1"])
    t2 = []
    for ratios in PCA_RATIOS:
        if ratios is None:
            fitted, seconds, tag = lossless, lossless_s, "pca-none"
        else:
            tag = "pca-%g-%g" % ratios
            fitted = r.path("%s.%s.npf.exr" % (pca_material, tag))
            seconds = r.timed("edit:" + fitted, fitted, [args.npf, "edit", lossless, "-o", fitted, "--no-albedo-check",
                                                         "--compress-pca", "%g,%g" % ratios])
        info = r.run([args.npf, "info", fitted], capture=True)
        ranks = [l.split(":", 1)[1].split()[0] for l in info.splitlines() if l.strip().startswith(("D rank", "G rank"))][:2]
        img = r.render_pair(fitted, tag, pca_material)
        t2.append({"ratios": ratios, "mb": file_mb(fitted), "ranks": ranks, "fit_s": seconds,
                   "m": r.compare_pair(ref, img)})
    uncompressed = t2[0]["mb"]

    # Speed/accuracy: presets and grids on a real material; evaluation time against rank.
    log("Speed and accuracy")
    trade_material = REAL[0] if args.quick else "ilm_l3_37_metallic_rgb"
    trade_ref = r.render_pair(r.source(trade_material), "reference", trade_material)
    trade = []
    settings = [("preview", ["--preset", "preview"]), ("production", ["--preset", "production"])]
    if not args.quick:
        settings += [("paper", ["--preset", "paper"])]
    for label, extra in settings:
        tag = "trade-" + label.replace(", ", "-").replace(" ", "")
        fitted, seconds = r.convert(trade_material, tag, extra)
        img = r.render_pair(fitted, tag, trade_material)
        trade.append({"label": label, "fit_s": seconds, "mb": file_mb(fitted), "m": r.compare_pair(trade_ref, img)})
    rank_rows = []
    for k in RANKS:
        fitted = r.path("%s.rank-%d.npf.exr" % (pca_material, k))
        r.timed("edit:" + fitted, fitted, [args.npf, "edit", lossless, "-o", fitted, "--no-albedo-check",
                                            "--compress-rank", "%d,%d" % (k, k)])
        img = r.render_pair(fitted, "rank-%d" % k, pca_material)
        b = r.bench(fitted)
        rank_rows.append({"rank": k, "mb": file_mb(fitted), "eval_ns": b["eval_memory_ns"],
                          "eval_full_ns": b["eval_memory_full_ns"], "m": r.compare_pair(ref, img)})
    plot(os.path.join(images, "speed_accuracy.png"), [
        {"title": "fit time against render PSNR (%s)" % trade_material, "xlabel": "fit wall time (s, log)",
         "ylabel": "PSNR (dB)", "logx": True,
         "series": [("presets and grids", "0.1,0.3,0.8", [(t["fit_s"], min(t["m"]["PSNR"], 99)) for t in trade])]},
        {"title": "evaluation time against rank (%s)" % pca_material, "xlabel": "SVD rank of D and G",
         "ylabel": "ns per eval", "series": [
             ("4 hero wavelengths", "0.1,0.3,0.8", [(q["rank"], q["eval_ns"]) for q in rank_rows]),
             ("every stored channel", "0.8,0.2,0.1", [(q["rank"], q["eval_full_ns"]) for q in rank_rows])]}])

    # Side-by-side images.
    shown = [n for n in ("ilm_l3_37_metallic_rgb", "brushed_copper", FAILURE) if n in REAL + SYNTHETIC]
    for name in shown:
        side_by_side(os.path.join(images, name + ".png"),
                     [r.picture(r.source(name), "reference", name),
                      r.picture(r.path("%s.ours.npf.exr" % name), "ours", name), r.path("%s.ours.heat.png" % name)],
                     ["reference", "NPF (production)", "relMSE 0..5 %"])

    # -- write docs/results.md
    md.append("# Results: the paper's tables on our data\n")
    md.append("Regenerated by `python3 scripts/make-results.py` (%s; renders %dx%d, %d samples per pixel, "
              "environment sampling alone (`--sampling env`), seed 1, and seed 2 for the noise floors; "
              "spectral renders at %s nm). Metrics are defined in [metrics.md](metrics.md); the "
              "renderer in [render.md](render.md). Every number below was produced by that run on the "
              "development machine (2-core EPYC VM).\n" % (time.strftime("%Y-%m-%d"), args.size, args.size, args.spp,
                                                           args.render_wavelengths))
    md.append("## Table 1: our anisotropic weight against Bagher's\n")
    md.append("Sphere scene under the default environment map. Reference: the raw RGL file (real materials) "
              "or the analytic recipe evaluated exactly (synthetic, fitted at %d wavelengths). Both fits use "
              "the production preset; only the volume weight differs.\n" % args.max_wavelengths)
    md.append("| material | ours: MAPE | relMSE | PSNR (dB) | floor (dB) | SSIM | Bagher: MAPE | relMSE | PSNR (dB) "
              "| floor (dB) | SSIM | fit (s) |")
    md.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for row in t1:
        md.append("| %s | %s | %s | %.1f |" % (row["name"], " | ".join(metrics_cells(row["ours"])),
                                              " | ".join(metrics_cells(row["bagher"])), row["ours_fit_s"]))
    md.append("")
    md.append(FLOOR_NOTE)
    md.append("\nConvergence: the real materials' comparison (ours) again at %d samples per pixel, reference and "
              "conversion both at that count (seeds 1 and 2). A PSNR that moves little between the two counts is "
              "the fit's error, not noise, as the floors say.\n" % high_spp)
    md.append("| material | PSNR at %d spp | floor at %d spp | PSNR at %d spp | floor at %d spp | SSIM at %d spp |"
              % (args.spp, args.spp, high_spp, high_spp, high_spp))
    md.append("|---|---|---|---|---|---|")
    by_name = {row["name"]: row for row in t1}
    for name in REAL:
        c = converged[name]["ours"]
        low = by_name[name]["ours"]
        md.append("| %s | %s | %s | %s | %s | %.4f |" % (name, fmt_psnr_judged(low), fmt_psnr(low["noise_floor_db"]),
                                                       fmt_psnr_judged(c), fmt_psnr(c["noise_floor_db"]), c["SSIM"]))
    md.append("\n## Energy: directional albedo against the raw file\n")
    md.append("`npf albedo CONVERSION --against RAW` ([albedo.md](albedo.md)) for the production conversions of "
              "Table 1 (ours): the relative difference of the directional albedo, mean over R, G and B, at each "
              "view angle. Negative: the conversion reflects less light than the measured material.\n")
    md.append("| material | " + " | ".join("%d deg" % t for t in albedo_thetas) + " |")
    md.append("|---|" + "---|" * len(albedo_thetas))
    for name in REAL:
        md.append("| %s | %s |" % (name, " | ".join("%+.1f %%" % (100 * v) for v in energy[name])))
    md.append("\n## Table 2: spectral compression (%s)\n" % pca_material)
    md.append("One production fit stored losslessly; each ratio is a re-compression of it (`npf edit --compress-pca`), "
              "the same as converting at that ratio from the same fit. Time: the fit, or the re-compression.\n")
    md.append("| PCA D / G | ranks D / G | size (MB) | ratio to uncompressed | PSNR (dB) | floor (dB) | SSIM | time (s) |")
    md.append("|---|---|---|---|---|---|---|---|")
    for q in t2:
        label = "none" if q["ratios"] is None else "%g / %g" % (100 * q["ratios"][0], 100 * q["ratios"][1])
        md.append("| %s | %s | %.3f | %.1f %% | %s | %s | %.4f | %.1f |" % (
            label, " / ".join(q["ranks"]), q["mb"], 100 * q["mb"] / uncompressed, fmt_psnr_judged(q["m"]),
            fmt_psnr(q["m"]["noise_floor_db"]), q["m"]["SSIM"], q["fit_s"]))
    md.append("\n" + FLOOR_NOTE)
    md.append("\n## Speed against accuracy\n")
    md.append("![speed and accuracy](%s/speed_accuracy.png)\n" % image_folder)
    md.append("Fit settings on %s (render PSNR against the raw file):\n" % trade_material)
    md.append("| settings | fit wall time (s) | size (MB) | PSNR (dB) | floor (dB) | SSIM |")
    md.append("|---|---|---|---|---|---|")
    for t in trade:
        md.append("| %s | %.1f | %.3f | %s | %s | %.4f |" % (t["label"], t["fit_s"], t["mb"], fmt_psnr_judged(t["m"]),
                                                          fmt_psnr(t["m"]["noise_floor_db"]), t["m"]["SSIM"]))
    md.append("\nEvaluation time against SVD rank on %s (`npf bench`, one thread, in-memory path):\n" % pca_material)
    md.append("| rank D, G | size (MB) | eval, 4 hero wavelengths (ns) | eval, every stored channel (ns) | PSNR (dB) "
              "| floor (dB) |")
    md.append("|---|---|---|---|---|---|")
    for q in rank_rows:
        md.append("| %d | %.3f | %.0f | %.0f | %s | %s |" % (q["rank"], q["mb"], q["eval_ns"], q["eval_full_ns"],
                                                         fmt_psnr_judged(q["m"]), fmt_psnr(q["m"]["noise_floor_db"])))
    md.append("\n## Side by side\n")
    for name in shown:
        md.append("**%s**: reference, NPF (pictures rendered with MIS), relMSE heatmap of Table 1's comparison "
                  "(environment sampling, blue 0 to red 5 %%)\n" % name)
        md.append("![%s](%s/%s.png)\n" % (name, image_folder, name))
    md.append("<!-- analysis -->\n")
    out = os.path.join(args.docs, "results.md" if not args.quick else "results-quick.md")
    analysis = ""
    if os.path.exists(out):
        old = open(out).read()
        if "<!-- analysis -->" in old:
            analysis = "\n" + old.split("<!-- analysis -->", 1)[1].lstrip("\n")
    with open(out + ".tmp", "w") as f:
        f.write("\n".join(md) + analysis)
    os.replace(out + ".tmp", out)
    log("wrote " + out)


if __name__ == "__main__":
    main()
