"""The npf Mitsuba plugin's calls are npf's (opt-in: needs `pip install mitsuba`; ctest
`mitsuba.plugin_calls`, label mitsuba).

- The traced plugin `npf` (Dr.Jit operations, Mitsuba's default symbolic mode): eval, pdf and
  sample through Mitsuba against the npf package for the same directions, random numbers and
  hero wavelengths, within single precision (relative RMS 1e-4; the package computes in double),
  in the scalar, LLVM and CUDA variants, RGB and spectral (CUDA skipped where Dr.Jit finds no
  GPU). Its draws are npf's: the same directions for the same numbers.
- The numpy fallback `npf_numpy`: the package's numbers exactly (1e-6), on a factor texture and a
  raw RGL file.
- Mismatched files and variants, and a missing file, are refused with npf.Error in one line; a
  scene naming its material relative to itself renders from another folder; an LLVM Dr.Jit
  cannot use is one line (exit status 1), not an abort.

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
import npf, npf.mitsuba
variant, kind, path, other = sys.argv[1:5]
npf.mitsuba.set_variant(variant)
if kind == "npf":
    npf.mitsuba.register()
    assert dr.flag(dr.JitFlag.SymbolicLoops) and dr.flag(dr.JitFlag.SymbolicCalls)  # no mode switch
else:
    npf.mitsuba.register(); npf.mitsuba.register_numpy()
bsdf = mi.load_dict({"type": kind, "filename": path})
m = npf.open(path)
scalar = variant.startswith("scalar")
rng = np.random.default_rng(3)
n = 300 if scalar else 4000
def hemisphere(k):
    a, b = rng.random(k), rng.random(k); s = np.sqrt(a)
    return np.stack([s * np.cos(2 * np.pi * b), s * np.sin(2 * np.pi * b), np.sqrt(1 - a)], 1).astype(np.float32)
wi, wo, u = hemisphere(n), hemisphere(n), rng.random((n, 2)).astype(np.float32)
hero = (380 + 400 * rng.random((n, 4))).astype(np.float32) if mi.is_spectral else None
ctx = mi.BSDFContext()
def calls(rows):
    """eval, pdf, sample's (wo, pdf, weight) of pairs `rows` as (k, ...) arrays."""
    si = dr.zeros(mi.SurfaceInteraction3f, 1 if scalar else len(rows))
    cols = lambda a: mi.Vector3f(*a[rows[0]]) if scalar else mi.Vector3f(a[rows].T)
    si.wi = cols(wi)
    if hero is not None:
        si.wavelengths = mi.Spectrum(*hero[rows[0]]) if scalar else mi.Spectrum(hero[rows].T)
    uu = mi.Point2f(*u[rows[0]]) if scalar else mi.Point2f(u[rows].T)
    bs, weight = bsdf.sample(ctx, si, 0.5 if scalar else mi.Float(np.full(len(rows), 0.5, np.float32)), uu)
    out = [bsdf.eval(ctx, si, cols(wo)), bsdf.pdf(ctx, si, cols(wo)), bs.wo, bs.pdf, weight]
    return [np.array(a, dtype=np.float64).reshape(1, -1) if scalar else np.atleast_2d(np.array(a, dtype=np.float64)).T for a in out]
if scalar:
    parts = [calls([i]) for i in range(n)]
    value, pdf, swo, spdf, sweight = [np.concatenate([p[k] for p in parts]) for k in range(5)]
else:
    value, pdf, swo, spdf, sweight = calls(list(range(n)))
pdf, spdf = pdf[:, 0], spdf[:, 0]
ref = m.eval(wi, wo, wavelengths=hero, cos=True)
ref_wo, ref_pdf, ref_weight = m.sample(wi, u, wavelengths=hero)
def rel_rms(a, b):
    return np.sqrt(np.mean((a - b) ** 2)) / max(np.sqrt(np.mean(b ** 2)), 1e-30)
