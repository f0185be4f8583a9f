"""npf: non-parametric factor BRDFs from Python.

Open any material npf reads (RGL ``.bsdf``, MERL ``.binary``, NPF factor texture ``.exr``,
Neural BRDF ``.h5``, analytic recipe ``.yaml``), evaluate, sample and convert it::

    import numpy as np, npf
    report = npf.convert("ilm.bsdf", "ilm.exr", preset="preview")
    m = npf.open("ilm.exr")
    wi = np.array([[0.0, 0.0, 1.0]]); wo = np.array([[0.3, 0.0, 0.95]])
    m.eval(wi, wo)            # (1, 3): f_r in 1/sr, what `npf eval` prints

Conventions (docs/conventions.md): directions in the local frame (z the normal, x the tangent),
both pointing away from the surface, normalised on reading; ``wi`` is the direction a query is
conditioned on (the camera side: Mitsuba's ``si.wi``), ``wo`` the one ``sample`` draws. Values
are f_r in 1/sr (``cos=True``: f_r cos(theta_o)); a pair with a direction at or below the
horizon gives 0. Errors are :class:`npf.Error` (a ``RuntimeError``) with ``.source`` (the file
or setting) and ``.problem``.

Batched calls take whole numpy arrays: a call costs a few microseconds, so pass thousands of
pairs at once, not one. Factor textures shade through the batched closure (AVX2 where the CPU has
it); other sources pair by pair. ``threads=0`` uses every core; the results do not depend on it.
"""

import os as _os

import numpy as _np

from . import _npf
from ._npf import Error, __version__

__all__ = ["Error", "Material", "open", "convert", "edit", "convert_settings", "edit_flags", "MAX_PAIRS", "__version__"]


def _error(source, problem):
    """An npf.Error as the compiled half raises them: "source: problem", with both attributes."""
    e = Error("{}: {}".format(source, problem))
    e.source, e.problem = source, problem
    return e


# The most pairs one call takes: its arrays (directions in and out, values) stay within a few
# GB. More would be allocated whole before anything runs, and past the machine's memory the
# process is killed without a word; pass larger work in chunks.
MAX_PAIRS = 1 << 26


def _numbers(name, a, dtype):
    """`a` as an array of real numbers of `dtype`: ragged lists, objects, strings, booleans and
    complex numbers are npf.Error naming the argument, not a numpy exception or a silent cast."""
    try:
        arr = _np.asarray(a)
    except (ValueError, TypeError) as e:
        raise _error(name, "not an array of numbers ({})".format(str(e).split(".")[0])) from None
    if arr.dtype.kind not in "iuf":
        raise _error(name, "expected real numbers, got an array of {}".format(arr.dtype))
    return arr.astype(dtype, copy=False)


def _threads(threads):
    if isinstance(threads, bool) or not isinstance(threads, (int, _np.integer)) or not 0 <= threads <= 1024:
        raise _error("threads", "expected a whole number in 0..1024 (0: every core), got {!r}".format(threads))
    return int(threads)


def _check_pairs(name, n):
    if n > MAX_PAIRS:
        raise _error(name, "{} pairs in one call; npf takes at most {} (npf.MAX_PAIRS): pass them in chunks".format(n, MAX_PAIRS))


def _path(path):
    """A file name as text: str, bytes or os.PathLike; a NUL byte is refused (the C side would
    read the name up to it, another file)."""
    text = _os.fsdecode(path) if isinstance(path, (bytes, _os.PathLike)) else path
    if not isinstance(text, str):
        raise _error(repr(path), "expected a file name (str, bytes or os.PathLike)")
    if "\0" in text:
        raise _error(repr(text), "a file name with a NUL byte")
    return text


def _directions(name, a):
    a = _numbers(name, a, _np.float64)
    if a.ndim == 1:
        a = a[None, :]
    if a.ndim != 2 or a.shape[1] != 3:
        raise _error(name, "expected an (N, 3) array of directions, got shape {}".format(a.shape))
    return a


