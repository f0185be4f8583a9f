"""The steps of make-results.py: each runs the npf tool once (npf synth, convert, render, compare,
eval, bench, albedo) and keeps its output in the work folder, reused by the next run."""

import json
import math
import os
import re
import subprocess
import sys
import time

from results.settings import BRDF_MAX_THETA, ROOT


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
        if name in self.args.ladder_synthetic:
            return self.synth(name)
        if name in self.args.synthetic:
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
        return None if name in self.args.real else self.args.render_wavelengths

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
        if name not in self.args.real:
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
        if reference.endswith(".bsdf") and os.path.basename(reference)[:-5] in self.args.ladder_synthetic:
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


def file_mb(path):
    return os.path.getsize(path) / 1e6
