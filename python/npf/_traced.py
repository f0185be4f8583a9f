"""npf's model and sampler in Dr.Jit operations (the traced half of the Mitsuba plugin,
npf/mitsuba.py): Eq. 1 over a factor texture's tables as npf_model.h evaluates it, and the
closure's sampler (npf_closure.h), in single precision, for the current Mitsuba variant (scalar,
LLVM or CUDA; RGB or spectral). The tables come from npf's reader (npf.Material.factor_tables)."""

import math as _math

import numpy as _np

_INV_HALF_PI = 2.0 / _math.pi
_INV_TWO_PI = 0.5 / _math.pi
_FLOAT_MAX = 3.4028234663852886e38
_BELOW_ONE = 1.0 - 2.0 ** -24  # the largest float below 1 (0x1.fffffep-1)


def _ops():
    """The Dr.Jit operations of the current variant: gathers and integer casts differ between the
    scalar variants (Python numbers, tables as lists) and the JIT ones (arrays, device tables)."""
    import drjit as dr
    import mitsuba as mi

    scalar = mi.variant().startswith("scalar")

    class Ops:
        Float, UInt32 = mi.Float, mi.UInt32

        @staticmethod
        def table(values, integer=False):
            a = _np.ascontiguousarray(_np.asarray(values).ravel(), dtype=_np.uint32 if integer else _np.float32)
            if scalar:
                return a.tolist()
            return mi.UInt32(a) if integer else mi.Float(a)

        @staticmethod
        def gather(table, index, active=True):
            if scalar:
                return table[int(index)] if active else 0
            return dr.gather(type(table), table, index, active)

        @staticmethod
        def to_uint(x):
            return int(x) if scalar else mi.UInt32(x)

        @staticmethod
        def to_float(i):
            return float(i) if scalar else mi.Float(i)

        @staticmethod
        def single(x):
            # Rounded to float where npf's sampler computes in float (the alias table's draw), so
            # that the scalar variants (Python's doubles) draw npf's directions too.
            return float(_np.float32(x)) if scalar else x

    return Ops


def _not(mask):
    # ~ on a Dr.Jit mask; on the scalar variants' Python bools ~True would be -2.
    return (not mask) if isinstance(mask, bool) else ~mask


def _nonzero(dr, x):
    # A denominator for a select's unused side: Python floats raise on 0 (the scalar variants).
    return dr.select(x == 0.0, 1.0, x)


def _sqrt(dr, x):
    return dr.sqrt(dr.maximum(x, 0.0))


def _azimuth(dr, x, y):
    phi = dr.atan2(y, x)
    return dr.select(phi < 0.0, phi + 2.0 * _math.pi, phi)


# ---- The table axes (npf_equation.h, table_interpolation.h): cell centres at k + 1/2 ----------

def _clamped(ops, dr, x, n):
    """D's and F's rows: clamped at the outer centres. (i0, i1, weight of i1)."""
    c = dr.clip(x - 0.5, 0.0, float(n - 1))
    whole = dr.floor(c)
    i1 = dr.minimum(whole + 1.0, float(n - 1))
    return ops.to_uint(whole), ops.to_uint(i1), c - whole


def _periodic(ops, dr, x, n):
    """Azimuths: periodic."""
    c = x - 0.5
    c = dr.select(c < 0.0, c + float(n), c)
    c = dr.select((c < 0.0) | _not(c < float(n)), c - dr.floor(c / float(n)) * float(n), c)
    i0 = dr.minimum(dr.floor(c), float(n - 1))
    i1 = dr.select(i0 + 1.0 == float(n), 0.0, i0 + 1.0)
    return ops.to_uint(i0), ops.to_uint(i1), c - i0


def _extrapolated(ops, dr, x, n):
    """G's rows: flat below the first centre, beyond the last along the line through the last two."""
    if n == 1:
        return ops.to_uint(0), ops.to_uint(0), 0.0 * x
    c = dr.maximum(x - 0.5, 0.0)
    i0 = dr.minimum(dr.floor(c), float(n - 2))
    return ops.to_uint(i0), ops.to_uint(i0 + 1.0), c - i0


