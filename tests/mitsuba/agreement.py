#!/usr/bin/env python3
"""How closely the traced Mitsuba plugin (npf.mitsuba) gives npf's numbers (docs/mitsuba.md,
"Agreement with npf"): eval, pdf and sample through Mitsuba against npf.open(f) on the pairs of
DIRS (the RGL reference pairs: wi then wo per line) and random ones, with random hero wavelengths
in spectral variants. Prints relative RMS and largest differences; a figure-maker, not a test
(tests/mitsuba/test_plugin_calls.py holds the thresholds).

usage: agreement.py VARIANT FACTORS.exr [DIRS]    (PYTHONPATH=build/python)
"""
import os, sys, numpy as np, drjit as dr, mitsuba as mi
import npf, npf.mitsuba
variant, path = sys.argv[1], sys.argv[2]
npf.mitsuba.set_variant(variant)
npf.mitsuba.register()
m = npf.open(path)
bsdf = mi.load_dict({"type": "npf", "filename": path})
rng = np.random.default_rng(3)
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
d = np.loadtxt(sys.argv[3] if len(sys.argv) > 3 else os.path.join(REPO, "..", "shared", "data", "rgl", "reference", "dirs.txt"))
def hemisphere(k):
    a, b = rng.random(k), rng.random(k); s = np.sqrt(a)
    return np.stack([s * np.cos(2 * np.pi * b), s * np.sin(2 * np.pi * b), np.sqrt(1 - a)], 1)
n = 20000 if not variant.startswith("scalar") else 300
wi = np.concatenate([d[:, :3], hemisphere(n)]); wo = np.concatenate([d[:, 3:], hemisphere(n)])
wi = (wi / np.linalg.norm(wi, axis=1, keepdims=True)).astype(np.float32).astype(np.float64)
wo = (wo / np.linalg.norm(wo, axis=1, keepdims=True)).astype(np.float32).astype(np.float64)
u = rng.random((len(wi), 2)).astype(np.float32)
N = len(wi)
hero = (380 + 400 * rng.random((N, 4))).astype(np.float32) if mi.is_spectral else None
ctx = mi.BSDFContext()
def call(i0, i1):
    si = dr.zeros(mi.SurfaceInteraction3f, i1 - i0) if not variant.startswith("scalar") else mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wi[i0:i1].T.astype(np.float32)) if i1 - i0 > 1 or not variant.startswith("scalar") else mi.Vector3f(*wi[i0])
    if hero is not None:
        si.wavelengths = mi.Spectrum(hero[i0:i1].T) if not variant.startswith("scalar") else mi.Spectrum(*hero[i0])
    w = mi.Vector3f(wo[i0:i1].T.astype(np.float32)) if not variant.startswith("scalar") else mi.Vector3f(*wo[i0])
    uu = mi.Point2f(u[i0:i1].T) if not variant.startswith("scalar") else mi.Point2f(*u[i0])
    v, p = bsdf.eval_pdf(ctx, si, w)
    bs, wt = bsdf.sample(ctx, si, 0.5, uu)
    return np.array(v).reshape(-1, 1 if variant.startswith("scalar") else i1 - i0).T if False else np.atleast_2d(np.array(v).T), np.atleast_1d(np.array(p)), np.atleast_2d(np.array(bs.wo).T), np.atleast_1d(np.array(bs.pdf)), np.atleast_2d(np.array(wt).T)
if variant.startswith("scalar"):
    rows = [call(i, i + 1) for i in range(N)]
    v, p, swo, spdf, swt = [np.concatenate([r[k] for r in rows]) for k in range(5)]
else:
    v, p, swo, spdf, swt = call(0, N)
ref = m.eval(wi, wo, wavelengths=hero, cos=True); pref = m.pdf(wi, wo)
sw, sp, sweight = m.sample(wi, u.astype(np.float64), wavelengths=hero)
def rel(a, b):
    scale = np.sqrt(np.mean(b ** 2)) + 1e-30
    return np.sqrt(np.mean((a - b) ** 2)) / scale, np.max(np.abs(a - b)) / scale
print(variant, path, N, "pairs")
print("eval  rel RMS %.2e  max %.2e" % rel(v, ref))
print("eval  dirs.txt only rel RMS %.2e" % rel(v[:500], ref[:500])[0])
print("pdf   rel RMS %.2e  max %.2e  mismatched(>1e-3) %d" % (*rel(p, pref), np.sum(np.abs(p - pref) > 1e-3 * np.maximum(pref, 1e-3))))
ok = sp > 0
print("sample: draws ok %d/%d (npf %d), direction max diff %.2e, pdf rel RMS %.2e, weight rel RMS %.2e" % (
    np.sum(spdf > 0), N, np.sum(ok), np.max(np.abs(swo[ok] - sw[ok])), rel(spdf, sp)[0], rel(swt, sweight)[0]))
both = (spdf > 0) & ok
r = np.abs(spdf[both] - sp[both]) / sp[both]
print("sample pdf: pairs off by >1e-3: %d of %d; max %.2e" % (np.sum(r > 1e-3), np.sum(both), r.max()))
