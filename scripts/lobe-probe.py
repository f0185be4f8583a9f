#!/usr/bin/env python3
"""How much would more separable lobes buy? A probe, not a product feature.

Fits sums of K NPF lobes,
    rho = rho_d + sum_k D_k(theta_h) F_k(theta_d) G_k(theta_i) G_k(theta_o) / (cos theta_i cos theta_o),
to an isotropic material sampled on a Rusinkiewicz grid (square-root mapped theta_h), by
alternating weighted least squares with npf's default weights (the paper's volume form,
w_I = (cos theta_i cos theta_o)^2, w_C = 1 / (rho + 0.01)), and prints the weighted error
relative to the data's weighted energy for K = 1, 2, 3, next to the same figure for the
conversion `npf convert` wrote (one lobe, bilinear tables, the real fitter).

The probe's tables are nearest-cell (coarser than npf's bilinear ones) and its K = 1 fit is
a check on the probe: it should land near the conversion's figure. The ratio between K = 1
and K = 2 is an upper estimate of what a second lobe would buy in the fit's own measure;
docs/fitting.md ("Beyond one lobe") relates it to render PSNR.

    python3 scripts/lobe-probe.py /work/shared/data/rgl/ilm_l3_37_metallic_rgb.bsdf ilm.npf.exr

Needs numpy and a built `npf` (for `npf eval` on both files).
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def grid_pairs(n_h, n_d, n_p):
    """Direction pairs at the cell centres of (sqrt-mapped theta_h, theta_d, phi_d in [0, pi))."""
    u = (np.arange(n_h) + 0.5) / n_h
    th, td, pd = np.meshgrid(np.pi / 2 * u ** 2, np.pi / 2 * (np.arange(n_d) + 0.5) / n_d,
                             np.pi * (np.arange(n_p) + 0.5) / n_p, indexing="ij")
    d = np.stack([np.sin(td) * np.cos(pd), np.sin(td) * np.sin(pd), np.cos(td)], -1)
    c, s = np.cos(th), np.sin(th)
    wi = np.stack([c * d[..., 0] + s * d[..., 2], d[..., 1], -s * d[..., 0] + c * d[..., 2]], -1)
    h = np.stack([s, np.zeros_like(s), c], -1)
    wo = 2 * (wi * h).sum(-1, keepdims=True) * h - wi
    volume = np.cos(td) * np.sin(th) * np.sin(td) * u[:, None, None]  # the volume form, constants dropped
    return wi.reshape(-1, 3), wo.reshape(-1, 3), volume.reshape(-1), th[:, 0, 0]


def evaluate(npf, material, pairs_path):
    out = subprocess.run([npf, "eval", material, "--dirs", pairs_path], check=True, capture_output=True, text=True)
    rows = [line.split() for line in out.stdout.splitlines() if line and not line.startswith("#")]
    return np.maximum(np.array(rows, dtype=float), 0.0)


class Probe:
    def __init__(self, wi, wo, volume, theta_h, n_h, n_d, n_p, n_g):
        ci, co = wi[:, 2], wo[:, 2]
        self.keep = (ci > 1e-4) & (co > 1e-4)
        k = self.keep
        self.n_h, self.n_d, self.n_g = n_h, n_d, n_g
        self.ih = np.repeat(np.arange(n_h), n_d * n_p)[k]
        self.id = np.tile(np.repeat(np.arange(n_d), n_p), n_h)[k]
        to_cell = lambda c: np.minimum((np.arccos(np.clip(c, -1, 1)) / (np.pi / 2) * n_g).astype(int), n_g - 1)
        self.gi, self.go = to_cell(ci[k]), to_cell(co[k])
        self.icc = 1.0 / (ci[k] * co[k])
        self.w_base = volume[k] * (ci[k] * co[k]) ** 2
        self.theta_h = theta_h

    def objective(self, y, model):
        w = self.w_base / (y + 0.01)
        return float((w * (model - y) ** 2).sum() / (w * y ** 2).sum())

    def fit(self, y, lobes, sweeps):
        w = self.w_base / (y + 0.01)
        bc = np.bincount
        D = [np.exp(-(self.theta_h / (0.05 * 6 ** k)) ** 2) + 1e-3 for k in range(lobes)]  # sharp to broad
        F = [np.ones(self.n_d) for _ in range(lobes)]
        G = [np.ones(self.n_g) for _ in range(lobes)]
        lobe = lambda k: D[k][self.ih] * F[k][self.id] * G[k][self.gi] * G[k][self.go] * self.icc
        rho_d = 0.0
        for _ in range(sweeps):
            for k in range(lobes):
                r = y - rho_d - sum(lobe(j) for j in range(lobes) if j != k)
                a = F[k][self.id] * G[k][self.gi] * G[k][self.go] * self.icc
                D[k] = np.maximum(bc(self.ih, w * r * a, self.n_h) / np.maximum(bc(self.ih, w * a * a, self.n_h), 1e-30), 0)
                a = D[k][self.ih] * G[k][self.gi] * G[k][self.go] * self.icc
                F[k] = np.maximum(bc(self.id, w * r * a, self.n_d) / np.maximum(bc(self.id, w * a * a, self.n_d), 1e-30), 0)
                # G appears on both sides: a damped Jacobi step with the other side held.
                ai = D[k][self.ih] * F[k][self.id] * G[k][self.go] * self.icc
                ao = D[k][self.ih] * F[k][self.id] * G[k][self.gi] * self.icc
                num = bc(self.gi, w * r * ai, self.n_g) + bc(self.go, w * r * ao, self.n_g)
                den = bc(self.gi, w * ai * ai, self.n_g) + bc(self.go, w * ao * ao, self.n_g)
                G[k] = 0.5 * G[k] + 0.5 * np.maximum(num / np.maximum(den, 1e-30), 0)
                s = F[k].max() or 1.0
                F[k] /= s
                D[k] *= s
                s = G[k].max() or 1.0
                G[k] /= s
                D[k] *= s * s
            rho_d = max(0.0, float((w * (y - sum(lobe(j) for j in range(lobes)))).sum() / w.sum()))
        return rho_d + sum(lobe(j) for j in range(lobes))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("source", help="the measured material (e.g. an isotropic RGL .bsdf)")
    ap.add_argument("conversion", help="its npf conversion (.exr), for the one-lobe reference figure")
    ap.add_argument("--npf", default=os.path.join(ROOT, "build", "tools", "npf", "npf"))
    ap.add_argument("--lobes", default="1,2,3")
    ap.add_argument("--grid", default="60,60,24", help="theta_h, theta_d, phi_d cells (G gets theta_h's count)")
    ap.add_argument("--sweeps", type=int, default=150)
    args = ap.parse_args()
    n_h, n_d, n_p = (int(v) for v in args.grid.split(","))
    wi, wo, volume, theta_h = grid_pairs(n_h, n_d, n_p)
    with tempfile.TemporaryDirectory() as tmp:
        pairs = os.path.join(tmp, "pairs.txt")
        np.savetxt(pairs, np.hstack([wi, wo]), fmt="%.9f")
        data = evaluate(args.npf, args.source, pairs)
        conversion = evaluate(args.npf, args.conversion, pairs)
    probe = Probe(wi, wo, volume, theta_h, n_h, n_d, n_p, n_h)
    channels = range(data.shape[1])
    name = os.path.basename(args.source)
    ref = np.mean([probe.objective(data[probe.keep, c], conversion[probe.keep, c]) for c in channels])
    print("| %s | npf convert (1 lobe) | %.4g |" % (name, ref))
    for lobes in (int(v) for v in args.lobes.split(",")):
        e = np.mean([probe.objective(data[probe.keep, c], probe.fit(data[probe.keep, c], lobes, args.sweeps))
                     for c in channels])
        print("| %s | probe, %d lobe%s | %.4g |" % (name, lobes, "" if lobes == 1 else "s", e), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
