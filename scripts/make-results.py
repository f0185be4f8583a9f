#!/usr/bin/env python3
"""Regenerates docs/results.md: the accuracy ladder (every --preset and the paper's Neural BRDF
baseline on each material: size, render PSNR under the studio and key-rim lightings with their
noise floors and under the noise-free directional lights, the relative RMS error in BRDF space,
albedo, fit and evaluation time), the paper's Tables 1 and 2 on our data and side-by-side
renders, by running the npf tool (synth, convert, render, compare, eval, albedo, bench).

    python3 scripts/make-results.py [--quick] [--work DIR] [--fresh] [--npf PATH]

Every step's output is kept in the work folder (default build/results-work) and reused on the
next run, so an interrupted run resumes; --fresh starts over. Images go to docs/results/.
Standard library only; the plots are drawn with oiiotool (OpenImageIO's tool, already a
dependency) and the DejaVu font (fonts-dejavu-core).
"""

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"

REAL = ["acrylic_felt_green_rgb", "cg_sunflower_rgb", "ilm_l3_37_metallic_rgb", "paper_white_rgb",
        "vch_golden_yellow_rgb"]
# Synthetic materials of the ladder: the recipe written out as an RGL file by `npf synth` (what a
# user converts; brushed copper: 195 wavelengths, 167 MB), which is then the reference too.
LADDER_SYNTHETIC = ["brushed_copper"]
# Synthetic anisotropic spectral materials converted straight from their recipes (rendered exactly
# as reference): Table 2 and the rank sweep use the failure case.
SYNTHETIC = ["crossed_lobes_failure"]
# Recipes that also get Table 1 rows (--table1-synthetic): none by default. Each production fit of
# a recipe at 41 wavelengths takes 4 to 7 minutes on 2 cores, and Table 1 needs two (ours and
# Bagher's); brushed copper's Table 1 row comes with the ladder. satin_fabric, red_plastic and
# thin_film_aluminium are left out for the same reason.
TABLE1_SYNTHETIC = []
FAILURE = "crossed_lobes_failure"
PCA_RATIOS = [None, (0.99, 0.99), (0.99, 0.95), (0.99, 0.90), (0.95, 0.95), (0.90, 0.90)]
RANKS = [1, 2, 4, 8, 16]
# The accuracy ladder (docs/fitting.md): tag (file names), label, npf convert flags. "ours" is the
# production conversion's tag (Table 1's, and scripts/make-edit-pictures.sh reuses it).
TIERS = [("paper", "paper", ["--preset", "paper"]),
         ("preview", "preview", ["--preset", "preview"]),
         ("ours", "production (default)", ["--preset", "production"]),
         ("fine", "fine", ["--preset", "fine"])]