tol = 1e-4 if kind == "npf" else 1e-6
assert rel_rms(value, ref) < tol, ("eval", rel_rms(value, ref))
assert rel_rms(pdf, m.pdf(wi, wo)) < tol, ("pdf", rel_rms(pdf, m.pdf(wi, wo)))
drawn, ref_drawn = spdf > 0, ref_pdf > 0
# The same draws: a pair whose reflected direction lands within rounding of the horizon may go
# either way in single precision.
assert np.sum(drawn != ref_drawn) <= max(1, n // 1000), ("draws", np.sum(drawn != ref_drawn))
both = drawn & ref_drawn
assert np.max(np.abs(swo[both] - ref_wo[both])) < 1e-4, ("directions", np.max(np.abs(swo[both] - ref_wo[both])))
# The pdf is piecewise constant over D's cells: a draw within rounding of a cell's edge may take
# the neighbour's density in single precision (2 of 18,109 draws on the brushed copper).
close = np.abs(spdf - ref_pdf) <= 1e-3 * ref_pdf
assert np.sum(both & ~close) <= max(2, n // 1000), ("sample pdf", np.sum(both & ~close))
same = both & close
assert rel_rms(spdf[same], ref_pdf[same]) < tol, ("sample pdf", rel_rms(spdf[same], ref_pdf[same]))
assert rel_rms(sweight[same], ref_weight[same]) < 10 * tol, ("weight", rel_rms(sweight[same], ref_weight[same]))
assert np.all(sweight[~drawn] == 0)
try:
    mi.load_dict({"type": kind, "filename": other})
except Exception as e:
    assert "variant" in str(e), e
else:
    raise AssertionError("a file of the other kind was accepted in " + variant)
try:
    mi.load_dict({"type": kind, "filename": "no_such_material.exr"})
except Exception as e:
    assert "no_such_material.exr: no such file" in str(e), e
else:
    raise AssertionError("a missing file was accepted")
print("ok")
'''


def _has_cuda():
    probe = "import drjit as dr, sys; sys.exit(0 if dr.has_backend(dr.JitBackend.CUDA) else 1)"
    return subprocess.run([sys.executable, "-c", probe], capture_output=True).returncode == 0


def _run(*args, cwd=None, env=None):
    env = dict(os.environ if env is None else env)  # PYTHONPATH absolute: some runs change folder
    env["PYTHONPATH"] = os.pathsep.join(os.path.abspath(p) for p in env.get("PYTHONPATH", "").split(os.pathsep) if p)
    return subprocess.run([sys.executable, *map(str, args)], capture_output=True, text=True, cwd=cwd, env=env)


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


VARIANTS = ["scalar_rgb", "scalar_spectral", "llvm_ad_rgb", "llvm_ad_spectral",
            pytest.param("cuda_ad_rgb", marks=pytest.mark.cuda), pytest.param("cuda_ad_spectral", marks=pytest.mark.cuda)]


@pytest.mark.parametrize("variant", VARIANTS)
def test_traced_plugin_calls_are_npfs(textures, variant):
    if variant.startswith("cuda") and not _has_cuda():
        pytest.skip("no CUDA device here (Dr.Jit finds no GPU)")
    rgb, spectral = textures
    path, other = (rgb, spectral) if variant.endswith("rgb") else (spectral, rgb)
    done = _run("-c", CHECK, variant, "npf", path, other)
    assert done.returncode == 0 and done.stdout.strip().endswith("ok"), done.stdout + done.stderr


@pytest.mark.parametrize("source", ["texture", "raw"])
def test_numpy_fallback_is_the_package(textures, source):
    rgb, spectral = textures
    path = rgb if source == "texture" else REPO / "data" / "materials" / "ilm_l3_37_metallic_rgb.bsdf"
    done = _run("-c", CHECK, "llvm_ad_rgb", "npf_numpy", path, spectral)
    assert done.returncode == 0 and done.stdout.strip().endswith("ok"), done.stdout + done.stderr


def test_scene_relative_material_renders_from_another_folder(textures, tmp_path):
    rgb, _ = textures
    scene_folder, elsewhere = tmp_path / "scene", tmp_path / "elsewhere"
    scene_folder.mkdir()
    elsewhere.mkdir()
    (scene_folder / "materials").mkdir()
    (scene_folder / "materials" / "ilm.exr").write_bytes(rgb.read_bytes())
    (scene_folder / "scene.xml").write_text(
        '<scene version="3.0.0"><integrator type="path"/><sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/>'
        '<integer name="height" value="8"/></film></sensor><emitter type="constant"/>'
        '<shape type="sphere"><transform name="to_world"><translate z="5"/></transform>'
        '<bsdf type="npf"><string name="filename" value="materials/ilm.exr"/></bsdf></shape></scene>')
    render = ("import sys, numpy as np, mitsuba as mi, npf.mitsuba\n"
              "npf.mitsuba.set_variant('llvm_ad_rgb'); npf.mitsuba.register()\n"
              "image = np.array(mi.render(mi.load_file(sys.argv[1]), spp=4))\n"
              "assert image.shape == (8, 8, 3) and np.isfinite(image).all() and image.max() > 0\nprint('ok')\n")
    done = _run("-c", render, scene_folder / "scene.xml", cwd=elsewhere)
    assert done.returncode == 0 and done.stdout.strip().endswith("ok"), done.stdout + done.stderr


def test_unusable_llvm_is_one_line(tmp_path):
    old = Path("/usr/lib/x86_64-linux-gnu/libLLVM-15.so")
    env = dict(os.environ)
    for given, problem in ((tmp_path / "libLLVM-19.so", "no such file"), (old, "LLVM 15 aborts Dr.Jit")):
        if problem.startswith("LLVM 15") and not old.exists():
            continue
        env["DRJIT_LIBLLVM_PATH"] = str(given)
        done = _run("-c", "import npf.mitsuba; npf.mitsuba.set_variant('llvm_ad_rgb')", env=env)
        last = done.stderr.strip().splitlines()[-1]
        assert done.returncode == 1 and problem in last and "libllvm19" in last, done.stderr
