"""The Mitsuba 3 BSDF plugin ``npf``: an NPF factor texture as a Mitsuba BSDF (docs/mitsuba.md)::

    import mitsuba as mi
    import npf.mitsuba
    npf.mitsuba.set_variant("llvm_ad_rgb")  # mi.set_variant, after checking that Dr.Jit finds an LLVM
    npf.mitsuba.register()                  # after the variant is set
    bsdf = mi.load_dict({"type": "npf", "filename": "ilm.exr"})

``npf`` evaluates, samples and gives the pdf of npf's model (docs/format.md) in Dr.Jit operations
over the file's tables (npf's reader hands them over: ``npf.Material.factor_tables``), so it is
traced like Mitsuba's own plugins: Mitsuba's default (symbolic) mode, the scalar, LLVM and CUDA
variants, RGB files in RGB variants and spectral files in spectral ones (the four hero
wavelengths of each path are npf's per-pair wavelengths). Its numbers are npf's (the same
interpolation, clamps and axis maps as npf_model.h and npf_closure.h, in single precision), and
its sampler is npf's: the same alias table over D's cells, the same mixture with cosine
sampling, so the same directions for the same random numbers.

Conventions: Mitsuba's ``si.wi`` is npf's ``wi`` (the conditioned, camera-side direction) and
the plugin's ``wo`` npf's ``wo``; both in the shading frame (z the normal, x the tangent: the
``dpdu`` direction of the mesh, which anisotropic materials need). ``eval`` returns
f_r cos(theta_o), ``sample`` the weight f_r cos(theta_o) / pdf, as Mitsuba's BSDFs do, and uses
``sample2`` for both the choice of strategy and the direction (npf's closure does);
``sample1`` is unused. One-sided, reflection only. File names go through Mitsuba's file
resolver (a scene names its material relative to itself).

Other sources npf opens (RGL ``.bsdf``, MERL, ...) have no tables: ``register_numpy()`` registers
``npf_numpy``, the fallback that calls npf's batched numpy functions for any source; it needs
wavefront execution, so it turns Dr.Jit's symbolic loops and calls off for the whole process.
"""

import ctypes.util as _ctypes_util
import glob as _glob
import os as _os

import numpy as _np

import npf as _npf
from npf._traced import TracedModel, _nonzero

# Debian 12's default LLVM (15) aborts inside Dr.Jit's code generator; 19 works (docs/mitsuba.md).
_LLVM_FIX = "apt-get install libllvm19 (Debian 12), or set DRJIT_LIBLLVM_PATH to a libLLVM.so of version 16 or later"
_LLVM_FOLDERS = ["/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu", "/usr/lib64", "/usr/lib", "/usr/local/lib"]


def _llvm_version(path):
    """The major version in a libLLVM file name (libLLVM-15.so, libLLVM.so.19.1), or 0."""
    name = _os.path.basename(path)
    for part in name.replace("libLLVM", "").replace("-", ".").split("."):
        if part.isdigit():
            return int(part)
    return 0


def find_llvm():
    """The libLLVM Dr.Jit's LLVM variants will use: DRJIT_LIBLLVM_PATH when set, else the newest
    in the usual folders. Returns (path, major version); (None, 0) when there is none."""
    given = _os.environ.get("DRJIT_LIBLLVM_PATH")
    if given:
        return given, _llvm_version(_os.path.realpath(given)) or _llvm_version(given)
    found = [p for folder in _LLVM_FOLDERS for p in _glob.glob(_os.path.join(folder, "libLLVM*.so*"))]
    if not found and _ctypes_util.find_library("LLVM"):
        found = [_ctypes_util.find_library("LLVM")]
    if not found:
        return None, 0
    best = max(found, key=lambda p: _llvm_version(p))
    return best, _llvm_version(best)