def _pair_arrays(wi, wo):
    wi, wo = _directions("wi", wi), _directions("wo", wo)
    _check_pairs("wi, wo", max(wi.shape[0], wo.shape[0]))
    if wi.shape[0] != wo.shape[0]:
        if wi.shape[0] == 1:
            wi = _np.broadcast_to(wi, wo.shape)
        elif wo.shape[0] == 1:
            wo = _np.broadcast_to(wo, wi.shape)
        else:
            raise _error("wi, wo", "{} and {} directions; give as many of each (or one of either)".format(
                wi.shape[0], wo.shape[0]))
    return _np.ascontiguousarray(wi), _np.ascontiguousarray(wo)


def _wavelengths(wavelengths, n):
    """None, (K,) shared by every pair, or (N, K) per pair (hero wavelengths), as float32 rows."""
    if wavelengths is None:
        return None, False
    w = _np.ascontiguousarray(_numbers("wavelengths", wavelengths, _np.float32))
    if w.ndim == 1:
        return w[None, :], False
    if w.ndim == 2 and w.shape[0] == n:
        return w, True
    raise _error("wavelengths", "expected (K,) or ({}, K) nanometres, got shape {}".format(n, w.shape))


class Material:
    """A material of any source npf reads; immutable, usable from several threads."""

    def __init__(self, path):
        self._m = _npf._Material(_path(path))
        self._info = self._m.info()

    @property
    def path(self):
        return self._info["path"]

    @property
    def info(self):
        """What `npf info` says: format, channels, wavelengths_nm, isotropic, details, ..."""
        return dict(self._info)

    @property
    def channels(self):
        """The stored channels: ['R', 'G', 'B'] or the wavelengths' names ('450.0' nm)."""
        return list(self._info["channel_names"])

    @property
    def wavelengths(self):
        """The stored wavelengths (nm) as an array; empty for RGB files."""
        return _np.asarray(self._info["wavelengths_nm"], dtype=_np.float64)

    @property
    def is_rgb(self):
        return self._info["channels"] == "rgb"

    def eval(self, wi, wo, wavelengths=None, cos=False, threads=0):
        """f_r(wi, wo) in 1/sr as an (N, channels) float64 array: every stored channel, or at
        ``wavelengths`` (nm; (K,) for every pair or (N, K) per pair, spectral files only)."""
        wi, wo = _pair_arrays(wi, wo)
        nm, per_pair = _wavelengths(wavelengths, wi.shape[0])
        return self._m.eval(wi, wo, nm, per_pair, bool(cos), _threads(threads))

    def pdf(self, wi, wo, threads=0):
        """The density (1/sr) with which :meth:`sample` draws wo given wi, shape (N,)."""
        wi, wo = _pair_arrays(wi, wo)
        return self._m.pdf(wi, wo, _threads(threads))

    def sample(self, wi, u, wavelengths=None, threads=0):
        """Draws wo given wi from uniform numbers u (N, 2) in [0, 1). Returns (wo (N, 3), pdf (N,),
        weight (N, channels)), the weight being f_r cos(theta_o) / pdf; a pair that draws
        nothing has wo 0, pdf 0 and weight 0."""
        wi = _directions("wi", wi)
        u = _numbers("u", u, _np.float64)
        if u.ndim == 1:
            u = u[None, :]
        if u.ndim != 2 or u.shape[1] != 2:
            raise _error("u", "expected an (N, 2) array of uniform numbers, got shape {}".format(u.shape))
        _check_pairs("wi, u", max(wi.shape[0], u.shape[0]))
        wi = _np.ascontiguousarray(wi)
        if wi.shape[0] == 1 and u.shape[0] > 1:
            wi = _np.ascontiguousarray(_np.broadcast_to(wi, (u.shape[0], 3)))
        elif u.shape[0] == 1 and wi.shape[0] > 1:
            u = _np.broadcast_to(u, (wi.shape[0], 2))
        if wi.shape[0] != u.shape[0]:
            raise _error("wi, u", "{} directions and {} samples".format(wi.shape[0], u.shape[0]))
        outside = ~((u >= 0.0) & (u <= 1.0))  # NaN included
        if outside.any():
            i, k = _np.argwhere(outside)[0]
            raise _error("u[{}, {}]".format(i, k), "not a uniform number in [0, 1): {}".format(u[i, k]))
        nm, per_pair = _wavelengths(wavelengths, wi.shape[0])
        return self._m.sample(wi, _np.ascontiguousarray(u), nm, per_pair, _threads(threads))

    def factor_tables(self):
        """A factor texture's tables as npf shades with them (docs/format.md), for renderers that
        evaluate the model themselves (npf.mitsuba): a dict of grid sizes (d_theta, d_phi,
        f_theta, g_theta, g_phi), float32 arrays rho_d, rho_s (C,), F (C, f_theta), D and G as
        {rank, basis (rank, cells), weights (C, rank)}, with a detail layer detail_grid
        (theta_h, theta_d, phi_d) and detail; wavelengths_nm; diffuse_probability; and unless
        that is 1 the half-vector sampler: keep, alias, density (1/sr) per D cell and half_sin2
        (the rows' edges). npf.Error for any other source."""
        return self._m.factor_tables()

    def __repr__(self):
        i = self._info
        kind = "RGB" if i["channels"] == "rgb" else "{} wavelengths".format(len(i["wavelengths_nm"]))
        return "npf.Material({!r}: {}, {}, {})".format(i["path"], i["format"], kind,
                                                       "isotropic" if i["isotropic"] else "anisotropic")