class _Basis:
    """A spectral basis (npf_model.h's SpectralBasis) on the device: one table per rank, the
    per-channel weights flat [channel][rank], and RGB's weights as numbers (traced as literals)."""

    def __init__(self, ops, d, rgb):
        self.rank = int(d["rank"])
        basis = _np.asarray(d["basis"], dtype=_np.float32)
        self.tables = [ops.table(basis[k]) for k in range(self.rank)]
        weights = _np.asarray(d["weights"], dtype=_np.float32)
        self.weights = ops.table(weights)
        self.rgb_weights = [[float(w) for w in row] for row in weights] if rgb else None

    def project(self, ops, corners):
        """The interpolated basis values at a position: corners are (index, weight) pairs."""
        values = []
        for table in self.tables:
            v = 0.0
            for index, weight in corners:
                v = v + ops.gather(table, index) * weight
            values.append(v)
        return values

    def combine(self, ops, projected, channel):
        """Channel `channel`'s table at the position (an int for RGB, a per-lane index for spectral)."""
        if self.rgb_weights is not None:
            w = self.rgb_weights[channel]
            v = 0.0
            for k in range(self.rank):
                v = v + w[k] * projected[k]
            return v
        v = 0.0
        for k in range(self.rank):
            v = v + ops.gather(self.weights, channel * self.rank + k) * projected[k]
        return v


