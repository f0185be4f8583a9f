#include <npf/shading/npf_model.h>

#include <npf/core/brdf.h>
#include <npf/core/error.h>
#include <npf/shading/npf_equation.h>
#include <npf/shading/table_interpolation.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace npf {

namespace {

using table::Lerp;
using table::bilinear;

// G's cell position for one direction, from its angles.
NpfModel::Lookup::Bilinear g_position(double theta, double phi, int g_theta, int g_phi, double& row, double& col) {
    const Lerp r = equation::g_row(theta, g_theta);
    // An isotropic table has one column (its azimuth was not computed).
    const Lerp c = g_phi == 1 ? Lerp{} : equation::column(phi, g_phi);
    row = r.i0 + r.t;
    col = c.i0 + c.t;
    return bilinear(r, c, g_phi);
}

double interpolate(const float* table, const NpfModel::Lookup::Bilinear& b) {
    return table[b.index[0]] * b.weight[0] + table[b.index[1]] * b.weight[1] + table[b.index[2]] * b.weight[2] +
           table[b.index[3]] * b.weight[3];
}

// The interpolated basis values of one table at one position.
void project(const SpectralBasis& s, const NpfModel::Lookup::Bilinear& b, double* out) {
    // Corners and weights in locals: `out` could alias b.weight as far as the compiler knows.
    const std::size_t i0 = b.index[0], i1 = b.index[1], i2 = b.index[2], i3 = b.index[3], cells = s.cells;
    const double w0 = b.weight[0], w1 = b.weight[1], w2 = b.weight[2], w3 = b.weight[3];
    const float* t = s.basis.data();
    for (int k = 0; k < s.rank; ++k, t += cells) out[k] = t[i0] * w0 + t[i1] * w1 + t[i2] * w2 + t[i3] * w3;
}

// The interpolated basis values of the detail layer at its eight corners.
void project(const SpectralBasis& s, const Trilinear& t, double* out) {
    const float* b = s.basis.data();
    for (int k = 0; k < s.rank; ++k, b += s.cells) {
        double v = 0.0;
        for (int j = 0; j < 8; ++j) v += b[t.index[j]] * t.weight[j];
        out[k] = v;
    }
}

double combine_detail(const SpectralBasis& s, std::size_t c, const Trilinear& t) {
    const float* w = s.weights.data() + c * std::size_t(s.rank);
    double v = 0.0;
    for (int k = 0; k < s.rank; ++k) {
        const float* b = s.basis.data() + std::size_t(k) * s.cells;
        double r = 0.0;
        for (int j = 0; j < 8; ++j) r += b[t.index[j]] * t.weight[j];
        v += w[k] * r;
    }
    return v;
}

double combine_direct(const SpectralBasis& s, std::size_t c, const NpfModel::Lookup::Bilinear& b) {
    const float* w = s.weights.data() + c * std::size_t(s.rank);
    double v = 0.0;
    for (int k = 0; k < s.rank; ++k) v += w[k] * interpolate(s.basis.data() + std::size_t(k) * s.cells, b);
    return v > 0.0 ? v : 0.0;
}

// ---- Validation ------------------------------------------------------------------------------

// Finite and within kMaxMaterialValue: a finite but absurd value (3e38) would overflow the
// sums and squares of every later computation (albedo, fit errors).
template <typename T>
bool all_finite(const std::vector<T>& v) {
    return std::all_of(v.begin(), v.end(), [](T x) { return std::isfinite(x) && std::fabs(double(x)) <= kMaxMaterialValue; });
}

void check_basis(const SpectralBasis& s, const char* name, std::size_t cells, std::size_t channels,
                 const std::string& source) {
    const std::string n(name);
    if (s.cells != cells) {
        throw Error(source,
                    n + " basis has " + std::to_string(s.cells) + " cells, its grid has " + std::to_string(cells));
    }
    const std::size_t max_rank = std::min(cells, channels);
    if (s.rank < 1 || std::size_t(s.rank) > max_rank) {
        throw Error(source, n + " rank " + std::to_string(s.rank) + " is outside 1.." + std::to_string(max_rank) +
                                " (min of " + std::to_string(cells) + " cells and " + std::to_string(channels) +
                                " channels)");
    }
    if (s.basis.size() != std::size_t(s.rank) * cells) throw Error(source, n + " basis has the wrong number of values");
    if (s.weights.size() != std::size_t(s.rank) * channels) {
        throw Error(source, n + " weights have the wrong number of values");
    }
    if (std::size_t(s.rank) * cells > NpfModel::kMaxBasisValues) {
        throw Error(source, n + " has " + std::to_string(std::size_t(s.rank) * cells) + " basis values (rank x cells), more than " +
                                std::to_string(NpfModel::kMaxBasisValues));
    }
    if (!all_finite(s.basis)) throw Error(source, "non-finite or out-of-range value in the " + n + " basis");
    if (!all_finite(s.weights)) throw Error(source, "non-finite or out-of-range value in the " + n + " weights");
    if (s.singular_values.size() != max_rank) {
        throw Error(source, n + " has " + std::to_string(s.singular_values.size()) + " singular values, expected " +
                                std::to_string(max_rank));
    }
    for (std::size_t k = 0; k < s.singular_values.size(); ++k) {
        const double v = s.singular_values[k];
        if (!std::isfinite(v) || v < 0.0 || (k > 0 && v > s.singular_values[k - 1])) {
            throw Error(source, n + " singular values must be finite, non-negative and descending");
        }
    }
    if (!(s.kept_ratio >= 0.0 && s.kept_ratio <= 1.0)) {
        throw Error(source, n + " kept ratio " + std::to_string(s.kept_ratio) + " is outside [0, 1]");
    }
}

}  // namespace

