"""The Mitsuba 3 BSDF plugin ``npf``: any material npf opens (a factor texture above all) as a
Mitsuba BSDF, evaluated and sampled by npf's batched calls (docs/mitsuba.md)::

    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")          # or llvm_ad_spectral for a spectral file
    import npf.mitsuba
    npf.mitsuba.register()                 # after set_variant
    bsdf = mi.load_dict({"type": "npf", "filename": "ilm.exr"})

Conventions: Mitsuba's ``si.wi`` is npf's ``wi`` (the conditioned, camera-side direction) and the
plugin's ``wo`` npf's ``wo``; both in the shading frame (z the normal, x the tangent: the
``dpdu`` direction of the mesh, which anisotropic materials need). ``eval`` returns
f_r cos(theta_o), ``sample`` the weight f_r cos(theta_o) / pdf, as Mitsuba's BSDFs do. RGB files
render in RGB variants, spectral files in spectral variants (four hero wavelengths per path).

A Python BSDF needs wavefront (not symbolic) execution: register() turns off Dr.Jit's symbolic
loops and calls. The LLVM variants need an LLVM Dr.Jit can use (Debian 12: libllvm19 and
DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1); the scalar variants work too, a
pair per call, far slower.
"""

import numpy as _np

import npf as _npf


def _rows(vector):
    """A Dr.Jit 3-vector (or 2-vector) of N lanes as an (N, k) float64 numpy array."""
    a = _np.array(vector, dtype=_np.float64)
    return _np.ascontiguousarray(a.T if a.ndim == 2 else a[None, :])


def register(name="npf"):
    """Registers the plugin under ``name`` for the current Mitsuba variant."""
    import drjit as dr
    import mitsuba as mi

    dr.set_flag(dr.JitFlag.SymbolicLoops, False)
    dr.set_flag(dr.JitFlag.SymbolicCalls, False)
    spectral = mi.is_spectral
    if mi.is_polarized:
        raise _npf._error(mi.variant(), "npf's plugin is unpolarized; use an rgb or spectral variant")

    class NpfBsdf(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            if not props.has_property("filename"):
                raise _npf._error("npf plugin", "needs a 'filename' (a material npf opens, e.g. a factor texture)")
            self.filename = str(props["filename"])
            self.material = _npf.open(self.filename)
            if self.material.is_rgb and spectral:
                raise _npf._error(self.filename, "holds RGB data; render it with an RGB variant (not {})".format(
                    mi.variant()))
            if not self.material.is_rgb and not spectral:
                raise _npf._error(self.filename, "holds spectral data; render it with a spectral variant (not {})".format(
                    mi.variant()))
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            if not self.material.info["isotropic"]:
                flags = flags | mi.BSDFFlags.Anisotropic
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
            return "NpfBsdf[filename={!r}, {}]".format(self.filename, self.material)

    mi.register_bsdf(name, lambda props: NpfBsdf(props))
    return NpfBsdf
