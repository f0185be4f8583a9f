// Naive reference evaluation of RGL files; see naive_rgl.h. Written from rgl-format.md only.
#include "naive_rgl.h"

#include <npf/materials/tensor_file.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>

namespace npf::testing {

namespace {

constexpr double kPi = 3.14159265358979323846;

double lerp(double a, double b, double t) { return a + (b - a) * t; }

double clamp01(double v) { return std::min(1.0, std::max(0.0, v)); }

// The cell (column c, row r) of a W x H node grid that holds (ux, uy), clamped to [0, 1], and
// the position (s, t) in it.
struct GridCell {
    std::size_t c, r;
    double s, t;
};
GridCell grid_cell(double ux, double uy, std::size_t W, std::size_t H) {
    const double gx = clamp01(ux) * static_cast<double>(W - 1), gy = clamp01(uy) * static_cast<double>(H - 1);
    const std::size_t c = std::min(static_cast<std::size_t>(std::floor(gx)), W - 2);
    const std::size_t r = std::min(static_cast<std::size_t>(std::floor(gy)), H - 2);
    return {c, r, gx - static_cast<double>(c), gy - static_cast<double>(r)};
}

// Sec. 3.4: tau in [0, 1] with a*tau + (b - a)*tau^2/2 = y. `error` models float32
// cancellation in the quadratic branch (NaivePerturbation::ramp).
double ramp(double a, double b, double y, double error) {
    if (std::fabs(a - b) < 1e-4 * (a + b)) return 2.0 * y / (a + b);
    if (a + b <= 0.0) return 0.0;  // a zero-density segment (not reached by valid tables)
    return (a - std::sqrt(std::max(0.0, a * a + 2.0 * y * (b - a)))) / (a - b) +
           error * 0x1.0p-23 * std::max(a, b) / std::fabs(a - b);
}

double dot(const Vec3d& a, const Vec3d& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

Vec3d normalized(const Vec3d& v) {
    double len = std::sqrt(dot(v, v));
    return {v.x / len, v.y / len, v.z / len};
}

// Sec. 0: elevation as 2 asin(|w - n| / 2), azimuth as atan2(y, x).
double elevation(const Vec3d& w) {
    double d = std::sqrt(w.x * w.x + w.y * w.y + (w.z - 1.0) * (w.z - 1.0));
    return 2.0 * std::asin(std::min(1.0, 0.5 * d));
}

double azimuth(const Vec3d& w) { return std::atan2(w.y, w.x); }

double u_theta_of(double theta) { return std::sqrt(2.0 * theta / kPi); }

// Sec. 7: the sign flips that fold wi into the stored azimuth range.
struct Flips {
    bool x = false, y = false;
};

Flips fold_flips(const Vec3d& wi, int reduction) {
    Flips f;
    if (reduction == 2) {
        if (!std::signbit(wi.y)) f.x = f.y = true;  // rotation by pi about the normal
    } else if (reduction == 4) {
        if (!std::signbit(wi.y)) f.y = true;
        if (!std::signbit(wi.x)) f.x = true;
    }
    return f;
}

Vec3d apply_flips(Vec3d w, const Flips& f) {
    if (f.x) w.x = -w.x;
    if (f.y) w.y = -w.y;
    return w;
}

std::vector<std::size_t> shape_of(const TensorField& f) {
    std::vector<std::size_t> s;
    for (auto e : f.shape) s.push_back(static_cast<std::size_t>(e));
    return s;
}

void check(bool ok, const std::string& path, const std::string& what) {
    if (!ok) throw std::runtime_error(path + ": " + what);
}

}  // namespace

// ---- NaivePl2d ------------------------------------------------------------------------------

NaivePl2d::NaivePl2d(std::vector<std::vector<double>> grids, std::size_t height,
                     std::size_t width, std::vector<double> values, bool normalize)
    : m_grids(std::move(grids)), m_height(height), m_width(width), m_normalized(normalize),
      m_data(std::move(values)) {
    m_slices = 1;
    for (const auto& g : m_grids) m_slices *= g.size();
    if (m_width < 2 || m_height < 2 || m_data.size() != m_slices * m_width * m_height)
        throw std::runtime_error("NaivePl2d: inconsistent table size");
    if (!normalize) return;

    const std::size_t W = m_width, H = m_height;
    const double dx = 1.0 / static_cast<double>(W - 1);
    const double dy = 1.0 / static_cast<double>(H - 1);
    m_row_cdf.assign(m_slices * H * W, 0.0);
    m_row_int.assign(m_slices * H, 0.0);
    m_marginal.assign(m_slices * H, 0.0);
    for (std::size_t s = 0; s < m_slices; ++s) {
        double* d = &m_data[s * H * W];
        double* C = &m_row_cdf[s * H * W];
        double* Rw = &m_row_int[s * H];
        double* M = &m_marginal[s * H];
        for (std::size_t r = 0; r < H; ++r) {
            C[r * W] = 0.0;
            for (std::size_t c = 1; c < W; ++c)
                C[r * W + c] = C[r * W + c - 1] + dx * (d[r * W + c - 1] + d[r * W + c]) / 2.0;
            Rw[r] = C[r * W + W - 1];
        }
        M[0] = 0.0;
        for (std::size_t r = 1; r < H; ++r) M[r] = M[r - 1] + dy * (Rw[r - 1] + Rw[r]) / 2.0;
        const double Z = M[H - 1];
        if (!(Z > 0.0)) throw std::runtime_error("NaivePl2d: slice with zero integral");
        for (std::size_t k = 0; k < H * W; ++k) {
            d[k] /= Z;
            C[k] /= Z;
        }
        for (std::size_t r = 0; r < H; ++r) {
            Rw[r] /= Z;
            M[r] /= Z;
        }
    }
}

std::vector<NaivePl2d::Corner> NaivePl2d::corners(const std::vector<double>& params) const {
    const std::size_t P = m_grids.size();
    if (params.size() != P) throw std::runtime_error("NaivePl2d: wrong parameter count");
    std::vector<std::size_t> index(P, 0);
    std::vector<double> t(P, 0.0);
    std::vector<std::size_t> stride(P, 1);
    for (std::size_t p = 0; p < P; ++p) {
        for (std::size_t p2 = p + 1; p2 < P; ++p2) stride[p] *= m_grids[p2].size();
        const auto& g = m_grids[p];
        if (g.size() == 1) continue;  // inert axis
        std::size_t i = 0;
        for (std::size_t k = 0; k + 1 < g.size(); ++k)  // largest i in [0, N-2] with g[i] <= q
            if (g[k] <= params[p]) i = k;
        index[p] = i;
        t[p] = std::min(1.0, std::max(0.0, (params[p] - g[i]) / (g[i + 1] - g[i])));
    }
    std::vector<Corner> out;
    for (std::size_t b = 0; b < (std::size_t(1) << P); ++b) {
        Corner c;
        c.weight = 1.0;
        bool skip = false;
        for (std::size_t p = 0; p < P; ++p) {
            const bool bp = ((b >> p) & 1u) != 0;
            if (bp && m_grids[p].size() == 1) {
                skip = true;
                break;
            }
            c.slice += (index[p] + (bp ? 1 : 0)) * stride[p];
            c.weight *= bp ? t[p] : 1.0 - t[p];
        }
        if (!skip) out.push_back(c);
    }
    return out;
}

double NaivePl2d::blend(const std::vector<Corner>& cs, const std::vector<double>& table,
                        std::size_t per_slice, std::size_t k) {
    double v = 0.0;
    for (const auto& c : cs) v += c.weight * table[c.slice * per_slice + k];
    return v;
}

double NaivePl2d::eval(double ux, double uy, const std::vector<double>& params) const {
    const auto cs = corners(params);
    const std::size_t W = m_width, H = m_height;
    const auto [c, r, s, t] = grid_cell(ux, uy, W, H);
    auto v = [&](std::size_t rr, std::size_t cc) { return blend(cs, m_data, H * W, rr * W + cc); };
    return lerp(lerp(v(r, c), v(r, c + 1), s), lerp(v(r + 1, c), v(r + 1, c + 1), s), t);
}

void NaivePl2d::sample(double xi_x, double xi_y, const std::vector<double>& params, double& ux,
                       double& uy, double& density, double ramp_error) const {
    if (!m_normalized) throw std::runtime_error("NaivePl2d: sample() on a raw table");
    const auto cs = corners(params);
    const std::size_t W = m_width, H = m_height;
    const double dx = 1.0 / static_cast<double>(W - 1);
    const double dy = 1.0 / static_cast<double>(H - 1);
    xi_x = std::min(1.0 - kSampleEpsilon, std::max(kSampleEpsilon, xi_x));
    xi_y = std::min(1.0 - kSampleEpsilon, std::max(kSampleEpsilon, xi_y));

    auto M = [&](std::size_t r) { return blend(cs, m_marginal, H, r); };
    auto Rw = [&](std::size_t r) { return blend(cs, m_row_int, H, r); };
    auto C = [&](std::size_t r, std::size_t c) { return blend(cs, m_row_cdf, H * W, r * W + c); };
    auto d = [&](std::size_t r, std::size_t c) { return blend(cs, m_data, H * W, r * W + c); };

    std::size_t r = 0;
    for (std::size_t k = 0; k + 1 < H; ++k)
        if (M(k) < xi_y) r = k;
    const double a = Rw(r), b = Rw(r + 1);
    const double t = ramp(a, b, (xi_y - M(r)) / dy, ramp_error);
    const double target = xi_x * lerp(a, b, t);
    auto Cr = [&](std::size_t c) { return lerp(C(r, c), C(r + 1, c), t); };
    std::size_t c = 0;
    for (std::size_t k = 0; k + 1 < W; ++k)
        if (Cr(k) < target) c = k;
    const double p0 = lerp(d(r, c), d(r + 1, c), t);
    const double p1 = lerp(d(r, c + 1), d(r + 1, c + 1), t);
    const double s = ramp(p0, p1, (target - Cr(c)) / dx, ramp_error);
    ux = (static_cast<double>(c) + s) * dx;
    uy = (static_cast<double>(r) + t) * dy;
    density = lerp(p0, p1, s);
}

void NaivePl2d::invert(double ux, double uy, const std::vector<double>& params, double& xi_x,
                       double& xi_y, double& density) const {
    if (!m_normalized) throw std::runtime_error("NaivePl2d: invert() on a raw table");
    const auto cs = corners(params);
    const std::size_t W = m_width, H = m_height;
    const double dx = 1.0 / static_cast<double>(W - 1);
    const double dy = 1.0 / static_cast<double>(H - 1);
    const auto [c, r, s, t] = grid_cell(ux, uy, W, H);

    auto M = [&](std::size_t rr) { return blend(cs, m_marginal, H, rr); };
    auto Rw = [&](std::size_t rr) { return blend(cs, m_row_int, H, rr); };
    auto C = [&](std::size_t rr, std::size_t cc) {
        return blend(cs, m_row_cdf, H * W, rr * W + cc);
    };
    auto d = [&](std::size_t rr, std::size_t cc) { return blend(cs, m_data, H * W, rr * W + cc); };

    const double p0 = lerp(d(r, c), d(r + 1, c), t);
    const double p1 = lerp(d(r, c + 1), d(r + 1, c + 1), t);
    density = lerp(p0, p1, s);
    const double a = Rw(r), b = Rw(r + 1);
    xi_x = (lerp(C(r, c), C(r + 1, c), t) + dx * (p0 * s + (p1 - p0) * s * s / 2.0)) /
           lerp(a, b, t);
    xi_y = M(r) + dy * (a * t + (b - a) * t * t / 2.0);
}

// ---- NaiveRgl -------------------------------------------------------------------------------

NaiveRgl NaiveRgl::load(const std::string& path) {
    const TensorFile file = TensorFile::read(path);
    NaiveRgl m;

    const TensorField& f_phi = file.require("phi_i");
    const TensorField& f_theta = file.require("theta_i");
    const TensorField& f_ndf = file.require("ndf");
    const TensorField& f_sigma = file.require("sigma");
    const TensorField& f_vndf = file.require("vndf");
    const TensorField& f_lum = file.require("luminance");
    const TensorField& f_jac = file.require("jacobian");
    const TensorField* f_rgb = file.find("rgb");
    const TensorField* f_spectra = file.find("spectra");
    const TensorField* f_wl = file.find("wavelengths");

    m.phi_i = file.to_double(f_phi);
    m.theta_i = file.to_double(f_theta);
    const std::size_t nP = m.phi_i.size(), nT = m.theta_i.size();
    check(nP >= 1 && nT >= 1, path, "empty phi_i or theta_i");
    const auto jac = file.to_double(f_jac);
    check(jac.size() == 1, path, "jacobian must have one element");
    m.jacobian = jac[0] != 0.0;

    // Sec. 2 / 7: isotropic iff nP <= 2 (powitacq, pbrt, Mitsuba 3); otherwise the reduction
    // is round(2 pi / (phi_last - phi_first)).
    m.isotropic = nP <= 2;
    m.reduction = 1;
    if (!m.isotropic) {
        m.reduction =
            static_cast<int>(std::lround(2.0 * kPi / (m.phi_i.back() - m.phi_i.front())));
        check(m.reduction == 1 || m.reduction == 2 || m.reduction == 4, path,
              "unsupported phi_i reduction");
    }

    const auto s_ndf = shape_of(f_ndf), s_sigma = shape_of(f_sigma);
    const auto s_vndf = shape_of(f_vndf), s_lum = shape_of(f_lum);
    check(s_ndf.size() == 2 && s_sigma.size() == 2, path, "ndf / sigma must be 2-D");
    check(s_vndf.size() == 4 && s_vndf[0] == nP && s_vndf[1] == nT, path, "vndf shape");
    check(s_lum.size() == 4 && s_lum[0] == nP && s_lum[1] == nT, path, "luminance shape");

    m.m_ndf = NaivePl2d({}, s_ndf[0], s_ndf[1], file.to_double(f_ndf), false);
    m.m_sigma = NaivePl2d({}, s_sigma[0], s_sigma[1], file.to_double(f_sigma), false);
    m.m_vndf = NaivePl2d({m.phi_i, m.theta_i}, s_vndf[2], s_vndf[3], file.to_double(f_vndf),
                         true);
    m.m_luminance = NaivePl2d({m.phi_i, m.theta_i}, s_lum[2], s_lum[3], file.to_double(f_lum),
                              true);

    const TensorField* f_data = nullptr;
    std::vector<double> channel_grid;
    if (f_wl != nullptr) {  // sec. 8: spectral iff `wavelengths` is present
        check(f_spectra != nullptr, path, "wavelengths without spectra");
        m.spectral = true;
        m.stored_wavelengths = file.to_double(*f_wl);
        channel_grid = m.stored_wavelengths;
        f_data = f_spectra;
    } else {
        check(f_rgb != nullptr, path, "neither rgb nor spectra");
        channel_grid = {0.0, 1.0, 2.0};
        f_data = f_rgb;
    }
    const auto s_data = shape_of(*f_data);
    check(s_data.size() == 5 && s_data[0] == nP && s_data[1] == nT &&
              s_data[2] == channel_grid.size() && s_data[3] == s_lum[2] && s_data[4] == s_lum[3],
          path, "data shape");
    m.m_data = NaivePl2d({m.phi_i, m.theta_i, channel_grid}, s_data[3], s_data[4],
                         file.to_double(*f_data), false);
    return m;
}

std::vector<double> NaiveRgl::channel_params(const std::vector<double>& wavelengths) const {
    if (!spectral) {
        if (!wavelengths.empty()) throw std::runtime_error("NaiveRgl: wavelengths for RGB file");
        return {0.0, 1.0, 2.0};
    }
    return wavelengths.empty() ? stored_wavelengths : wavelengths;
}

std::vector<double> NaiveRgl::data_values(double xi_x, double xi_y, double phi_in,
                                          double theta_in,
                                          const std::vector<double>& wavelengths,
                                          bool clamp) const {
    std::vector<double> out;
    for (double lambda : channel_params(wavelengths)) {
        double v = m_data.eval(xi_x, xi_y, {phi_in, theta_in, lambda});
        if (clamp) v = std::max(0.0, v);
        out.push_back(v);
    }
    return out;
}

NaiveRgl::Lookup NaiveRgl::lookup(const Vec3d& wi_in, const Vec3d& wo_in,
                                  const NaivePerturbation& perturb) const {
    Lookup l;
    const Flips flips = isotropic ? Flips{} : fold_flips(wi_in, reduction);
    l.wi = apply_flips(wi_in, flips);
    const Vec3d wo = apply_flips(wo_in, flips);
    l.wh = normalized({l.wi.x + wo.x, l.wi.y + wo.y, l.wi.z + wo.z});

    l.theta_i = elevation(l.wi);
    l.phi_i = azimuth(l.wi);
    const double th_h = elevation(l.wh);
    double ph_h = azimuth(l.wh);
    if (isotropic) ph_h -= l.phi_i;
    l.uh_y = (ph_h + kPi) / (2.0 * kPi);
    l.uh_y -= std::floor(l.uh_y);
    l.uh_y += perturb.uh_y;
    l.uh_x = u_theta_of(th_h) + perturb.uh_x;
    l.ui_x = u_theta_of(l.theta_i);
    l.ui_y = (l.phi_i + kPi) / (2.0 * kPi);

    m_vndf.invert(l.uh_x, l.uh_y, {l.phi_i, l.theta_i}, l.xi_x, l.xi_y, l.vndf_density);
    l.xi_x += perturb.xi_x;
    l.xi_y += perturb.xi_y;
    return l;
}

std::vector<double> NaiveRgl::eval_cos(const Vec3d& wi_in, const Vec3d& wo_in,
                                       const std::vector<double>& wavelengths, bool clamp,
                                       const NaivePerturbation& perturb) const {
    const std::size_t n = channel_params(wavelengths).size();
    if (wi_in.z <= 0.0 || wo_in.z <= 0.0) return std::vector<double>(n, 0.0);
    const Lookup l = lookup(wi_in, wo_in, perturb);
    std::vector<double> S = data_values(l.xi_x, l.xi_y, l.phi_i, l.theta_i, wavelengths, clamp);
    if (jacobian) {
        const double factor = m_ndf.eval(l.uh_x, l.uh_y, {}) / (4.0 * m_sigma.eval(l.ui_x, l.ui_y, {}));
        for (double& v : S) v *= factor;
    }
    return S;
}

double NaiveRgl::pdf(const Vec3d& wi_in, const Vec3d& wo_in,
                     const NaivePerturbation& perturb) const {
    if (wi_in.z <= 0.0 || wo_in.z <= 0.0) return 0.0;
    const Lookup l = lookup(wi_in, wo_in, perturb);
    const double pL = m_luminance.eval(l.xi_x, l.xi_y, {l.phi_i, l.theta_i});
    const double J = std::max(2.0 * kPi * kPi * l.uh_x * std::sqrt(l.wh.x * l.wh.x + l.wh.y * l.wh.y),
                              1e-6) *
                     4.0 * dot(l.wi, l.wh);
    return l.vndf_density * pL / J;
}

bool NaiveRgl::sample(const Vec3d& wi_in, double u1, double u2, Vec3d& wo_out, double& pdf_out,
                      std::vector<double>* weight, const std::vector<double>& wavelengths,
                      bool clamp, const NaivePerturbation& perturb) const {
    pdf_out = 0.0;
    if (weight != nullptr) weight->assign(channel_params(wavelengths).size(), 0.0);
    if (wi_in.z <= 0.0) return false;
    const Flips flips = isotropic ? Flips{} : fold_flips(wi_in, reduction);
    const Vec3d wi = apply_flips(wi_in, flips);

    const double th_i = elevation(wi), ph_i = azimuth(wi);
    const double ui_x = u_theta_of(th_i), ui_y = (ph_i + kPi) / (2.0 * kPi);

    double xi_x = 0.0, xi_y = 0.0, pL = 0.0;
    // The readers swap u1 and u2.
    m_luminance.sample(u2 + perturb.u2, u1 + perturb.u1, {ph_i, th_i}, xi_x, xi_y, pL,
                       perturb.ramp);
    xi_x += perturb.xi_x;
    xi_y += perturb.xi_y;
    double uh_x = 0.0, uh_y = 0.0, pV = 0.0;
    m_vndf.sample(xi_x, xi_y, {ph_i, th_i}, uh_x, uh_y, pV, perturb.ramp);
    uh_x += perturb.uh_x;
    uh_y += perturb.uh_y;

    const double th_h = (kPi / 2.0) * uh_x * uh_x;
    double ph_h = (2.0 * uh_y - 1.0) * kPi;
    if (isotropic) ph_h += ph_i;
    const Vec3d wh{std::cos(ph_h) * std::sin(th_h), std::sin(ph_h) * std::sin(th_h),
                   std::cos(th_h)};
    const double dwh = dot(wi, wh);
    const Vec3d wo{2.0 * dwh * wh.x - wi.x, 2.0 * dwh * wh.y - wi.y, 2.0 * dwh * wh.z - wi.z};
    if (wo.z <= 0.0) return false;

    pdf_out = pV * pL / (std::max(2.0 * kPi * kPi * uh_x * std::sin(th_h), 1e-6) * 4.0 * dwh);
    wo_out = apply_flips(wo, flips);
    if (weight != nullptr) {
        std::vector<double> S = data_values(xi_x, xi_y, ph_i, th_i, wavelengths, clamp);
        if (jacobian) {
            const double factor =
                m_ndf.eval(uh_x, uh_y, {}) / (4.0 * m_sigma.eval(ui_x, ui_y, {}));
            for (double& v : S) v *= factor;
        }
        for (std::size_t k = 0; k < S.size(); ++k) (*weight)[k] = S[k] / pdf_out;
    }
    return true;
}

}  // namespace npf::testing