def check_llvm():
    """Raises npf.Error in one line when Dr.Jit's LLVM backend would not run here: no libLLVM, or
    only one older than 16 (LLVM 15 aborts the process inside Dr.Jit with a long dump). Sets
    DRJIT_LIBLLVM_PATH to the one found when it was not set (Dr.Jit reads it when it starts)."""
    path, version = find_llvm()
    if "DRJIT_LIBLLVM_PATH" in _os.environ:
        if _os.sep in path and not _os.path.exists(path):  # a bare name is the loader's to find
            raise _npf._error("DRJIT_LIBLLVM_PATH={}".format(path), "no such file; " + _LLVM_FIX)
        if 0 < version < 16:
            raise _npf._error("DRJIT_LIBLLVM_PATH={}".format(path), "LLVM {} aborts Dr.Jit; {}".format(version, _LLVM_FIX))
        return path
    if path is None:
        raise _npf._error("Dr.Jit's LLVM variants", "no libLLVM found; " + _LLVM_FIX)
    if 0 < version < 16:
        raise _npf._error(path, "LLVM {} aborts Dr.Jit's LLVM variants; {}".format(version, _LLVM_FIX))
    _os.environ["DRJIT_LIBLLVM_PATH"] = path
    return path


def set_variant(variant):
    """mitsuba.set_variant(variant), after check_llvm() for an LLVM variant."""
    import mitsuba as mi
    if variant.startswith("llvm"):
        check_llvm()
    mi.set_variant(variant)


def _resolve(filename):
    """`filename` through the current thread's file resolver (the scene's folder first, as
    Mitsuba's own plugins resolve theirs); npf.Error naming it when no such file exists."""
    import mitsuba as mi
    resolved = str(mi.Thread.thread().file_resolver().resolve(filename))
    if not _os.path.exists(resolved):
        raise _npf._error(filename, "no such file (looked up through Mitsuba's file resolver: the scene's folder, then the working directory)")
    return resolved


def _opened(props, spectral, needs):
    """The plugin's material: `filename` through the scene's resolver, opened by npf's reader and
    checked against the variant. Returns (path, material, Mitsuba flags)."""
    import mitsuba as mi
    if not props.has_property("filename"):
        raise _npf._error("npf plugin", "needs a 'filename' ({})".format(needs))
    filename = _resolve(str(props["filename"]))
    material = _npf.open(filename)
    _check_variant(material, filename, spectral)
    flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
    if not material.info["isotropic"]:
        flags = flags | mi.BSDFFlags.Anisotropic
    return filename, material, flags


def _check_variant(material, filename, spectral):
    import mitsuba as mi
    if material.is_rgb and spectral:
        raise _npf._error(filename, "holds RGB data; render it with an RGB variant (not {})".format(mi.variant()))
    if not material.is_rgb and not spectral:
        raise _npf._error(filename, "holds spectral data; render it with a spectral variant (not {})".format(mi.variant()))