NBRDF = "Neural BRDF"
# Albedo column of the ladder: the views the detail fit holds (0..80 degrees), as in fitting.md.
LADDER_THETAS = [0, 20, 40, 60, 70, 80]
# Estimator cells per strategy (npf albedo --samples): NPF files sample their own lobes well
# (standard errors about 0.1 %); a Neural BRDF is sampled by the cosine and its MIS partner, so
# glossy networks need more cells to bring the standard error of the worst difference down.
ALBEDO_SAMPLES = {"npf": 256, "nbrdf": 1024}
# The ladder's lightings besides the shipped studio map (npf render --light, docs/render.md sec. 2a):
# key-rim is a map (environment sampling and a paired floor, as studio); directional is delta
# lights without Monte Carlo, so one render and no floor.
LIGHTS = ["key-rim", "directional"]
# BRDF space: count the pairs with both directions within this angle (the views the fit holds).
BRDF_MAX_THETA = 80.0
# The targets the ladder is judged by: (PSNR in dB, largest file as a fraction of the input).
TARGETS = [(40.0, 1.0 / 8), (45.0, 1.0 / 3)]


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
        before = os.times()
        r = subprocess.run(cmd, stdout=subprocess.PIPE if capture else subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True)
        after = os.times()
        # CPU seconds of the command (all its threads): with the wall time, what a step would take
        # on a machine shared with other work.
        self.last_cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
        if r.returncode != 0:
            raise SystemExit("make-results: failed (%d): %s\n%s" % (r.returncode, " ".join(cmd), r.stderr))
        return r.stdout

    def timed(self, key, out, cmd, log_path=None, source=None):
        """Runs cmd unless `out` exists and is newer than `source` (the file it is made from);
        remembers its wall time under `key`. With log_path, its standard output is kept there (for
        the figures a command prints, e.g. convert's summary)."""
        stale = source is not None and os.path.exists(out) and os.path.getmtime(source) > os.path.getmtime(out)
        if stale or not os.path.exists(out) or key not in self.times or (log_path and not os.path.exists(log_path)):
            start = time.monotonic()
            stdout = self.run(cmd, capture=bool(log_path))
            self.times[key] = time.monotonic() - start
            self.times["cpu:" + key] = self.last_cpu
            if log_path:
                with open(log_path + ".tmp", "w") as f:
                    f.write(stdout)
                os.replace(log_path + ".tmp", log_path)
            self.save_times()
        return self.times[key]

    def save_times(self):
        with open(self.times_path + ".tmp", "w") as f:
            json.dump(self.times, f, indent=1)
        os.replace(self.times_path + ".tmp", self.times_path)

    def cached_json(self, key, fn):
        """fn()'s result, measured once and kept (timings and estimates: a resumed run reports the
        same figures as the run that measured them)."""
        key = "json:" + key
        if key not in self.times:
            self.times[key] = fn()
            self.save_times()
        return self.times[key]

    # -- steps ---------------------------------------------------------------------------------

    def source(self, name):
        """The material a conversion starts from, and the reference it is judged against."""
        if name in LADDER_SYNTHETIC:
            return self.synth(name)
        if name in SYNTHETIC:
            return os.path.join(ROOT, "configs", "materials", name + ".yaml")
        return os.path.join(self.args.shared, "rgl", name + ".bsdf")

    def synth(self, name):
        """The recipe written out as an RGL file (npf synth)."""
        out = self.path(name + ".bsdf")
        cmd = [self.npf, "synth", "--recipe", os.path.join(ROOT, "configs", "materials", name + ".yaml"), "-o", out,
               "--quiet"] + self.args.synth_flags
        self.timed("synth:" + out, out, cmd)
        return out

    def nbrdf(self, name):
        """The paper's baseline: the authors' Neural BRDF network of the material, if there is one."""
        path = os.path.join(self.args.shared, "nbrdf", name + ".h5")
        return path if os.path.exists(path) else None

    def wavelengths(self, name):
        # One quadrature for a material's reference and its conversions, so that colour
        # differences come from the fit alone.
        return None if name in REAL else self.args.render_wavelengths

    def render(self, material, tag, name, spp=None, seed=1, light="studio"):
        # Environment sampling alone: a material and its reference rendered at the same seed are
        # then estimated at the same light directions, and their difference is nearly free of
        # noise (the paired noise floor, docs/metrics.md). "env" in the name keeps a work folder
        # of earlier (MIS) runs from being reused, and the size and sample count those of other
        # settings. The studio map (the default lighting) keeps the names of the runs before
        # --light; other lightings add theirs. Directional lights have no Monte Carlo: one render,
        # whatever spp and seed.
        spp = spp or self.args.spp
        if light == "directional":
            out = self.path("%s.%s.directional.%d.exr" % (name, tag, self.args.size))
        else:
            out = self.path("%s.%s.%senv.%d.%dspp%s.exr" % (name, tag, "" if light == "studio" else light + ".",
                                                          self.args.size, spp,
                                                          "" if seed == 1 else ".seed%d" % seed))
        cmd = [self.npf, "render", material, "-o", out, "--size", str(self.args.size), "--spp",
               str(spp), "--seed", str(seed), "--sampling", "env", "--quiet"]
        if light != "studio":
            cmd += ["--light", light]
        if self.wavelengths(name):
            cmd += ["--wavelengths", self.wavelengths(name)]
        self.timed("render:" + out, out, cmd, source=material)
        return out

    def picture(self, material, tag, name):
        """A MIS render for the side-by-side figures: environment sampling alone, which the
        comparisons use, leaves bright speckles around glossy highlights (they cancel in a
        comparison at the same seed, not in a picture)."""
        out = self.path("%s.%s.mis.%d.%dspp.exr" % (name, tag, self.args.size, self.args.spp))
        cmd = [self.npf, "render", material, "-o", out, "--png", out[:-4] + ".png", "--size", str(self.args.size),
               "--spp", str(self.args.spp), "--seed", "1", "--quiet"]
        if self.wavelengths(name):
            cmd += ["--wavelengths", self.wavelengths(name)]
        self.timed("render:" + out, out, cmd, source=material)
        return out[:-4] + ".png"

    def render_pair(self, material, tag, name, spp=None, light="studio"):
        """The material rendered at seeds 1 and 2: what compare_pair needs for the noise floor."""
        return (self.render(material, tag, name, spp, seed=1, light=light),
                self.render(material, tag, name, spp, seed=2, light=light))

    def compare_light(self, material, reference, tag, name, light):
        """The material against its reference under one of LIGHTS: paired with its floor (a map), or
        the one noise-free pair of renders (directional; its floor is infinite, none is rendered)."""
        if light == "directional":
            m = self.compare(self.render(reference, "reference", name, light=light),
                             self.render(material, tag, name, light=light))
            m["noise_floor_db"] = math.inf
            m["noise_limited"] = False
            return m
        return self.compare_pair(self.render_pair(reference, "reference", name, light=light),
                                 self.render_pair(material, tag, name, light=light))

    def reference_values(self, name):
        """(dirs.txt, <name>.txt) of the RGL group's own loader (rgl/reference in the shared data),
        or None where the material has none."""
        folder = os.path.join(self.args.shared, "rgl", "reference")
        dirs, values = os.path.join(folder, "dirs.txt"), os.path.join(folder, name + ".txt")
        return (dirs, values) if os.path.exists(dirs) and os.path.exists(values) else None

    def brdf_rms(self, material, name):
        """The relative RMS of f_r cos(theta_o) in BRDF space, every channel pooled,
        sqrt(sum (t - r)^2 / sum r^2), over the pairs with both directions within BRDF_MAX_THETA:
        at the 500 reference pairs against the RGL loader's values where the material has them
        (`npf eval --dirs --cos`), else at npf's 500 held-out pairs against the source
        (`npf eval --against --json`). Returns {"relative_rms", "pairs", "truth"}."""
        ref = self.reference_values(name)
        if ref:
            dirs, values = ref
            cmd = [self.npf, "eval", material, "--dirs", dirs, "--cos"]

            def measure():
                test = rows_of(self.run(cmd, capture=True))
                truth = rows_of(open(values).read())
                pairs = rows_of(open(dirs).read())
                if not (len(test) == len(truth) == len(pairs)):
                    raise SystemExit("make-results: %s: %d values, %d reference values, %d pairs" % (
                        " ".join(cmd), len(test), len(truth), len(pairs)))
                cos_max = math.cos(math.radians(BRDF_MAX_THETA))
                num = den = 0.0
                used = 0
                for d, t, r in zip(pairs, test, truth):
                    if d[2] >= cos_max and d[5] >= cos_max:
                        used += 1
                        num += sum((a - b) ** 2 for a, b in zip(t, r))
                        den += sum(b * b for b in r)
                return {"relative_rms": math.sqrt(num / den), "pairs": used, "truth": "rgl-reference"}

            return self.cached_json("brdf:" + " ".join(cmd[2:]) + " " + stamp(material) + " " + stamp(values), measure)
        cmd = [self.npf, "eval", material, "--against", self.source(name), "--max-theta", "%g" % BRDF_MAX_THETA,
               "--json"]
        if self.wavelengths(name):
            cmd += ["--wavelengths", self.wavelengths(name)]

        def against():
            m = json.loads(self.run(cmd, capture=True))
            return {"relative_rms": float(m["relative_rms"]), "pairs": int(m["used"]), "truth": "held-out"}

        return self.cached_json("brdf:" + " ".join(cmd[2:]) + " " + stamp(material) + " " + stamp(self.source(name)),
                                against)

    def convert(self, name, tag, extra):
        """(file, fit seconds): the time npf convert's summary reports (the conversion alone), else
        the command's wall time."""
        out = self.path("%s.%s.npf.exr" % (name, tag))
        summary = out[:-4] + ".log"
        cmd = [self.npf, "convert", self.source(name), "-o", out, "--quiet"] + extra
        if name not in REAL:
            cmd += ["--max-wavelengths", str(self.args.max_wavelengths)] + self.args.synthetic_convert_flags
        seconds = self.timed("convert:" + out, out, cmd, log_path=summary, source=self.source(name))
        m = re.search(r"^\s*time\s+([0-9.]+) s", open(summary).read(), re.M)
        return out, float(m.group(1)) if m else seconds

    def convert_or_fail(self, name, tag, extra):
        """convert(), or (None, npf's error) where npf refuses the conversion: the ladder shows a
        refused tier as such instead of stopping. The refusal is remembered for this npf binary and
        source (a later run with either changed tries again)."""
        key = "failed:convert:%s.%s %s %s %s" % (name, tag, " ".join(extra), stamp(self.npf), stamp(self.source(name)))
        if key in self.times:
            return None, self.times[key]
        try:
            return self.convert(name, tag, extra)
        except SystemExit as e:
            lines = [l for l in str(e).splitlines() if "error:" in l]
            self.times[key] = lines[-1].split("error:", 1)[1].strip() if lines else str(e).strip().splitlines()[-1]
            self.save_times()
            log("  refused: " + self.times[key])
            return None, self.times[key]

    def detail_dropped(self, fitted):
        """Whether npf convert fitted a detail layer and left it out (anisotropic materials, where it
        did not lower the BRDF-space error; docs/fitting.md)."""
        summary = fitted[:-4] + ".log"
        return os.path.exists(summary) and "fitted but not kept" in open(summary).read()

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

    def bench(self, material, against=None):
        """npf bench --json, one thread; measured once per file (see cached_json)."""
        cmd = [self.npf, "bench", material, "--json", "--seconds", str(self.args.bench_seconds), "--threads", "1"]
        if against:
            cmd += ["--against", against]
        return self.cached_json("bench:" + stamp(material) + (":" + stamp(against) if against else ""),
                                lambda: json.loads(self.run(cmd, capture=True)))

    def albedo(self, material, reference, thetas, samples=None):
        """npf albedo MATERIAL --against REFERENCE --json (deterministic, so cached like a file)."""
        cmd = [self.npf, "albedo", material, "--against", reference, "--theta", ",".join(str(t) for t in thetas),
               "--json"]
        if samples:
            cmd += ["--samples", str(samples)]
        if reference.endswith(".bsdf") and os.path.basename(reference)[:-5] in LADDER_SYNTHETIC:
            # The synthesized file's 195 wavelengths: the renders' quadrature instead.
            cmd += ["--wavelengths", self.args.render_wavelengths]
        return self.cached_json("albedo:" + " ".join(cmd[2:]) + " " + stamp(material) + " " + stamp(reference),
                                lambda: json.loads(self.run(cmd, capture=True)))