double SpectralBasis::at(std::size_t channel, std::size_t cell) const {
    const float* w = weights.data() + channel * std::size_t(rank);
    double v = 0.0;
    for (int k = 0; k < rank; ++k) v += double(w[k]) * basis[std::size_t(k) * cells + cell];
    return v;
}

double NpfModel::g_at_horizon(std::size_t c, int column) const {
    if (g_theta < 2) return G.at(c, std::size_t(column));
    const std::size_t last = std::size_t(g_theta - 1) * std::size_t(g_phi) + std::size_t(column);
    const std::size_t prev = std::size_t(g_theta - 2) * std::size_t(g_phi) + std::size_t(column);
    return equation::g_at_horizon(G.at(c, last), G.at(c, prev));
}

bool NpfModel::g_open_at_horizon() const {
    if (g_theta < 2) return false;
    for (std::size_t c = 0; c < channel_count(); ++c) {
        if (!(rho_s[c] > 0.f)) continue;
        for (int j = 0; j < g_phi; ++j) {
            if (g_at_horizon(c, j) > 0.0) return true;
        }
    }
    return false;
}

int NpfModel::close_g_at_horizon() {
    if (g_theta < 2) return 0;
    int changed = 0;
    const std::size_t last_row = std::size_t(g_theta - 1) * std::size_t(g_phi);
    const std::size_t prev_row = std::size_t(g_theta - 2) * std::size_t(g_phi);
    for (int j = 0; j < g_phi; ++j) {
        const std::size_t last = last_row + std::size_t(j), prev = prev_row + std::size_t(j);
        double scale = 1.0;
        for (std::size_t c = 0; c < channel_count(); ++c) {
            if (!(rho_s[c] > 0.f) || !(g_at_horizon(c, j) > 0.0)) continue;
            const double g_last = G.at(c, last), g_prev = G.at(c, prev);
            // A hair below the closing scale, so that float rounding of the scaled basis cannot
            // leave the line's end above 0.
            scale = std::min(scale, equation::g_closing_scale(g_last, g_prev) * (1.0 - 1e-6));
        }
        if (scale < 1.0) {
            for (int k = 0; k < G.rank; ++k) G.basis[std::size_t(k) * G.cells + last] *= float(scale);
            ++changed;
        }
    }
    return changed;
}

