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
import os
import shutil
import sys
import time
from types import SimpleNamespace

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # the results package beside this script

from results import measure  # noqa: E402
from results.report import write_report  # noqa: E402
from results.runner import Runner, log  # noqa: E402
from results.settings import FAILURE, LADDER_SYNTHETIC, REAL, ROOT, SYNTHETIC  # noqa: E402


def parse_args():
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
    # The materials, on the arguments (the runner and the report read them there).
    args.synth_flags, args.synthetic_convert_flags = [], []
    args.real = list(REAL)
    args.ladder_synthetic = [n for n in args.ladder_synthetic.split(",") if n]
    args.table1_synthetic = [n for n in args.table1_synthetic.split(",") if n]
    args.synthetic = SYNTHETIC + [n for n in args.table1_synthetic if n not in SYNTHETIC]
    if args.quick:
        args.size, args.spp, args.max_wavelengths = 64, 16, 8
        # A small brushed copper (8 wavelengths): the synth path, not the 167 MB file.
        args.synth_flags = ["--wavelengths", "380:780:8"]
        # The anisotropic fits on preview's grid, with few sweeps: the paper's grid takes minutes.
        args.synthetic_convert_flags = ["--grid", "32,64,32,64", "--g-grid", "32,64", "--iterations", "20"]
        args.real = args.real[2:3]
        args.work += "-quick"
    return args


class Stages:
    """Each stage's wall time and the CPU time of the npf processes it ran, logged as it ends."""

    def __init__(self):
        self.done = []  # (stage, wall seconds, CPU seconds)
        self.clock = [time.monotonic(), os.times()]

    def end(self, name):
        now, t = time.monotonic(), os.times()
        self.done.append((name, now - self.clock[0], (t.children_user - self.clock[1].children_user) +
                          (t.children_system - self.clock[1].children_system)))
        log("%s: %.0f s wall, %.0f s CPU" % self.done[-1])
        self.clock = [now, t]

    def summary(self):
        log("stages (wall, CPU of the npf processes; this run's steps only, cached ones cost nothing):")
        for name, wall, cpu in self.done:
            log("  %-12s %7.0f s wall %7.0f s CPU" % (name, wall, cpu))


def main():
    args = parse_args()
    if args.fresh and os.path.isdir(args.work):
        shutil.rmtree(args.work)
    r = Runner(args)
    # --quick must not overwrite the committed figures: its images go to a folder of their own.
    f = SimpleNamespace(args=args, image_folder="results-quick" if args.quick else "results",
                        albedo_thetas=[0, 30, 60, 75, 85, 89], high_spp=args.spp * args.converge,
                        pca_material=FAILURE, converged={})
    images = os.path.join(args.docs, f.image_folder)
    os.makedirs(images, exist_ok=True)
    stages = Stages()
    f.ladder, f.capped = measure.measure_ladder(r, args)
    stages.end("ladder")
    measure.plot_ladder(images, f.ladder)
    f.t1 = measure.measure_table1(r, args)
    stages.end("table 1")
    f.energy = measure.measure_energy(r, args, f.albedo_thetas)
    stages.end("energy")
    if args.converge > 0:
        f.converged = measure.measure_convergence(r, args, f.high_spp)
        stages.end("convergence")
    f.t2, reference, lossless = measure.measure_table2(r, args, f.pca_material)
    stages.end("table 2")
    f.rank_rows = measure.measure_ranks(r, args, f.pca_material, reference, lossless)
    measure.plot_speed(images, f.ladder, f.pca_material, f.rank_rows)
    stages.end("rank sweep")
    f.shown = measure.draw_pictures(r, args, images)
    stages.end("pictures")
    log("wrote " + write_report(f))
    stages.summary()


if __name__ == "__main__":
    main()