def rows_of(text):
    """The rows of numbers of a text table, lines starting with '#' and blank ones skipped."""
    return [[float(v) for v in line.split()] for line in text.splitlines() if line.strip() and
            not line.lstrip().startswith("#")]


def stamp(path):
    """A file's name with its modification time: cached figures of a file redone are measured again."""
    return "%s@%d" % (path, os.stat(path).st_mtime_ns)


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
    """panels: list of dicts with title, xlabel, ylabel, logx, series [(label, colour, [(x, y)])
    or (label, colour, [(x, y)], style)], and optional hlines [(y, label)] (dashed guides) and
    legend ("right", default, or "left"). style: {"line": False} draws points only, {"marker":
    "ring"} hollow squares, {"marker": "cross"} crosses, {"in_order": True} joins the points in the
    order given (else by x), {"legend": False} leaves the series out of the legend. Drawn with
    oiiotool: axes, ticks, polylines, points, labels."""
    n = len(panels)
    pw = width // n
    cmd = ["oiiotool", "--create", "%dx%d" % (width, height), "3", "--fill:color=1,1,1", "%dx%d" % (width, height)]

    def text(x, y, s, size=14, color="0,0,0"):
        cmd.extend(["--text:x=%d:y=%d:size=%d:color=%s:font=%s" % (x, y, size, color, FONT), s])

    def marker(kind, colour, px, py):
        if kind == "cross":
            cmd.extend(["--line:color=%s" % colour, "%d,%d,%d,%d" % (px - 5, py - 5, px + 5, py + 5),
                        "--line:color=%s" % colour, "%d,%d,%d,%d" % (px - 5, py + 5, px + 5, py - 5)])
        elif kind == "ring":
            cmd.extend(["--box:color=%s" % colour, "%d,%d,%d,%d" % (px - 5, py - 5, px + 5, py + 5)])
        else:
            cmd.extend(["--box:color=%s:fill=1" % colour, "%d,%d,%d,%d" % (px - 3, py - 3, px + 3, py + 3)])

    for i, p in enumerate(panels):
        x0, x1 = i * pw + 70, (i + 1) * pw - 20
        y0, y1 = height - 60, 40  # y grows downwards
        series = [tuple(s) + ({},) if len(s) == 3 else tuple(s) for s in p["series"]]
        pts = [pt for s in series for pt in s[2]]
        fx = (lambda v: math.log10(v)) if p.get("logx") else (lambda v: v)
        xs = [fx(x) for x, _ in pts]
        ys = [y for _, y in pts] + [y for y, _ in p.get("hlines", [])]
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
        for y, label in p.get("hlines", []):  # dashed guides
            _, py = to_px(10 ** xlo if p.get("logx") else xlo, y)
            for xa in range(x0 + 2, x1, 12):
                cmd.extend(["--line:color=0.5,0.5,0.5", "%d,%d,%d,%d" % (xa, py, min(xa + 6, x1), py)])
            text(x0 + 6, int(py) - 4, label, 12, "0.4,0.4,0.4")
        text(x0, y1 - 16, p["title"], 16)
        text((x0 + x1) // 2 - 60, height - 15, p["xlabel"], 13)
        text(x0 + 5, y1 + 14, p["ylabel"], 13)
        legend_x = x0 + 110 if p.get("legend") == "left" else x1 - 190
        j = 0
        for label, colour, points, style in series:
            if len(points) > 1 and style.get("line", True):
                coords = []
                for x, y in (points if style.get("in_order") else sorted(points)):
                    px, py = to_px(x, y)
                    coords += [int(px), int(py)]
                cmd.extend(["--line:color=%s" % colour, ",".join(map(str, coords))])
            for x, y in points:
                px, py = to_px(x, y)
                marker(style.get("marker", "box"), colour, int(px), int(py))
            if style.get("legend", True):
                text(legend_x, y1 + 20 + 18 * j, label, 13, colour)
                j += 1
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

COLOURS = ["0.1,0.6,0.2", "0.95,0.55,0.0", "0.5,0.2,0.7", "0.1,0.35,0.85", "0.85,0.1,0.1", "0.55,0.3,0.1",
           "0.0,0.6,0.6", "0.4,0.4,0.4"]


def short(name):
    return name[:-4] if name.endswith("_rgb") else name


def fmt_size(mb):
    return "%.1f KB" % (mb * 1e3) if mb < 1 else "%.2f MB" % mb


def fmt_albedo(worst):
    """The worst relative difference, with its standard error where that is not small beside it."""
    v, se = 100 * worst["relative_difference"], 100 * worst["standard_error"]
    text = "%+.1f %% (%g deg)" % (v, worst["theta_deg"])
    return text + (" +- %.1f" % se if se >= 0.5 else "")


def fmt_rms(b):
    return "%.2f %%" % (100 * b["relative_rms"])


def meets(row, psnr, fraction, input_mb):
    return row is not None and row["m"]["PSNR"] >= psnr and row["mb"] <= fraction * input_mb


def fraction_label(fraction):
    return "1/%d" % round(1 / fraction)


def listing(names, total):
    """'3 of 6: felt, paper_white, brushed_copper' (or 'none of 6', 'all 6')."""
    if not names:
        return "none of %d" % total
    if len(names) == total:
        return "all %d" % total
    return "%d of %d: %s" % (len(names), total, ", ".join(short(n) for n in names))


def ladder_verdicts(ladder):
    """Which tiers meet the targets and beat the Neural BRDF, from the measured figures: a table,
    then a few sentences (markdown lines)."""
    names = list(ladder)
    with_nbrdf = [n for n in names if ladder[n]["nbrdf"]]
    labels = [label for _, label, _ in TIERS] + ([NBRDF] if with_nbrdf else [])
    out = ["| tier | " + " | ".join("%g dB at <= %s of the input" % (p, fraction_label(f)) for p, f in TARGETS) +
           " | higher studio PSNR than Neural BRDF | and smaller | higher key-rim PSNR | higher directional PSNR "
           "| lower BRDF rel. RMS than Neural BRDF |",
           "|---|" + "---|" * (len(TARGETS) + 5)]
    for label in labels:
        pool = with_nbrdf if label == NBRDF else names
        cells = []
        for psnr, fraction in TARGETS:
            cells.append(listing([n for n in pool if meets(ladder[n]["by_label"].get(label), psnr, fraction,
                                                           ladder[n]["input_mb"])], len(pool)))
        if label == NBRDF:
            cells += ["", "", "", "", ""]
        else:
            # A tier npf refused on a material counts as not ahead there.
            pool = [n for n in with_nbrdf if label in ladder[n]["by_label"]]
            better = [n for n in pool
                      if ladder[n]["by_label"][label]["m"]["PSNR"] > ladder[n]["by_label"][NBRDF]["m"]["PSNR"]]
            smaller = [n for n in better if ladder[n]["by_label"][label]["mb"] <= ladder[n]["by_label"][NBRDF]["mb"]]
            cells += [listing(better, len(with_nbrdf)), listing(smaller, len(with_nbrdf))]
            for light in LIGHTS:
                cells.append(listing([n for n in pool if ladder[n]["by_label"][label]["lights"][light]["PSNR"] >
                                      ladder[n]["by_label"][NBRDF]["lights"][light]["PSNR"]], len(with_nbrdf)))
            cells.append(listing([n for n in pool if ladder[n]["by_label"][label]["brdf"]["relative_rms"] <
                                  ladder[n]["by_label"][NBRDF]["brdf"]["relative_rms"]], len(with_nbrdf)))
        out.append("| %s | %s |" % (label, " | ".join(cells)))
    out.append("")
    # Per material: the smallest tier that meets each target, and the PSNR gained over the network.
    for psnr, fraction in TARGETS:
        parts = []
        for n in names:
            ok = [row for row in ladder[n]["rows"] if meets(row, psnr, fraction, ladder[n]["input_mb"])]
            best = min(ok, key=lambda row: row["mb"]) if ok else None
            if best:
                parts.append("%s %s (%s dB, 1/%.0f)" % (short(n), best["tier"].split()[0], fmt_psnr(best["m"]["PSNR"]),
                                                       ladder[n]["input_mb"] / best["mb"]))
            else:
                parts.append("%s no tier" % short(n))
        out.append("- **%g dB at <= %s of the input**, the smallest file that does it: %s." %
                   (psnr, fraction_label(fraction), "; ".join(parts)))
    if with_nbrdf:
        parts = []
        for n in with_nbrdf:
            nb = ladder[n]["by_label"][NBRDF]
            gains = ["%s %+.1f dB at %.1fx the size" % (row["tier"].split()[0], row["m"]["PSNR"] - nb["m"]["PSNR"],
                                                       row["mb"] / nb["mb"])
                     for row in ladder[n]["rows"] if row["tier"] != NBRDF]
            parts.append("%s (%s dB): %s" % (short(n), fmt_psnr(nb["m"]["PSNR"]), ", ".join(gains)))
        out.append("- **Against Neural BRDF** (studio PSNR of each tier minus the network's, and its size as a "
                   "multiple of the network's %s): %s." % (fmt_size(ladder[with_nbrdf[0]]["by_label"][NBRDF]["mb"]),
                                                          "; ".join(parts)))
        parts = []
        for n in with_nbrdf:
            nb = ladder[n]["by_label"][NBRDF]
            cells = ["%s %+.1f / %+.1f" % (row["tier"].split()[0],
                                           *(row["lights"][light]["PSNR"] - nb["lights"][light]["PSNR"]
                                             for light in LIGHTS))
                     for row in ladder[n]["rows"] if row["tier"] != NBRDF]
            parts.append("%s (%s / %s dB): %s" % (short(n), *(fmt_psnr(nb["lights"][light]["PSNR"]) for light in LIGHTS),
                                                  ", ".join(cells)))
        out.append("- **Against Neural BRDF under key-rim / directional** (each tier's PSNR minus the network's, "
                   "in dB): %s." % "; ".join(parts))
        parts = []
        for n in with_nbrdf:
            nb = ladder[n]["by_label"][NBRDF]
            cells = ["%s %s" % (row["tier"].split()[0], fmt_rms(row["brdf"])) for row in ladder[n]["rows"]
                     if row["tier"] != NBRDF]
            parts.append("%s (network %s): %s" % (short(n), fmt_rms(nb["brdf"]), ", ".join(cells)))
        out.append("- **BRDF rel. RMS against Neural BRDF** (at the reference pairs within %g degrees): %s." % (
            BRDF_MAX_THETA, "; ".join(parts)))
    refused = ["%s %s" % (short(n), f["tier"]) for n in names for f in ladder[n]["failed"]]
    if refused:
        out.append("- **Refused.** `npf convert` refused these conversions (its error is in the tier's row of the "
                   "material's table): %s. They count as missing every target and as behind the network." %
                   ", ".join(refused))
    limited = ["%s %s (studio)" % (short(n), row["tier"]) for n in names for row in ladder[n]["rows"]
               if row["m"].get("noise_limited")]
    limited += ["%s %s (key-rim)" % (short(n), row["tier"]) for n in names for row in ladder[n]["rows"]
                if row["lights"]["key-rim"].get("noise_limited")]
    out.append("- **Noise.** %s" % (
        "Every studio and key-rim PSNR in the tables is more than 3 dB below its paired noise floor, so each "
        "measures the materials' difference, not the renders' noise (directional renders have none)." if not limited
        else "Within 3 dB of the noise floor (starred; their true PSNR is higher, so a target they meet holds, one "
        "they miss may not): %s. Directional renders have no noise." % ", ".join(limited)))
    return out


def sections(text):
    """[(heading line or None, text)]: text cut before each line starting with '## '."""
    parts = re.split(r"(?m)^(?=## )", text)
    return [(part.splitlines()[0] if part.startswith("## ") else None, part) for part in parts]


def keep_hand_sections(old, new):
    """new with the sections of old (its generated part) that this script does not write, each put
    back after the section it followed (e.g. "Speed beside the paper's", written by hand with
    figures from other runs): regenerating must not lose them."""
    new_parts = sections(new)
    written = {h for h, _ in new_parts}
    previous = None
    for heading, part in sections(old):
        if heading is not None and heading not in written:
            at = next((k + 1 for k, (h, _) in enumerate(new_parts) if h == previous), len(new_parts))
            if not part.endswith("\n\n"):
                part = part.rstrip("\n") + "\n\n"
            new_parts.insert(at, (heading, part))
            written.add(heading)
        previous = heading
    return "".join(part for _, part in new_parts)


def main():
    global REAL, SYNTHETIC, TABLE1_SYNTHETIC, LADDER_SYNTHETIC
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--npf", default=os.path.join(ROOT, "build", "tools", "npf", "npf"))
    ap.add_argument("--shared", default=os.path.join(os.path.dirname(ROOT), "shared", "data"))
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "results-work"))
    ap.add_argument("--docs", default=os.path.join(ROOT, "docs"))
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=128)
    ap.add_argument("--converge", type=int, default=0,
                    help="also render Table 1's real comparisons with this many times --spp (0: skip; the paired "
                         "noise floor beside every PSNR answers the same question at no extra cost)")
    ap.add_argument("--max-wavelengths", type=int, default=41)
    ap.add_argument("--render-wavelengths", default="380:780:41")
    ap.add_argument("--bench-seconds", type=float, default=0.5)
    ap.add_argument("--paper-sweeps", type=int, default=20,
                    help="cap the paper preset's sweeps on the ladder's synthetic materials (0: no cap). Uncapped, "
                         "its fit of brushed copper runs to its 500-sweep cap, well over half an hour on 2 cores, "
                         "while its weighted error moves by less than 0.2 %% after the tenth sweep")
    ap.add_argument("--ladder-synthetic", default=",".join(LADDER_SYNTHETIC),
                    help="recipes of configs/materials/ written out by npf synth and put through the ladder (and "
                         "Table 1), comma-separated; brushed copper takes about 12 minutes on 2 cores, "
                         "satin_fabric would take about as long")
    ap.add_argument("--table1-synthetic", default="",
                    help="recipes of configs/materials/ that also get a Table 1 row, comma-separated (e.g. "
                         "crossed_lobes_failure,satin_fabric): 8 to 14 minutes each on 2 cores")
    ap.add_argument("--quick", action="store_true", help="small renders, few materials: checks the pipeline")
    ap.add_argument("--fresh", action="store_true", help="discard the work folder first")
    args = ap.parse_args()
    args.synth_flags, args.synthetic_convert_flags = [], []
    LADDER_SYNTHETIC = [n for n in args.ladder_synthetic.split(",") if n]
    TABLE1_SYNTHETIC = [n for n in args.table1_synthetic.split(",") if n]
    SYNTHETIC = SYNTHETIC + [n for n in TABLE1_SYNTHETIC if n not in SYNTHETIC]
    if args.quick:
        args.size, args.spp, args.max_wavelengths = 64, 16, 8
        # A small brushed copper (8 wavelengths): the synth path, not the 167 MB file.
        args.synth_flags = ["--wavelengths", "380:780:8"]
        # The anisotropic fits on preview's grid, with few sweeps: the paper's grid takes minutes.
        args.synthetic_convert_flags = ["--grid", "32,64,32,64", "--g-grid", "32,64", "--iterations", "20"]
        REAL = REAL[2:3]
        args.work += "-quick"
    if args.fresh and os.path.isdir(args.work):
        shutil.rmtree(args.work)
    r = Runner(args)
    # --quick must not overwrite the committed figures: its images go to a folder of their own.
    image_folder = "results-quick" if args.quick else "results"
    images = os.path.join(args.docs, image_folder)
    os.makedirs(images, exist_ok=True)
    md = []
    stages = []  # (stage, wall seconds, CPU seconds of the npf processes)
    clock = [time.monotonic(), os.times()]

    def stage(name):
        now, t = time.monotonic(), os.times()
        stages.append((name, now - clock[0], (t.children_user - clock[1].children_user) +
                       (t.children_system - clock[1].children_system)))
        log("%s: %.0f s wall, %.0f s CPU" % stages[-1])
        clock[0], clock[1] = now, t

    # The accuracy ladder: every preset and the Neural BRDF on each material, judged against the
    # raw file by paired renders (with the noise floor), albedo, size and speed.
    log("Ladder")
    ladder = {}
    capped = {}  # material -> the paper tier's sweep cap, where it has one
    for name in REAL + LADDER_SYNTHETIC:
        raw = r.source(name)
        ref = r.render_pair(raw, "reference", name)
        rows = []
        failed = []  # tiers whose conversion npf refused: (label, its error), shown as such
        for tag, label, extra in TIERS:
            if tag == "paper" and name in LADDER_SYNTHETIC and args.paper_sweeps > 0 and \
                    "--iterations" not in args.synthetic_convert_flags:
                tag, extra = "paper-%dsweeps" % args.paper_sweeps, extra + ["--iterations", str(args.paper_sweeps)]
                capped[name] = args.paper_sweeps
            if tag == "ours":  # Table 1 and the pictures need the production conversion: no failing there
                fitted, seconds = r.convert(name, tag, extra)
            else:
                fitted, seconds = r.convert_or_fail(name, tag, extra)
                if fitted is None:
                    failed.append({"tier": label, "tag": tag, "error": seconds})
                    continue
            img = r.render_pair(fitted, tag, name)
            heat = r.path("%s.%s.heat.png" % (name, tag)) if tag == "ours" else None
            rows.append({"tier": label, "tag": tag, "file": fitted, "mb": file_mb(fitted), "fit_s": seconds,
                         "dropped": r.detail_dropped(fitted),
                         "m": r.compare_pair(ref, img, heat),
                         "lights": {light: r.compare_light(fitted, raw, tag, name, light) for light in LIGHTS},
                         "brdf": r.brdf_rms(fitted, name),
                         "albedo": r.albedo(fitted, raw, LADDER_THETAS, ALBEDO_SAMPLES["npf"])["worst"],
                         "eval_ns": r.bench(fitted)["eval_memory_ns"]})
        nb = r.nbrdf(name)
        if nb:
            img = r.render_pair(nb, "nbrdf", name)
            # npf bench times NPF files; the network's own evaluation is its --against column.
            production = [row for row in rows if row["tag"] == "ours"][0]
            rows.append({"tier": NBRDF, "tag": "nbrdf", "file": nb, "mb": file_mb(nb), "fit_s": None,
                         "m": r.compare_pair(ref, img),
                         "lights": {light: r.compare_light(nb, raw, "nbrdf", name, light) for light in LIGHTS},
                         "brdf": r.brdf_rms(nb, name),
                         "albedo": r.albedo(nb, raw, LADDER_THETAS, ALBEDO_SAMPLES["nbrdf"])["worst"],
                         "eval_ns": r.bench(production["file"], against=nb)["eval_raw_ns"]})
        # The raw file through npf's own reader, by the same measure: what the column reads when
        # the conversion is perfect (the reader against the RGL loader).
        reader = r.brdf_rms(raw, name) if r.reference_values(name) else None
        ladder[name] = {"input_mb": file_mb(raw), "input": raw, "rows": rows, "nbrdf": nb, "failed": failed,
                        "reader": reader,
                        "by_label": {row["tier"]: row for row in rows}}
    stage("ladder")
    plot(os.path.join(images, "ladder.png"), [
        {"title": "the accuracy ladder: render PSNR against file size", "xlabel": "file size (KB, log)",
         "ylabel": "PSNR (dB)", "logx": True, "legend": "left",
         "hlines": [(psnr, "%g dB" % psnr) for psnr, _ in TARGETS],
         "series": [s for k, name in enumerate(ladder) for s in (
             (short(name), COLOURS[k % len(COLOURS)],
              [(row["mb"] * 1e3, min(row["m"]["PSNR"], 99)) for row in ladder[name]["rows"] if row["tag"] != "nbrdf"],
              {"in_order": True}),
             ("", COLOURS[k % len(COLOURS)],
              [(row["mb"] * 1e3, min(row["m"]["PSNR"], 99)) for row in ladder[name]["rows"] if row["tag"] == "nbrdf"],
              {"line": False, "marker": "cross", "legend": False}))] +
            [("crosses: Neural BRDF", "0,0,0", [], {})]}], width=900, height=520)

    # Table 1: the paper's weight against Bagher's; ours is the ladder's production conversion.
    log("Table 1")
    t1 = []
    for name in REAL + LADDER_SYNTHETIC + TABLE1_SYNTHETIC:
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
    stage("table 1")
    # Energy: directional albedo of each real conversion against its raw file (npf albedo),
    # mean over the channels of the relative difference, at a few view angles up to grazing.
    log("Energy")
    albedo_thetas = [0, 30, 60, 75, 85, 89]
    energy = {}
    for name in REAL:
        rows = r.albedo(r.path("%s.ours.npf.exr" % name), r.source(name), albedo_thetas)["rows"]
        energy[name] = [sum(row[-1]) / len(row[-1]) for row in rows]
    stage("energy")

    # Convergence (optional, --converge): Table 1's real comparisons again with `converge` times
    # the samples. If the PSNR barely moves, the fit's error, not Monte Carlo noise, is what
    # Table 1 measures: a check of the floors.
    converged = {}
    high_spp = args.spp * args.converge
    if args.converge > 0:
        log("Convergence")
        for name in REAL:
            ref_hi = r.render_pair(r.source(name), "reference-%dspp" % high_spp, name, spp=high_spp)
            ours_hi = r.render_pair(r.path("%s.ours.npf.exr" % name), "ours-%dspp" % high_spp, name, spp=high_spp)
            converged[name] = {"ours": r.compare_pair(ref_hi, ours_hi)}
        stage("convergence")

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
                                                         "--compress-pca", "%g,%g" % ratios], source=lossless)
        info = r.run([args.npf, "info", fitted], capture=True)
        ranks = [l.split(":", 1)[1].split()[0] for l in info.splitlines() if l.strip().startswith(("D rank", "G rank"))][:2]
        img = r.render_pair(fitted, tag, pca_material)
        t2.append({"ratios": ratios, "mb": file_mb(fitted), "ranks": ranks, "fit_s": seconds,
                   "m": r.compare_pair(ref, img)})
    uncompressed = t2[0]["mb"]
    stage("table 2")

    # Speed against accuracy: the ladder's fit times (no new conversions) and evaluation time
    # against rank.
    log("Speed and accuracy")
    rank_rows = []
    for k in RANKS:
        fitted = r.path("%s.rank-%d.npf.exr" % (pca_material, k))
        r.timed("edit:" + fitted, fitted, [args.npf, "edit", lossless, "-o", fitted, "--no-albedo-check",
                                            "--compress-rank", "%d,%d" % (k, k)], source=lossless)
        img = r.render_pair(fitted, "rank-%d" % k, pca_material)
        b = r.bench(fitted)
        rank_rows.append({"rank": k, "mb": file_mb(fitted), "eval_ns": b["eval_memory_ns"],
                          "eval_full_ns": b["eval_memory_full_ns"], "m": r.compare_pair(ref, img)})
    plot(os.path.join(images, "speed_accuracy.png"), [
        {"title": "fit time against render PSNR (the ladder's tiers)", "xlabel": "fit time (s, log)",
         "ylabel": "PSNR (dB)", "logx": True, "legend": "left",
         "series": [(short(name), COLOURS[k % len(COLOURS)],
                     [(max(row["fit_s"], 0.05), min(row["m"]["PSNR"], 99)) for row in ladder[name]["rows"]
                      if row["fit_s"] is not None])
                    for k, name in enumerate(ladder)]},
        {"title": "evaluation time against rank (%s)" % pca_material, "xlabel": "SVD rank of D and G",
         "ylabel": "ns per eval", "series": [
             ("4 hero wavelengths", "0.1,0.3,0.8", [(q["rank"], q["eval_ns"]) for q in rank_rows]),
             ("every stored channel", "0.8,0.2,0.1", [(q["rank"], q["eval_full_ns"]) for q in rank_rows])]}],
        width=1100, height=460)
    stage("rank sweep")

    # Side-by-side images: the production conversion and the heatmap of its comparison (Table 1's);
    # the failure case, when it has no Table 1 row, as Table 2's 99 / 99 row (the production
    # preset's ratios, without the detail layer, which production keeps on an anisotropic material
    # only where it lowers the BRDF-space error).
    shown = []
    for name in ("ilm_l3_37_metallic_rgb", "brushed_copper", FAILURE):
        if name in REAL + LADDER_SYNTHETIC + TABLE1_SYNTHETIC:
            shown.append((name, "ours", "NPF (production)"))
        elif name == FAILURE:
            shown.append((name, "pca-0.99-0.99", "NPF (PCA 99 / 99)"))
    for name, tag, label in shown:
        heat = r.path("%s.%s.heat.png" % (name, tag))
        if not os.path.exists(heat):
            r.compare_pair(r.render_pair(r.source(name), "reference", name),
                           r.render_pair(r.path("%s.%s.npf.exr" % (name, tag)), tag, name), heat)
        side_by_side(os.path.join(images, name + ".png"),
                     [r.picture(r.source(name), "reference", name),
                      r.picture(r.path("%s.%s.npf.exr" % (name, tag)), tag, name), heat],
                     ["reference", label, "relMSE 0..5 %"])
    stage("pictures")

    # -- write docs/results.md
    md.append("# Results: the accuracy ladder and the paper's tables on our data\n")
    md.append("Regenerated by `python3 scripts/make-results.py` (%s; renders %dx%d, %d samples per pixel, "
              "environment sampling alone (`--sampling env`), seed 1, and seed 2 for the noise floors; "
              "spectral renders at %s nm). Metrics are defined in [metrics.md](metrics.md); the "
              "renderer in [render.md](render.md). Every number below was produced by that run on the "
              "development machine (2-core EPYC VM).\n" % (time.strftime("%Y-%m-%d"), args.size, args.size, args.spp,
                                                           args.render_wavelengths))

    md.append("## The accuracy ladder\n")
    md.append("Each material converted at every tier of `npf convert --preset` ([fitting.md](fitting.md), \"The "
              "accuracy ladder\"): **paper** (the paper's pure model: no detail layer, G open at the horizon), "
              "**preview** (detail layer 16 x 8 x 16), **production** (the default, 32 x 12 x 32) and **fine** "
              "(40 x 20 x 40); beside them the paper's baseline, the authors' **Neural BRDF** network of the same "
              "measured material (`../shared/data/nbrdf/*.h5`, rendered by `npf render`). Reference: the raw "
              "file, the RGL .bsdf%s." % (
                  "" if not LADDER_SYNTHETIC else
                  " (%s: the recipe written out by `npf synth --recipe configs/materials/NAME.yaml`, %s, converted "
                  "at %d of its wavelengths; renders and albedo at %s nm)" % (
                      ", ".join(LADDER_SYNTHETIC),
                      " and ".join(fmt_size(ladder[n]["input_mb"]) for n in LADDER_SYNTHETIC),
                      args.max_wavelengths, args.render_wavelengths)))
    md.append("")
    ref_pairs = [row["brdf"]["pairs"] for lad in ladder.values() for row in lad["rows"]
                 if row["brdf"]["truth"] == "rgl-reference"]
    held_out_names = [n for n in ladder if ladder[n]["rows"][0]["brdf"]["truth"] == "held-out"]
    md.append("- **Studio PSNR, SSIM**: paired renders under the shipped studio map (`npf render`'s default "
              "lighting; reference and test at the same seed, environment sampling alone), the display-encoded "
              "images compared by `npf compare`; **floor**: the PSNR's paired noise floor, the same pair again at "
              "seed 2 (`npf compare --floor`, [metrics.md](metrics.md) sec. 5); a star marks a PSNR within 3 dB of "
              "its floor.")
    md.append("- **Key-rim PSNR** and its **floor**: the same paired comparison under `npf render --light key-rim` "
              "([render.md](render.md) sec. 2a: a dim grey sky with two small bright discs, a key light above and in "
              "front of the sphere, whose reflection shows the height and shape of a glossy peak, and a grazing rim "
              "light behind it, which lights the grazing band along the silhouette), same size, samples, seeds and "
              "environment sampling as studio.")
    md.append("- **Directional PSNR**: `npf render --light directional` (the key's and the rim's directions as delta "
              "lights, one ray per pixel, no Monte Carlo), reference and test compared by `npf compare`. Nothing in "
              "it is noise, so it has no floor (none is rendered) and is never starred; it is the pointwise check.")
    md.append("- **BRDF rel. RMS**: the relative RMS error of f_r cos(theta_o) in BRDF space, every channel pooled, "
              "sqrt(sum (t - r)^2 / sum r^2), over the pairs with both directions within %g degrees of the normal. "
              "t: the conversion (or network) evaluated by `npf eval CONV --dirs dirs.txt --cos`; pairs and truth r: "
              "the 500 reference pairs of `../shared/data/rgl/reference/dirs.txt` (%s of them within %g degrees) "
              "and the values the RGL group's own loader (`powitacq_rgb`) gives there "
              "(`reference/<material>.txt`): a truth that does not go through npf's reader (the raw files "
              "themselves, through npf's reader, score %s by it).%s" % (
                  BRDF_MAX_THETA, "/".join(str(k) for k in sorted(set(ref_pairs))) or "none", BRDF_MAX_THETA,
                  "at most %.1e" % max(lad["reader"]["relative_rms"] for lad in ladder.values() if lad["reader"])
                  if any(lad["reader"] for lad in ladder.values()) else "-",
                  "" if not held_out_names else
                  " %s (no reference values): `npf eval CONV --against SOURCE --json` instead, its `relative_rms`, "
                  "the same quantity at npf's 500 fixed held-out pairs against the source file as npf reads it "
                  "(marked \"held-out pairs\" in its table)." % ", ".join(held_out_names)))
    md.append("- **Albedo**: the largest relative difference of the directional albedo from the raw file over the "
              "views %s degrees and every channel (`npf albedo CONV --against RAW --samples N`; N = %d for NPF "
              "files, %d for the networks, whose sampler finds glossy lobes less well), with the view where it "
              "is and, where it is not small, the estimate's standard error in percent." % (
                  ", ".join(str(t) for t in LADDER_THETAS), ALBEDO_SAMPLES["npf"], ALBEDO_SAMPLES["nbrdf"]))
    md.append("- **Fit**: `npf convert`'s own time (its summary), on all cores. **Eval**: `npf bench`, one thread, "
              "the closure's in-memory path at 4 hero wavelengths (RGB files: R, G, B), ns per call; for the "
              "network, its own evaluation on the same directions (`npf bench PRODUCTION.exr --against NET.h5`, "
              "`eval_raw_ns`).\n")
    md.append("![the accuracy ladder](%s/ladder.png)\n" % image_folder)
    md.append("Each line joins a material's paper, preview, production and fine conversions, in that order; "
              "crosses: the Neural BRDF of the same material (studio PSNR). Which tiers meet the targets (studio "
              "PSNR and size, computed from the tables below), and on how many materials each tier is ahead of the "
              "network under each lighting and in BRDF space:\n")
    md.extend(ladder_verdicts(ladder))
    md.append("")
    for name in ladder:
        lad = ladder[name]
        md.append("**%s** (input %s, `%s`)\n" % (name, fmt_size(lad["input_mb"]), os.path.basename(lad["input"])))
        held_out = lad["rows"][0]["brdf"]["truth"] == "held-out"
        md.append("| tier | size | ratio to input | studio PSNR (dB) | floor (dB) | key-rim PSNR (dB) | floor (dB) "
                  "| directional PSNR (dB) | SSIM (studio) | BRDF rel. RMS%s | worst albedo error, 0..80 deg "
                  "| fit (s) | eval (ns) |" % (" (held-out pairs)" if held_out else ""))
        md.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        order = [label for _, label, _ in TIERS] + [NBRDF]
        for row in sorted(lad["rows"] + lad["failed"], key=lambda q: order.index(q["tier"])):
            if "error" in row:
                error = row["error"].replace(os.path.dirname(lad["input"]) + os.sep, "").replace("|", "/")
                md.append("| %s | refused by `npf convert`: %s |%s" % (row["tier"], error, " |" * 11))
                continue
            kr, dl = row["lights"]["key-rim"], row["lights"]["directional"]
            md.append("| %s | %s | 1/%.1f | %s | %s | %s | %s | %s | %.4f | %s | %s | %s | %.0f |" % (
                row["tier"] + (" (detail layer not kept)" if row.get("dropped") else ""), fmt_size(row["mb"]),
                lad["input_mb"] / row["mb"], fmt_psnr_judged(row["m"]),
                fmt_psnr(row["m"]["noise_floor_db"]), fmt_psnr_judged(kr), fmt_psnr(kr["noise_floor_db"]),
                fmt_psnr(dl["PSNR"]), row["m"]["SSIM"], fmt_rms(row["brdf"]), fmt_albedo(row["albedo"]),
                "%.1f" % row["fit_s"] if row["fit_s"] is not None else "(trained)", row["eval_ns"]))
        md.append("")
        if held_out:
            md.append("(BRDF rel. RMS: %s has no values from the RGL group's loader; the column is `npf eval CONV "
                      "--against %s --json`, `relative_rms`: the same quantity at npf's 500 fixed held-out pairs "
                      "(%d within %g degrees), against the source file as read by npf%s.)\n" % (
                          name, os.path.basename(lad["input"]), lad["rows"][0]["brdf"]["pairs"], BRDF_MAX_THETA,
                          ", at %s nm" % args.render_wavelengths if name not in REAL else ""))
        if name in capped:
            md.append("(paper: the preset with its sweeps capped at %d, `--iterations %d`. Uncapped, the line search "
                      "crawls on to the preset's 500-sweep cap, longer than all the rest of this run on 2 cores, "
                      "while the weighted error moves by less than 0.2 %% after the tenth sweep (`NPF_AWLS_TRACE=1`, "
                      "first block).)\n" % (capped[name], capped[name]))

    md.append("## Table 1: our anisotropic weight against Bagher's\n")
    md.append("Sphere scene under the default environment map, against the raw file as above%s. Both fits use "
              "the production preset (ours is the ladder's production conversion); only the volume weight "
              "differs. Fit: ours, in seconds.\n" % (
                  " (%s: the recipe evaluated exactly, fitted at %d wavelengths)" % (", ".join(TABLE1_SYNTHETIC),
                                                                                  args.max_wavelengths)
                  if TABLE1_SYNTHETIC else ""))
    md.append("| material | ours: MAPE | relMSE | PSNR (dB) | floor (dB) | SSIM | Bagher: MAPE | relMSE | PSNR (dB) "
              "| floor (dB) | SSIM | fit (s) |")
    md.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for row in t1:
        md.append("| %s | %s | %s | %.1f |" % (row["name"], " | ".join(metrics_cells(row["ours"])),
                                              " | ".join(metrics_cells(row["bagher"])), row["ours_fit_s"]))
    md.append("")
    md.append(FLOOR_NOTE)
    if converged:
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
            md.append("| %s | %s | %s | %s | %s | %.4f |" % (
                name, fmt_psnr_judged(low), fmt_psnr(low["noise_floor_db"]), fmt_psnr_judged(c),
                fmt_psnr(c["noise_floor_db"]), c["SSIM"]))
    md.append("\n## Energy: directional albedo against the raw file\n")
    md.append("`npf albedo CONVERSION --against RAW` ([albedo.md](albedo.md)) for the production conversions: the "
              "relative difference of the directional albedo, mean over R, G and B, at each view angle, up to "
              "grazing (the ladder's column stops at 80 degrees, the views the fit holds). Negative: the conversion "
              "reflects less light than the measured material.\n")
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
    md.append("Left: the ladder's fit times (paper, preview, production, fine) against their PSNR. Right: evaluation "
              "time against SVD rank on %s (`npf bench`, one thread, in-memory path):\n" % pca_material)
    md.append("| rank D, G | size (MB) | eval, 4 hero wavelengths (ns) | eval, every stored channel (ns) | PSNR (dB) "
              "| floor (dB) |")
    md.append("|---|---|---|---|---|---|")
    for q in rank_rows:
        md.append("| %d | %.3f | %.0f | %.0f | %s | %s |" % (q["rank"], q["mb"], q["eval_ns"], q["eval_full_ns"],
                                                         fmt_psnr_judged(q["m"]), fmt_psnr(q["m"]["noise_floor_db"])))
    md.append("\n## Side by side\n")
    for name, tag, label in shown:
        md.append("**%s**: reference, %s (pictures rendered with MIS), relMSE heatmap of %s comparison "
                  "(environment sampling, blue 0 to red 5 %%)\n" % (name, label, "Table 1's" if tag == "ours"
                                                                     else "Table 2's"))
        md.append("![%s](%s/%s.png)\n" % (name, image_folder, name))
    md.append("<!-- analysis -->\n")
    out = os.path.join(args.docs, "results.md" if not args.quick else "results-quick.md")
    analysis = ""
    text = "\n".join(md)
    if os.path.exists(out):
        old = open(out).read()
        if "<!-- analysis -->" in old:
            analysis = "\n" + old.split("<!-- analysis -->", 1)[1].lstrip("\n")
        text = keep_hand_sections(old.split("<!-- analysis -->", 1)[0], text)
    with open(out + ".tmp", "w") as f:
        f.write(text + analysis)
    os.replace(out + ".tmp", out)
    log("wrote " + out)
    log("stages (wall, CPU of the npf processes; this run's steps only, cached ones cost nothing):")
    for name, wall, cpu in stages:
        log("  %-12s %7.0f s wall %7.0f s CPU" % (name, wall, cpu))


if __name__ == "__main__":
    main()
