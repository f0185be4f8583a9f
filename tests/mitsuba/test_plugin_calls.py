"""The npf Mitsuba plugin's calls are npf's (opt-in: needs `pip install mitsuba`; ctest
`mitsuba.plugin_calls`, label mitsuba): eval, pdf and sample through Mitsuba give what the npf
package gives for the same directions, random numbers and hero wavelengths, in an RGB and a
spectral LLVM variant; mismatched files and variants are refused with npf.Error.

Each variant runs in a process of its own (Mitsuba's variant is process-wide).
"""
import os
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
NPF = os.environ.get("NPF_EXECUTABLE", str(REPO / "build" / "tools" / "npf" / "npf"))

CHECK = r'''
import sys, numpy as np, drjit as dr, mitsuba as mi
mi.set_variant(sys.argv[1])
import npf, npf.mitsuba
npf.mitsuba.register()
path, other = sys.argv[2], sys.argv[3]
bsdf = mi.load_dict({"type": "npf", "filename": path})
m = npf.open(path)
rng = np.random.default_rng(3)
n = 2000
def hemisphere(k):
    a, b = rng.random(k), rng.random(k); s = np.sqrt(a)
    return np.stack([s * np.cos(2 * np.pi * b), s * np.sin(2 * np.pi * b), np.sqrt(1 - a)], 1).astype(np.float32)
wi, wo, u = hemisphere(n), hemisphere(n), rng.random((n, 2)).astype(np.float32)
si = dr.zeros(mi.SurfaceInteraction3f, n)
si.wi = mi.Vector3f(wi.T)
hero = None
if mi.is_spectral:
    hero = (400 + 300 * rng.random((n, 4))).astype(np.float32)
    si.wavelengths = mi.Spectrum(hero.T)
ctx = mi.BSDFContext()
value = np.array(bsdf.eval(ctx, si, mi.Vector3f(wo.T))).T
np.testing.assert_allclose(value, m.eval(wi, wo, wavelengths=hero, cos=True), rtol=1e-6, atol=0)
np.testing.assert_allclose(np.array(bsdf.pdf(ctx, si, mi.Vector3f(wo.T))), m.pdf(wi, wo), rtol=1e-6, atol=0)
bs, weight = bsdf.sample(ctx, si, mi.Float(np.zeros(n, np.float32)), mi.Point2f(u.T))
wo2, pdf2, weight2 = m.sample(wi, u, wavelengths=hero)
np.testing.assert_allclose(np.array(bs.wo).T, wo2, rtol=0, atol=1e-7)
np.testing.assert_allclose(np.array(bs.pdf), pdf2, rtol=1e-6, atol=0)
np.testing.assert_allclose(np.array(weight).T, weight2, rtol=1e-6, atol=0)
try:
    mi.load_dict({"type": "npf", "filename": other})
except Exception as e:
    assert "variant" in str(e), e
else:
    raise AssertionError("a file of the other kind was accepted in " + sys.argv[1])
print("ok")
'''


@pytest.fixture(scope="module")
def textures(tmp_path_factory):
    try:  # an opt-in test: asked for, it fails without Mitsuba rather than skipping
        import mitsuba  # noqa: F401
    except ImportError as e:
        pytest.fail("needs the Python package mitsuba (pip install mitsuba): {}".format(e), pytrace=False)
    folder = tmp_path_factory.mktemp("plugin")
    rgb, spectral = folder / "ilm.exr", folder / "copper.exr"
    fast = ["--preset", "preview", "--error-pairs", "0", "--no-predict", "--quiet"]
    subprocess.run([NPF, "convert", REPO / "data" / "materials" / "ilm_l3_37_metallic_rgb.bsdf", "-o", rgb, *fast],
                   check=True, capture_output=True)
    subprocess.run([NPF, "convert", REPO / "configs" / "materials" / "brushed_copper.yaml", "-o", spectral, *fast,
                    "--wavelengths", "400:700:8", "--grid", "16,8,16,32", "--g-grid", "16,8"], check=True,
                   capture_output=True)
    return rgb, spectral


@pytest.mark.parametrize("variant", ["llvm_ad_rgb", "llvm_ad_spectral"])
def test_plugin_calls_are_npfs(textures, variant):
    rgb, spectral = textures
    path, other = (rgb, spectral) if variant.endswith("rgb") else (spectral, rgb)
    done = subprocess.run([sys.executable, "-c", CHECK, variant, str(path), str(other)], capture_output=True, text=True)
    assert done.returncode == 0 and done.stdout.strip().endswith("ok"), done.stdout + done.stderr