void NpfModel::validate(const std::string& source) const {
    // Generous bounds that keep every size product far from overflow.
    constexpr int kMaxGrid = 1 << 16;
    auto check_grid = [&](int n, const char* name) {
        if (n < 1 || n > kMaxGrid) {
            throw Error(source,
                        std::string(name) + " = " + std::to_string(n) + " is outside 1.." + std::to_string(kMaxGrid));
        }
    };
    check_grid(d_theta, "D theta size");
    check_grid(d_phi, "D phi size");
    check_grid(f_theta, "F theta size");
    check_grid(g_theta, "G theta size");
    check_grid(g_phi, "G phi size");

    const std::size_t C = channel_count();
    if (C == 0) throw Error(source, "no channels");
    if (channels.size() != C) {
        throw Error(source, "the channel list names " + std::to_string(channels.size()) + " channels, the tables hold " +
                                std::to_string(C));
    }
    if (!channels.is_rgb()) {
        const std::vector<float>& w = channels.wavelengths();
        for (std::size_t k = 0; k < w.size(); ++k) {
            if (!std::isfinite(w[k]) || w[k] <= 0.f || (k > 0 && !(w[k] > w[k - 1]))) {
                throw Error(source, "wavelengths must be positive, finite and strictly ascending");
            }
        }
    }
    if (rho_s.size() != C) {
        throw Error(source, "rho_s has " + std::to_string(rho_s.size()) + " values, expected " + std::to_string(C));
    }
    if (F.size() != C * std::size_t(f_theta)) throw Error(source, "F has the wrong number of values");
    auto check_non_negative = [&](const std::vector<float>& v, const char* name) {
        for (float x : v) {
            if (!std::isfinite(x)) throw Error(source, std::string("non-finite value in ") + name);
            if (x < 0.f) throw Error(source, std::string("negative value in ") + name);
            if (x > kMaxMaterialValue) throw Error(source, std::string("out-of-range value in ") + name);
        }
    };
    check_non_negative(rho_d, "rho_d");
    check_non_negative(rho_s, "rho_s");
    check_non_negative(F, "F");
    for (const auto& [name, cells] : {std::pair<const char*, std::size_t>{"D", std::size_t(d_theta) * std::size_t(d_phi)},
                                      {"G", std::size_t(g_theta) * std::size_t(g_phi)}}) {
        if (cells > kMaxTableCells) {
            throw Error(source, std::string(name) + " has " + std::to_string(cells) + " cells, more than " +
                                    std::to_string(kMaxTableCells));
        }
    }
    check_basis(D, "D", std::size_t(d_theta) * std::size_t(d_phi), C, source);
    // The sampler's luminance-averaged D clamps every channel's D at 0 in every cell, so it costs
    // channels x rank x cells: bounded, so that no file within the other caps takes minutes to open.
    if (double(C) * double(D.rank) * double(D.cells) > kMaxSamplerWork) {
        throw Error(source, "D's " + std::to_string(C) + " channels x rank " + std::to_string(D.rank) + " x " +
                                std::to_string(D.cells) + " cells are more than the 2^32 a sampler is built from (docs/format.md sec. 8)");
    }
    check_basis(G, "G", std::size_t(g_theta) * std::size_t(g_phi), C, source);
    if (has_detail()) {
        check_grid(detail_grid.theta_h, "detail theta_h size");
        check_grid(detail_grid.theta_d, "detail theta_d size");
        check_grid(detail_grid.phi_d, "detail phi_d size");
        if (detail_grid.cells() > kMaxDetailCells) {
            throw Error(source, "the detail grid has " + std::to_string(detail_grid.cells()) + " cells, more than " +
                                    std::to_string(kMaxDetailCells));
        }
        check_basis(detail, "detail", detail_grid.cells(), C, source);
    } else if (detail.rank != 0 || !detail.basis.empty() || !detail.weights.empty()) {
        throw Error(source, "detail values without a detail grid");
    }
    // Each value under the cap is not enough: five factors of 9e11 multiply to 6e59.
    check_value_bound(source, value_bound(), has_detail() ? "rho_d + rho_s x D x F x G x G + detail" : "rho_d + rho_s x D x F x G x G");
}

bool NpfModel::half_vector(const Vec3& wi, const Vec3& wo, HalfVector& h) const {
    if (!pair_in_domain(wi, wo)) return false;
    h.cos_i = wi.z;
    h.cos_o = wo.z;
    half_vector_angles(wi.x, wi.y, wi.z, wo.x, wo.y, wo.z, d_phi > 1, h.theta_h, h.u_h, h.phi_h, h.cos_d);
    return true;
}

bool NpfModel::prepare(const Vec3& wi, const Vec3& wo, Lookup& at, bool project_bases) const {
    if (!pair_in_domain(wi, wo)) return false;
    PairAngles a;
    pair_angles(wi.x, wi.y, wi.z, wo.x, wo.y, wo.z, angle_needs(), a);
    position(a, at, project_bases);
    return true;
}

void NpfModel::position(const PairAngles& a, Lookup& at, bool project_bases) const {
    at.cos_i = a.cos_i;
    at.cos_o = a.cos_o;
    at.inv_cos_product = a.inv_cos_product;
    at.theta_h = a.theta_h;
    at.phi_h = a.phi_h;
    at.u_h = a.u_h;
    at.cos_d = a.cos_d;
    const Lerp d_row = equation::d_row(at.u_h, d_theta);
    const Lerp d_col = equation::column(a.phi_h, d_phi);
    at.d_row = d_row.i0 + d_row.t;
    at.d_col = d_col.i0 + d_col.t;
    at.d = bilinear(d_row, d_col, d_phi);
    const Lerp f = equation::f_row(a.theta_d, f_theta);
    at.f0 = f.i0;
    at.f1 = f.i1;
    at.f_t = f.t;
    at.g_i = g_position(a.theta_gi, a.phi_gi, g_theta, g_phi, at.g_i_row, at.g_i_col);
    at.g_o = g_position(a.theta_go, a.phi_go, g_theta, g_phi, at.g_o_row, at.g_o_col);
    if (has_detail()) {
        at.r_at = detail_position(detail_grid, at.u_h, a.theta_d, a.phi_d);
        at.r = trilinear(detail_grid, at.r_at);
    }
    at.cached = project_bases && D.rank <= kInlineRank && G.rank <= kInlineRank && detail.rank <= kInlineRank;
    if (at.cached) {
        project(D, at.d, at.d_basis);
        project(G, at.g_i, at.g_i_basis);
        project(G, at.g_o, at.g_o_basis);
        if (detail.rank > 0) project(detail, at.r, at.r_basis);
    }
}