def open(path):  # noqa: A001 (the package's verb, as npf.open(path) in the issue)
    """Opens any material source npf reads; raises npf.Error naming the file when it cannot."""
    return Material(path)


def _setting_text(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return ",".join(_setting_text(v) for v in value)
    if isinstance(value, float):
        return repr(value)
    return str(value)


def convert_settings():
    """The conversion settings ``convert`` takes: the batch configuration's keys (docs/batch.md),
    the same as `npf convert`'s flags with '_' for '-'."""
    return [key for key, _ in _npf.convert_setting_keys()]


def convert(source, output, progress=None, **settings):
    """Fits a material and writes its factor texture, as `npf convert SOURCE -o OUTPUT` does.

    Settings are keywords named as the batch configuration's keys, with the values their flags
    take: ``preset="preview"``, ``wavelengths="380:780:41"``, ``detail="none"``,
    ``error_pairs=0``, ``no_predict=True``, ``grid=(90, 1, 90, 180)``, ``threads=2``. ``progress(fraction)`` is
    called as the work proceeds. Returns the report (errors, ranks, predicted PSNR, seconds, ...)
    as a dict. The output is published whole or not at all."""
    pairs = [(key, _setting_text(value)) for key, value in settings.items()]
    return _npf.convert(_path(source), _path(output), pairs, progress)


def edit_flags():
    """The edits ``edit`` takes as keywords: `npf edit`'s flags with '_' for '-'."""
    return [name[2:].replace("-", "_") for name, _ in _npf.edit_flags()]


def edit(source, output=None, recipe=None, dry_run=False, **edits):
    """Edits a factor texture, as `npf edit SOURCE -o OUTPUT [--recipe RECIPE] [flags]` does: the
    recipe's steps, then the keywords in the order given (``stretch_tangent=2, rotate=30``,
    ``diffuse_srgb=(0.8, 0.1, 0.1)``, ``limit_albedo=1``; a switch takes True). Returns the report
    (each step's summary, warnings, the history keys, the largest directional albedo)."""
    takes_value = dict(_npf.edit_flags())
    flags = []
    for key, value in edits.items():
        flag = "--" + key.replace("_", "-")
        if flag not in takes_value:
            raise _error(key, "not an edit (npf.edit_flags() lists them)")
        if not takes_value[flag]:
            if value is not True:
                raise _error(key, "a switch; give True")
            flags.append((flag, ""))
        else:
            flags.append((flag, _setting_text(value)))
    if output is None and not dry_run:
        raise _error("edit", "an output file is needed (or dry_run=True)")
    return _npf.edit(_path(source), "" if output is None else _path(output), "" if recipe is None else _path(recipe), flags,
                     bool(dry_run))