def register(name="npf"):
    """Registers the traced plugin under ``name`` for the current Mitsuba variant (any mode)."""
    import drjit as dr
    import mitsuba as mi

    if mi.is_polarized:
        raise _npf._error(mi.variant(), "npf's plugin is unpolarized; use an rgb or spectral variant")
    spectral = mi.is_spectral

    class NpfBsdf(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.filename, self.material, flags = _opened(props, spectral, "an NPF factor texture: npf convert writes one")
            if not self.material.info["batched"]:
                raise _npf._error(self.filename, "is not an NPF factor texture (npf convert makes one; npf.mitsuba.register_numpy() shades any source npf opens)")
            self.model = TracedModel(self.material)
            self.m_components = [flags]
            self.m_flags = flags

        def _spectrum(self, values):
            return mi.Spectrum(*values) if len(values) > 1 else mi.Spectrum(values[0])

        def _wavelengths(self, si):
            return [si.wavelengths[k] for k in range(len(si.wavelengths))] if spectral else None

        def eval(self, ctx, si, wo, active=True):
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection, 0):
                return mi.Spectrum(0.0)
            at = self.model.prepare(si.wi, wo)
            value = self._spectrum(self.model.values(at, self._wavelengths(si)))
            return dr.select(active & at["domain"], value, 0.0)

        def pdf(self, ctx, si, wo, active=True):
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection, 0):
                return mi.Float(0.0)
            return dr.select(active, self.model.pdf(si.wi, wo), 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            bs = mi.BSDFSample3f()
            if not ctx.is_enabled(mi.BSDFFlags.GlossyReflection, 0):
                return bs, mi.Spectrum(0.0)
            wo = self.model.draw(si.wi, sample2.x, sample2.y)
            pdf = self.model.pdf(si.wi, wo)
            ok = active & (si.wi.z > 0.0) & (wo.z > 0.0) & (pdf > 0.0)
            at = self.model.prepare(si.wi, wo)
            values = self.model.values(at, self._wavelengths(si))
            weight = self._spectrum([self.model._finite(v / _nonzero(dr, pdf)) for v in values])
            bs.wo = wo
            bs.pdf = dr.select(ok, pdf, 0.0)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            return bs, dr.select(ok, weight, 0.0)

        def traverse(self, callback):
            pass

        def to_string(self):
            return "NpfBsdf[filename={!r}, {}]".format(self.filename, self.material)

    mi.register_bsdf(name, lambda props: NpfBsdf(props))
    return NpfBsdf


def _rows(vector):
    """A Dr.Jit 3-vector (or 2-vector) of N lanes as an (N, k) float64 numpy array."""
    a = _np.array(vector, dtype=_np.float64)
    return _np.ascontiguousarray(a.T if a.ndim == 2 else a[None, :])


def register_numpy(name="npf_numpy"):
    """Registers the fallback under ``name``: any source npf opens, shaded by npf's batched numpy
    calls. It needs wavefront execution: turns off Dr.Jit's symbolic loops and calls for the
    whole process (slower, and far more memory, than the traced plugin)."""
    import drjit as dr
    import mitsuba as mi

    dr.set_flag(dr.JitFlag.SymbolicLoops, False)
    dr.set_flag(dr.JitFlag.SymbolicCalls, False)
    spectral = mi.is_spectral
    if mi.is_polarized:
        raise _npf._error(mi.variant(), "npf's plugin is unpolarized; use an rgb or spectral variant")

    class NpfNumpyBsdf(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.filename, self.material, flags = _opened(props, spectral, "a material npf opens, e.g. a factor texture")
            self.m_components = [flags]
            self.m_flags = flags

        def _wavelengths(self, si, n):
            if not spectral:
                return None
            w = _np.array(si.wavelengths, dtype=_np.float64)  # (4, N) or (4,)
            return _np.ascontiguousarray(_np.broadcast_to(w.T if w.ndim == 2 else w[None, :], (n, w.shape[0])))

        def _spectrum(self, values):
            return mi.Spectrum(_np.ascontiguousarray(values.T.astype(_np.float32)))

        def _enabled(self, ctx):
            return ctx.is_enabled(mi.BSDFFlags.GlossyReflection, 0)

        def sample(self, ctx, si, sample1, sample2, active=True):
            wi, u = _rows(si.wi), _rows(sample2)
            n = max(len(wi), len(u))
            wo, pdf, weight = self.material.sample(wi, u, wavelengths=self._wavelengths(si, n))
            if not self._enabled(ctx):
                pdf[:] = 0.0
            bs = dr.zeros(mi.BSDFSample3f, n)
            bs.wo = mi.Vector3f(_np.ascontiguousarray(wo.T.astype(_np.float32)))
            bs.pdf = mi.Float(pdf.astype(_np.float32))
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            ok = active & (bs.pdf > 0.0)
            return bs, dr.select(ok, self._spectrum(weight), 0.0)

        def eval(self, ctx, si, wo, active=True):
            wi, wo = _rows(si.wi), _rows(wo)
            values = self.material.eval(wi, wo, wavelengths=self._wavelengths(si, max(len(wi), len(wo))), cos=True)
            if not self._enabled(ctx):
                values[:] = 0.0
            return dr.select(active, self._spectrum(values), 0.0)

        def pdf(self, ctx, si, wo, active=True):
            p = self.material.pdf(_rows(si.wi), _rows(wo))
            if not self._enabled(ctx):
                p[:] = 0.0
            return dr.select(active, mi.Float(p.astype(_np.float32)), 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def traverse(self, callback):
            pass

        def to_string(self):
            return "NpfNumpyBsdf[filename={!r}, {}]".format(self.filename, self.material)

    mi.register_bsdf(name, lambda props: NpfNumpyBsdf(props))
    return NpfNumpyBsdf