class TracedModel:
    """npf's model and sampler (npf_model.h, npf_closure.h) in Dr.Jit operations over a factor
    texture's tables, for the current Mitsuba variant. `material` is an npf.Material."""

    def __init__(self, material):
        import drjit as dr
        import mitsuba as mi
        self.dr, self.mi = dr, mi
        self.ops = ops = _ops()
        t = material.factor_tables()
        self.rgb = t["channels"] == "rgb"
        self.channel_count = len(t["rho_d"])
        self.d_theta, self.d_phi, self.f_theta = int(t["d_theta"]), int(t["d_phi"]), int(t["f_theta"])
        self.g_theta, self.g_phi = int(t["g_theta"]), int(t["g_phi"])
        self.rho_d = [float(v) for v in t["rho_d"]]
        self.rho_s = [float(v) for v in t["rho_s"]]
        self.rho_d_table, self.rho_s_table = ops.table(t["rho_d"]), ops.table(t["rho_s"])
        self.F = ops.table(t["F"])
        self.D, self.G = _Basis(ops, t["D"], self.rgb), _Basis(ops, t["G"], self.rgb)
        self.detail_grid = tuple(int(n) for n in t["detail_grid"]) if "detail_grid" in t else None
        self.detail = _Basis(ops, t["detail"], self.rgb) if self.detail_grid else None
        self.wavelengths = [float(w) for w in t["wavelengths_nm"]]
        self.wavelength_table = ops.table(t["wavelengths_nm"]) if self.wavelengths else None
        self.diffuse_probability = float(t["diffuse_probability"])
        self.sampler = None
        if "sampler" in t:
            s = t["sampler"]
            self.cells = len(s["keep"])
            self.keep, self.alias = ops.table(s["keep"]), ops.table(s["alias"], integer=True)
            self.density, self.half_sin2 = ops.table(s["density"]), ops.table(s["half_sin2"])
            self.sampler = True

    # ---- Eq. 1 at a pair (NpfModel::prepare and value) ------------------------------------------

    def _bilinear(self, row, col, cols):
        r0, r1, rt = row
        if cols == 1:  # one column (isotropic): the column is 0 wherever the azimuth falls
            return [(r0, 1.0 - rt), (r1, rt)]
        c0, c1, ct = col
        return [(r0 * cols + c0, (1.0 - rt) * (1.0 - ct)), (r0 * cols + c1, (1.0 - rt) * ct),
                (r1 * cols + c0, rt * (1.0 - ct)), (r1 * cols + c1, rt * ct)]

    def prepare(self, wi, wo):
        """Everything every channel shares at the pairs (wi, wo): the projected bases, F's row,
        1 / (cos_i cos_o) and the pair's domain (both directions above the horizon)."""
        dr, ops = self.dr, self.ops
        ix, iy, iz = wi.x, wi.y, wi.z
        ox, oy, oz = wo.x, wo.y, wo.z
        hx, hy, hz = ix + ox, iy + oy, iz + oz
        r2 = hx * hx + hy * hy
        length = _sqrt(dr, r2 + hz * hz)
        theta_h = dr.atan2(_sqrt(dr, r2), hz)
        u_h = _sqrt(dr, theta_h * _INV_HALF_PI)
        phi_h = _azimuth(dr, hx, hy) if self.d_phi > 1 else 0.0 * hx
        cx, cy, cz = iy * oz - iz * oy, iz * ox - ix * oz, ix * oy - iy * ox
        theta_d = dr.atan2(_sqrt(dr, cx * cx + cy * cy + cz * cz), 1.0 + (ix * ox + iy * oy + iz * oz))
        at = {"domain": (iz > 0.0) & (oz > 0.0), "inv_cos": 1.0 / _nonzero(dr, iz * oz), "cos_o": oz}
        d_col = _periodic(ops, dr, phi_h * _INV_TWO_PI * float(self.d_phi), self.d_phi) if self.d_phi > 1 else None
        at["D"] = self.D.project(ops, self._bilinear(_clamped(ops, dr, u_h * float(self.d_theta), self.d_theta), d_col,
                                                     self.d_phi))
        for name, (x, y, z) in (("Gi", (ix, iy, iz)), ("Go", (ox, oy, oz))):
            theta = dr.atan2(_sqrt(dr, x * x + y * y), z)
            row = _extrapolated(ops, dr, theta * _INV_HALF_PI * float(self.g_theta), self.g_theta)
            col = _periodic(ops, dr, _azimuth(dr, x, y) * _INV_TWO_PI * float(self.g_phi), self.g_phi) if self.g_phi > 1 else None
            at[name] = self.G.project(ops, self._bilinear(row, col, self.g_phi))
        at["F"] = _clamped(ops, dr, theta_d * _INV_HALF_PI * float(self.f_theta), self.f_theta)
        if self.detail:
            # phi_d: wi's azimuth in the half vector's frame (detail_grid.h); at the pole wi's own.
            gh, gd, gp = self.detail_grid
            dx = hz * (hx * ix + hy * iy) - r2 * iz
            dy = length * (hx * iy - hy * ix)
            along_normal = _not(r2 > 1e-24 * length * length)
            phi_d = _azimuth(dr, dr.select(along_normal, ix, dx), dr.select(along_normal, iy, dy))
            h0, h1, ht = _clamped(ops, dr, u_h * float(gh), gh)
            d0, d1, dt = _clamped(ops, dr, theta_d * _INV_HALF_PI * float(gd), gd)
            p0, p1, pt = _periodic(ops, dr, phi_d * _INV_TWO_PI * float(gp), gp)
            corners = []
            for h, wh in ((h0, 1.0 - ht), (h1, ht)):
                for d, wd in ((d0, 1.0 - dt), (d1, dt)):
                    for p, wp in ((p0, 1.0 - pt), (p1, pt)):
                        corners.append(((h * gd + d) * gp + p, wh * wd * wp))
            at["R"] = self.detail.project(ops, corners)
        return at

    def channel_value(self, at, c):
        """f_r of stored channel c (an int for RGB, per-lane indices for spectral files)."""
        dr, ops = self.dr, self.ops
        d = dr.maximum(self.D.combine(ops, at["D"], c), 0.0)
        gi = dr.maximum(self.G.combine(ops, at["Gi"], c), 0.0)
        go = dr.maximum(self.G.combine(ops, at["Go"], c), 0.0)
        f0, f1, ft = at["F"]
        f = ops.gather(self.F, c * self.f_theta + f0) * (1.0 - ft) + ops.gather(self.F, c * self.f_theta + f1) * ft
        if self.rgb:
            rho_d, rho_s = self.rho_d[c], self.rho_s[c]
        else:
            rho_d, rho_s = ops.gather(self.rho_d_table, c), ops.gather(self.rho_s_table, c)
        v = rho_d + rho_s * d * f * gi * go * at["inv_cos"]
        if self.detail:
            v = dr.maximum(v + self.detail.combine(ops, at["R"], c), 0.0)
        return v

    def _finite(self, v):
        # npf's finite_float: a grazing pair can push f_r cos past float's range; NaN is 0.
        dr = self.dr
        return dr.select(dr.isnan(v), 0.0, dr.minimum(v, _FLOAT_MAX))

    def values(self, at, wavelengths=None):
        """f_r cos(theta_o) per channel (a list): every stored channel of an RGB file, or the
        spectral file's value at each of `wavelengths` (linear between the stored neighbours,
        constant outside them, as npf's closure)."""
        dr, ops = self.dr, self.ops
        out = []
        if self.rgb or wavelengths is None:
            for c in range(self.channel_count):
                out.append(self._finite(dr.maximum(self.channel_value(at, c), 0.0) * at["cos_o"]))
            return out
        n = len(self.wavelengths)
        for lam in wavelengths:
            if n == 1:
                i0 = ops.to_uint(0 * lam)
                v = self.channel_value(at, i0)
            else:
                # The last stored wavelength at or below lam, at most n - 2 (channels.h).
                i = dr.binary_search(0, n - 1, lambda k: ops.gather(self.wavelength_table, k) <= lam)
                i0 = dr.minimum(dr.maximum(i, 1) - 1, n - 2)
                i0 = ops.to_uint(i0)
                g0, g1 = ops.gather(self.wavelength_table, i0), ops.gather(self.wavelength_table, i0 + 1)
                t = dr.clip((lam - g0) / (g1 - g0), 0.0, 1.0)
                a, b = self.channel_value(at, i0), self.channel_value(at, i0 + 1)
                v = dr.select(t == 0.0, a, (1.0 - t) * a + t * b)
            out.append(self._finite(dr.maximum(v, 0.0) * at["cos_o"]))
        return out

    # ---- The sampler (NpfClosure::pdf_at, draw_light) -------------------------------------------

    def pdf(self, wi, wo):
        dr, ops = self.dr, self.ops
        ix, iy, iz, ox, oy, oz = wi.x, wi.y, wi.z, wo.x, wo.y, wo.z
        pd = self.diffuse_probability
        p = pd * oz * (1.0 / _math.pi)
        if self.sampler:
            hx, hy, hz = ix + ox, iy + oy, iz + oz
            r2 = hx * hx + hy * hy
            theta_h = dr.atan2(_sqrt(dr, r2), hz)
            u_h = _sqrt(dr, theta_h * _INV_HALF_PI)
            phi_h = _azimuth(dr, hx, hy) if self.d_phi > 1 else 0.0 * hx
            cos_d = (ix * hx + iy * hy + iz * hz) / _nonzero(dr, _sqrt(dr, r2 + hz * hz))
            k = dr.minimum(dr.floor(u_h * float(self.d_theta)), float(self.d_theta - 1))
            j = dr.minimum(dr.floor(phi_h * _INV_TWO_PI * float(self.d_phi)), float(self.d_phi - 1))
            ok = (cos_d > 0.0) & (theta_h < 0.5 * _math.pi)
            cell = ops.to_uint(dr.select(ok, k * float(self.d_phi) + j, 0.0))
            p = p + dr.select(ok, (1.0 - pd) * ops.gather(self.density, cell, ok) / (4.0 * _nonzero(dr, cos_d)), 0.0)
        return self._finite(dr.select((iz > 0.0) & (oz > 0.0), p, 0.0))

    def draw(self, wi, u1, u2):
        """The direction npf's closure draws from (u1, u2) given wi (draw_light): the cosine
        strategy where u2 < diffuse_probability, else a half vector from the alias table over D's
        cells, reflected. Returns a Vector3f (below the horizon: a failed draw)."""
        dr, mi, ops = self.dr, self.mi, self.ops
        pd = self.diffuse_probability
        v_cos = ops.single(dr.minimum(u2 / pd, _BELOW_ONE)) if pd > 0.0 else u2
        light_cos = self._cosine_direction(u1, v_cos)
        if not self.sampler:
            return light_cos
        v = ops.single(dr.minimum((u2 - pd) / (1.0 - pd), _BELOW_ONE))
        n = self.cells
        scaled = ops.single(u1 * float(n))
        i = dr.minimum(dr.floor(scaled), float(n - 1))
        f = ops.single(dr.minimum(scaled - i, _BELOW_ONE))
        i = ops.to_uint(i)
        keep = ops.gather(self.keep, i)
        kept = f < keep
        index = dr.select(kept, i, ops.gather(self.alias, i))
        remainder = dr.select(kept, f / _nonzero(dr, keep), ops.single(f - keep) / _nonzero(dr, ops.single(1.0 - keep)))
        remainder = dr.minimum(ops.single(remainder), _BELOW_ONE)
        k, j = index // self.d_phi, index % self.d_phi
        s0, s1 = ops.gather(self.half_sin2, k), ops.gather(self.half_sin2, k + 1)
        s = s0 + (s1 - s0) * remainder
        cos_theta, sin_theta = 1.0 - 2.0 * s, 2.0 * _sqrt(self.dr, s * (1.0 - s))
        phi = 2.0 * _math.pi * (ops.to_float(j) + v) / float(self.d_phi)
        sin_phi, cos_phi = dr.sincos(phi)
        h = mi.Vector3f(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)
        light_h = 2.0 * dr.dot(wi, h) * h - wi
        return dr.select(u2 < pd, light_cos, light_h)

    def _cosine_direction(self, u1, u2):
        # npf's cosine_hemisphere_direction (Shirley-Chiu's concentric map).
        dr, mi = self.dr, self.mi
        a, b = 2.0 * u1 - 1.0, 2.0 * u2 - 1.0
        first = dr.abs(a) > dr.abs(b)
        r = dr.select(first, a, b)
        safe_a, safe_b = dr.select(a == 0.0, 1.0, a), dr.select(b == 0.0, 1.0, b)
        phi = dr.select(first, (_math.pi / 4.0) * (b / safe_a), (_math.pi / 2.0) - (_math.pi / 4.0) * (a / safe_b))
        zero = (a == 0.0) & (b == 0.0)
        r, phi = dr.select(zero, 0.0, r), dr.select(zero, 0.0, phi)
        s, c = dr.sincos(phi)
        return mi.Vector3f(r * c, r * s, _sqrt(dr, 1.0 - r * r))