namespace {

// Channel c's value without the detail layer, the tables combined corner by corner.
double base_uncached(const NpfModel& m, const NpfModel::Lookup& at, std::size_t c) {
    const double d = combine_direct(m.D, c, at.d);
    const double gi = combine_direct(m.G, c, at.g_i);
    const double go = combine_direct(m.G, c, at.g_o);
    const float* f = m.F.data() + c * std::size_t(m.f_theta);
    const double fv = f[at.f0] * (1 - at.f_t) + f[at.f1] * at.f_t;
    return equation::value(m.rho_d[c], m.rho_s[c], d, fv, gi, go, at.inv_cos_product);
}

}  // namespace

double NpfModel::value_uncached(const Lookup& at, std::size_t c) const {
    const double base = base_uncached(*this, at, c);
    if (detail.rank == 0) return base;
    return equation::with_detail(base, combine_detail(detail, c, at.r));
}

void NpfModel::values(const Lookup& at, double* out, double* base) const {
    const std::size_t C = channel_count();
    if (!at.cached) {
        for (std::size_t c = 0; c < C; ++c) {
            const double v = base_uncached(*this, at, c);
            if (base) base[c] = v;
            out[c] = detail.rank == 0 ? v : equation::with_detail(v, combine_detail(detail, c, at.r));
        }
        return;
    }
    // value()'s sums term for term, a block of channels at a time, the channel loops innermost.
    // The first term is added to 0.0 as value() does (-0.0 becomes 0.0), not stored over a
    // zeroed array: zeroing four arrays per block compiled to memset calls, a quarter of the time.
    constexpr std::size_t kBlock = 64;
    const double one_minus_t = 1 - at.f_t;
    const auto combine = [](const SpectralBasis& s, std::size_t c0, std::size_t n, const double* basis, double* sums) {
        const std::size_t rank = std::size_t(s.rank);
        const float* w = s.weights.data() + c0 * rank;
        if (rank == 0) {
            for (std::size_t j = 0; j < n; ++j) sums[j] = 0.0;
            return;
        }
        for (std::size_t j = 0; j < n; ++j) sums[j] = 0.0 + w[j * rank] * basis[0];
        for (std::size_t k = 1; k < rank; ++k) {
            for (std::size_t j = 0; j < n; ++j) sums[j] += w[j * rank + k] * basis[k];
        }
    };
    for (std::size_t c0 = 0; c0 < C; c0 += kBlock) {
        const std::size_t n = std::min(kBlock, C - c0);
        double d[kBlock], gi[kBlock], go[kBlock], r[kBlock];
        combine(D, c0, n, at.d_basis, d);
        combine(G, c0, n, at.g_i_basis, gi);
        combine(G, c0, n, at.g_o_basis, go);
        if (detail.rank > 0) combine(detail, c0, n, at.r_basis, r);
        const float* f = F.data() + c0 * std::size_t(f_theta);
        for (std::size_t j = 0; j < n; ++j) {
            const float* fc = f + j * std::size_t(f_theta);
            const double fv = fc[at.f0] * one_minus_t + fc[at.f1] * at.f_t;
            const double v = equation::value(rho_d[c0 + j], rho_s[c0 + j], d[j], fv, gi[j], go[j], at.inv_cos_product);
            if (base) base[c0 + j] = v;
            out[c0 + j] = detail.rank == 0 ? v : equation::with_detail(v, r[j]);
        }
    }
}

void NpfModel::eval_all(const Vec3& wi, const Vec3& wo, double* out) const {
    Lookup at;
    const std::size_t C = channel_count();
    if (!prepare(wi, wo, at)) {
        std::fill(out, out + C, 0.0);
        return;
    }
    values(at, out);
}

double NpfModel::eval(std::size_t c, const Vec3& wi, const Vec3& wo) const {
    Lookup at;
    return prepare(wi, wo, at) ? value(at, c) : 0.0;
}

}  // namespace npf
