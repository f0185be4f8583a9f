// The passes of BlockFit (included by block_fit.h). Each pass streams the samples once; inner
// loops run over the L lanes with no dependence between lanes, which the compiler vectorises.
#pragma once

#include "parallel.h"

#include <npf/core/vec.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace npf::fit_detail {

// G at both directions of sample s for every lane: linear in theta between the owner cell and
// its neighbour (SampleSet), never below 0.
template <int L>
inline void interpolate_g(const std::vector<float>& G, const SampleSet& s, std::uint32_t k, float* gi, float* go) {
    const float* __restrict a = &G[std::size_t(s.gi[k]) * L];
    const float* __restrict a2 = &G[std::size_t(s.gi2[k]) * L];
    const float* __restrict b = &G[std::size_t(s.go[k]) * L];
    const float* __restrict b2 = &G[std::size_t(s.go2[k]) * L];
    const float ti = s.ti[k], to = s.to[k];
    for (int l = 0; l < L; ++l) {
        gi[l] = std::max(0.f, a[l] + ti * (a2[l] - a[l]));
        go[l] = std::max(0.f, b[l] + to * (b2[l] - b[l]));
    }
}

template <int L>
BlockFit<L>::BlockFit(const SampleSet& samples, const AwlsOptions& options, int threads)
    : m_s(samples),
      m_o(options),
      m_split(balanced_cell_split(samples, kSlices)),
      m_threads(std::clamp(threads, 1, kSlices)),
      m_trace(std::getenv("NPF_AWLS_TRACE") != nullptr) {
    m_rho.resize(samples.size() * L);
    m_w.resize(samples.size() * L);
    m_cell.resize(samples.d_cells * 3 * L);
    m_g_acc.resize(std::size_t(kSlices));
    m_f_acc.resize(std::size_t(kSlices));
}

template <int L>
template <typename Body>
void BlockFit<L>::for_each_slice(Body body) const {
    parallel_slices(std::size_t(kSlices), m_threads, [&](int, std::size_t b, std::size_t e) {
        for (std::size_t slice = b; slice < e; ++slice) body(int(slice));
    });
}

template <int L>
std::size_t BlockFit<L>::resample(const Brdf& source, const Channels& channels) {
    const ChannelQuery query = source.query(channels);
    const std::size_t n = query.size();
    std::vector<std::size_t> invalid(std::size_t(m_threads), 0);
    parallel_slices(m_s.size(), m_threads, [&](int t, std::size_t b, std::size_t e) {
        std::vector<float> v(n);
        for (std::size_t s = b; s < e; ++s) {
            const float* d = &m_s.directions[6 * s];
            source.eval_cos(Vec3(d[0], d[1], d[2]), Vec3(d[3], d[4], d[5]), query, v.data());
            float* rho = &m_rho[s * L];
            float* w = &m_w[s * L];
            for (int l = 0; l < L; ++l) {
                const float value = v[std::min(std::size_t(l), n - 1)] / d[5];
                double weight = m_s.geometry[s];
                if (!std::isfinite(value)) {
                    if (std::size_t(l) < n) ++invalid[std::size_t(t)];
                    rho[l] = 0.f;
                    w[l] = 0.f;
                    continue;
                }
                if (m_o.compressive_power != 0.0) {
                    weight *= std::pow(std::max(0.0, double(value)) + m_o.compressive_epsilon, -m_o.compressive_power);
                }
                rho[l] = value;
                w[l] = float(weight);
            }
        }
    });
    m_sw.fill(0.0);
    m_swr.fill(0.0);
    m_swrr.fill(0.0);
    for (std::size_t s = 0; s < m_s.size(); ++s) {
        for (int l = 0; l < L; ++l) {
            const double w = m_w[s * L + l], r = m_rho[s * L + l];
            m_sw[l] += w;
            m_swr[l] += w * r;
            m_swrr[l] += w * r * r;
        }
    }
    std::size_t count = 0;
    for (std::size_t c : invalid) count += c;
    return count;
}

template <int L>
BlockFactors<L> BlockFit<L>::cold_start() const {
    BlockFactors<L> f;
    f.D.assign(m_s.d_cells * L, 1.f);
    f.F.assign(m_s.f_cells * L, 1.f);
    f.G.assign(m_s.g_cells * L, 1.f);
    f.rho_d.fill(0.0);
    f.rho_s.fill(1.0);
    return f;
}

template <int L>
BlockFactors<L> BlockFit<L>::warm_start(const BlockFactors<L>& from, int lane) const {
    BlockFactors<L> f;
    auto broadcast = [&](const std::vector<float>& src, std::vector<float>& dst) {
        dst.resize(src.size());
        for (std::size_t k = 0; k < src.size() / L; ++k) std::fill_n(&dst[k * L], L, src[k * L + std::size_t(lane)]);
    };
    broadcast(from.D, f.D);
    broadcast(from.F, f.F);
    broadcast(from.G, f.G);
    f.rho_d.fill(from.rho_d[std::size_t(lane)]);
    f.rho_s.fill(std::max(from.rho_s[std::size_t(lane)], 1e-6));  // a zero rho_s would freeze D, F, G
    return f;
}

// D and rho_d together: a constant rho_d and the tail of D explain the same samples, and
// alternating between them converges slowly. Every sample lies in exactly one D cell, so the
// joint least-squares problem has a closed form: eliminate each D_k, solve the scalar equation
// for rho_d, then back-substitute (both clamped at 0).
template <int L>
void BlockFit<L>::update_d_and_diffuse(BlockFactors<L>& f) {
    for_each_slice([&](int t) {
        float rs[L];
        for (int l = 0; l < L; ++l) rs[l] = float(f.rho_s[std::size_t(l)]);
        for (std::size_t k = m_split[std::size_t(t)]; k < m_split[std::size_t(t) + 1]; ++k) {
            float wb[L] = {}, wbb[L] = {}, wrb[L] = {};
            for (std::uint32_t r = m_s.cell_ring_begin[k]; r < m_s.cell_ring_begin[k + 1]; ++r) {
                const float* __restrict F = &f.F[std::size_t(m_s.ring_f[r]) * L];
                float rsf[L];
                for (int l = 0; l < L; ++l) rsf[l] = rs[l] * F[l];
                for (std::uint32_t s = m_s.ring_begin[r]; s < m_s.ring_begin[r + 1]; ++s) {
                    float Gi[L], Go[L];
                    interpolate_g<L>(f.G, m_s, s, Gi, Go);
                    const float c = m_s.inv_cc[s];
                    const float* __restrict rho = &m_rho[std::size_t(s) * L];
                    const float* __restrict w = &m_w[std::size_t(s) * L];
                    for (int l = 0; l < L; ++l) {
                        const float b = rsf[l] * Gi[l] * Go[l] * c;
                        const float w_b = w[l] * b;
                        wb[l] += w_b;
                        wbb[l] += w_b * b;
                        wrb[l] += w_b * rho[l];
                    }
                }
            }
            double* cell = &m_cell[k * 3 * L];
            for (int l = 0; l < L; ++l) cell[l] = wb[l], cell[L + l] = wbb[l], cell[2 * L + l] = wrb[l];
        }
    });
    for (int l = 0; l < L; ++l) {
        double num = m_swr[l], den = m_sw[l];
        for (std::size_t k = 0; k < m_s.d_cells; ++k) {
            const double* cell = &m_cell[k * 3 * L];
            if (!(cell[L + l] > 1e-30)) continue;
            num -= cell[l] * cell[2 * L + l] / cell[L + l];
            den -= cell[l] * cell[l] / cell[L + l];
        }
        const double rho_d = den > 1e-9 * m_sw[l] ? std::max(0.0, num / den) : 0.0;
        f.rho_d[std::size_t(l)] = rho_d;
        for (std::size_t k = 0; k < m_s.d_cells; ++k) {
            const double* cell = &m_cell[k * 3 * L];
            if (cell[L + l] > 1e-30) f.D[k * L + l] = float(std::max(0.0, (cell[2 * L + l] - rho_d * cell[l]) / cell[L + l]));
        }
    }
}

template <int L>
void BlockFit<L>::update_f(BlockFactors<L>& f) {
    for_each_slice([&](int t) {
        std::vector<double>& acc = m_f_acc[std::size_t(t)];
        acc.assign(2 * m_s.f_cells * L, 0.0);
        float rd[L], rs[L];
        for (int l = 0; l < L; ++l) rd[l] = float(f.rho_d[std::size_t(l)]), rs[l] = float(f.rho_s[std::size_t(l)]);
        for (std::size_t k = m_split[std::size_t(t)]; k < m_split[std::size_t(t) + 1]; ++k) {
            float rsd[L];
            for (int l = 0; l < L; ++l) rsd[l] = rs[l] * f.D[k * L + l];
            for (std::uint32_t r = m_s.cell_ring_begin[k]; r < m_s.cell_ring_begin[k + 1]; ++r) {
                float num[L] = {}, den[L] = {};
                for (std::uint32_t s = m_s.ring_begin[r]; s < m_s.ring_begin[r + 1]; ++s) {
                    float Gi[L], Go[L];
                    interpolate_g<L>(f.G, m_s, s, Gi, Go);
                    const float c = m_s.inv_cc[s];
                    const float* __restrict rho = &m_rho[std::size_t(s) * L];
                    const float* __restrict w = &m_w[std::size_t(s) * L];
                    for (int l = 0; l < L; ++l) {
                        const float b = rsd[l] * Gi[l] * Go[l] * c;
                        const float w_b = w[l] * b;
                        num[l] += w_b * (rho[l] - rd[l]);
                        den[l] += w_b * b;
                    }
                }
                double* a = &acc[std::size_t(m_s.ring_f[r]) * 2 * L];
                for (int l = 0; l < L; ++l) a[l] += num[l], a[L + l] += den[l];
            }
        }
    });
    for (std::size_t j = 0; j < m_s.f_cells; ++j) {
        for (int l = 0; l < L; ++l) {
            double num = 0.0, den = 0.0;
            for (const std::vector<double>& acc : m_f_acc) num += acc[j * 2 * L + l], den += acc[j * 2 * L + L + l];
            if (den > 1e-30) f.F[j * L + l] = float(std::max(0.0, num / den));
        }
    }
}

// G appears twice per sample: each sample updates the cell of wi with the other copy held at
// its previous value, and the cell of wo likewise (reciprocity); the result is damped by half,
// the diagonal Gauss-Newton step for a factor that enters squared, which keeps the alternation
// from oscillating between the two copies.
template <int L>
void BlockFit<L>::update_g(BlockFactors<L>& f) {
    for_each_slice([&](int t) {
        std::vector<float>& acc = m_g_acc[std::size_t(t)];
        acc.assign(2 * m_s.g_cells * L, 0.f);
        float rd[L], rs[L];
        for (int l = 0; l < L; ++l) rd[l] = float(f.rho_d[std::size_t(l)]), rs[l] = float(f.rho_s[std::size_t(l)]);
        for (std::size_t k = m_split[std::size_t(t)]; k < m_split[std::size_t(t) + 1]; ++k) {
            float rsd[L];
            for (int l = 0; l < L; ++l) rsd[l] = rs[l] * f.D[k * L + l];
            for (std::uint32_t r = m_s.cell_ring_begin[k]; r < m_s.cell_ring_begin[k + 1]; ++r) {
                const float* __restrict F = &f.F[std::size_t(m_s.ring_f[r]) * L];
                float rsdf[L];
                for (int l = 0; l < L; ++l) rsdf[l] = rsd[l] * F[l];
                for (std::uint32_t s = m_s.ring_begin[r]; s < m_s.ring_begin[r + 1]; ++s) {
                    float Gi[L], Go[L];
                    interpolate_g<L>(f.G, m_s, s, Gi, Go);
                    const float c = m_s.inv_cc[s];
                    const float* __restrict rho = &m_rho[std::size_t(s) * L];
                    const float* __restrict w = &m_w[std::size_t(s) * L];
                    float common[L], wa[L];
                    for (int l = 0; l < L; ++l) {
                        common[l] = rsdf[l] * c;
                        wa[l] = w[l] * (rho[l] - rd[l]);
                    }
                    // Each direction updates the cell it lies in (its owner), the interpolated
                    // value's shape within the cell taken from the current table.
                    const float* __restrict Gi_owner = &f.G[std::size_t(m_s.gi[s]) * L];
                    const float* __restrict Go_owner = &f.G[std::size_t(m_s.go[s]) * L];
                    float* __restrict ai = &acc[std::size_t(m_s.gi[s]) * 2 * L];
                    for (int l = 0; l < L; ++l) {
                        const float shape = Gi_owner[l] > 0.f ? Gi[l] / Gi_owner[l] : 1.f;
                        const float b = common[l] * Go[l] * shape;
                        ai[l] += wa[l] * b;
                        ai[L + l] += w[l] * b * b;
                    }
                    float* __restrict ao = &acc[std::size_t(m_s.go[s]) * 2 * L];
                    for (int l = 0; l < L; ++l) {
                        const float shape = Go_owner[l] > 0.f ? Go[l] / Go_owner[l] : 1.f;
                        const float b = common[l] * Gi[l] * shape;
                        ao[l] += wa[l] * b;
                        ao[L + l] += w[l] * b * b;
                    }
                }
            }
        }
    });
    for (std::size_t j = 0; j < m_s.g_cells; ++j) {
        for (int l = 0; l < L; ++l) {
            double num = 0.0, den = 0.0;
            for (const std::vector<float>& acc : m_g_acc) num += acc[j * 2 * L + l], den += acc[j * 2 * L + L + l];
            if (den > 1e-30) f.G[j * L + l] = float(0.5 * (f.G[j * L + l] + std::max(0.0, num / den)));
        }
    }
}

// rho_d and rho_s jointly: the model is rho_d + rho_s m with m = D F G G / cc fixed, a
// two-parameter weighted least-squares problem solved in closed form (with the non-negativity
// constraints), whose sums also give the error.
template <int L>
std::array<double, L> BlockFit<L>::update_diffuse_specular(BlockFactors<L>& f, bool solve) {
    std::vector<std::array<double, 3 * L>> sums(static_cast<std::size_t>(kSlices));
    for_each_slice([&](int t) {
        std::array<double, 3 * L>& out = sums[std::size_t(t)];
        out.fill(0.0);
        for (std::size_t k = m_split[std::size_t(t)]; k < m_split[std::size_t(t) + 1]; ++k) {
            const float* Dk = &f.D[k * L];
            for (std::uint32_t r = m_s.cell_ring_begin[k]; r < m_s.cell_ring_begin[k + 1]; ++r) {
                const float* __restrict F = &f.F[std::size_t(m_s.ring_f[r]) * L];
                float df[L], wm[L] = {}, wmm[L] = {}, wrm[L] = {};
                for (int l = 0; l < L; ++l) df[l] = Dk[l] * F[l];
                for (std::uint32_t s = m_s.ring_begin[r]; s < m_s.ring_begin[r + 1]; ++s) {
                    float Gi[L], Go[L];
                    interpolate_g<L>(f.G, m_s, s, Gi, Go);
                    const float c = m_s.inv_cc[s];
                    const float* __restrict rho = &m_rho[std::size_t(s) * L];
                    const float* __restrict w = &m_w[std::size_t(s) * L];
                    for (int l = 0; l < L; ++l) {
                        const float m = df[l] * Gi[l] * Go[l] * c;
                        const float w_m = w[l] * m;
                        wm[l] += w_m;
                        wmm[l] += w_m * m;
                        wrm[l] += w_m * rho[l];
                    }
                }
                for (int l = 0; l < L; ++l) out[l] += wm[l], out[L + l] += wmm[l], out[2 * L + l] += wrm[l];
            }
        }
    });
    std::array<double, L> error{};
    for (int l = 0; l < L; ++l) {
        double swm = 0.0, swmm = 0.0, swrm = 0.0;
        for (const auto& s : sums) swm += s[l], swmm += s[L + l], swrm += s[2 * L + l];
        const double sw = m_sw[l], swr = m_swr[l];
        double rd = 0.0, rs = 0.0;
        if (!solve) {
            rd = f.rho_d[std::size_t(l)], rs = f.rho_s[std::size_t(l)];
            const double e = m_swrr[l] - 2.0 * rd * swr - 2.0 * rs * swrm + rd * rd * sw + 2.0 * rd * rs * swm + rs * rs * swmm;
            error[std::size_t(l)] = std::max(0.0, e);
            continue;
        }
        const double det = sw * swmm - swm * swm;
        if (det > 1e-12 * sw * swmm) {
            rd = (swr * swmm - swm * swrm) / det;
            rs = (sw * swrm - swm * swr) / det;
        }
        if (!(det > 1e-12 * sw * swmm) || rd < 0.0 || rs < 0.0) {
            // The constrained optimum lies on a boundary: try each, keep the better.
            const double rs_only = swmm > 0.0 ? std::max(0.0, swrm / swmm) : 0.0;
            const double rd_only = sw > 0.0 ? std::max(0.0, swr / sw) : 0.0;
            const double e_rs = m_swrr[l] - 2.0 * rs_only * swrm + rs_only * rs_only * swmm;
            const double e_rd = m_swrr[l] - 2.0 * rd_only * swr + rd_only * rd_only * sw;
            if (e_rs < e_rd) rd = 0.0, rs = rs_only;
            else rd = rd_only, rs = 0.0;
        }
        f.rho_d[std::size_t(l)] = rd;
        f.rho_s[std::size_t(l)] = rs;
        const double e = m_swrr[l] - 2.0 * rd * swr - 2.0 * rs * swrm + rd * rd * sw + 2.0 * rd * rs * swm + rs * rs * swmm;
        error[std::size_t(l)] = std::max(0.0, e);
    }
    return error;
}

// Fixes the scale ambiguities without changing the model: projected area of D = 1, G = 1 at
// normal incidence, F = 1 at theta_d = 0.
template <int L>
void BlockFit<L>::normalise(BlockFactors<L>& f) const {
    const RusinkiewiczGrid& grid = m_o.grid;
    const double du = 1.0 / grid.theta_h, dphi = 2.0 * kPiD / grid.phi_h;
    std::array<double, L> area{};
    for (int i = 0; i < grid.theta_h; ++i) {
        const double u = (i + 0.5) * du, th = grid.theta_h_at(i);
        const double cell = std::cos(th) * std::sin(th) * kPiD * u * du * dphi;
        for (int j = 0; j < grid.phi_h; ++j) {
            const float* d = &f.D[(std::size_t(i) * std::size_t(grid.phi_h) + std::size_t(j)) * L];
            for (int l = 0; l < L; ++l) area[std::size_t(l)] += d[l] * cell;
        }
    }
    std::array<double, L> g0{};
    for (int j = 0; j < m_o.g_phi; ++j) {
        for (int l = 0; l < L; ++l) g0[std::size_t(l)] += f.G[std::size_t(j) * L + std::size_t(l)] / m_o.g_phi;
    }
    for (int l = 0; l < L; ++l) {
        const std::size_t ul = std::size_t(l);
        const double a = area[ul], g = g0[ul], f0 = f.F[ul];
        if (!(a > 0.0) || !(g > 0.0) || !(f0 > 0.0) || !std::isfinite(a * g * f0)) continue;
        for (std::size_t k = 0; k < m_s.d_cells; ++k) f.D[k * L + ul] = float(f.D[k * L + ul] / a);
        // G <= 1 (= G at normal incidence): masking only takes light away. It also closes the
        // near-symmetry G -> G s, F -> F / s^2 in the direction where G would grow past 1.
        const double bound = m_o.bound_g ? 1.0 : INFINITY;
        for (std::size_t k = 0; k < m_s.g_cells; ++k) f.G[k * L + ul] = float(std::min(bound, f.G[k * L + ul] / g));
        for (std::size_t k = 0; k < m_s.f_cells; ++k) f.F[k * L + ul] = float(f.F[k * L + ul] / f0);
        f.rho_s[ul] *= a * g * g * f0;
    }
}

// The NPF model has a near-symmetry that the data hardly constrain: G -> G s(theta), F -> F /
// s(theta_d)^2 leaves rho_s D F G G / cc unchanged on the specular ridge (theta_h = 0, where
// theta_i = theta_o = theta_d) and changes it only to second order in theta_h off it, which D
// then absorbs. Where the alternation ends on that ridge depends on where it starts; starting G
// from Smith's masking of the data's own D puts it at the microfacet theory's member, so that
// the factors mean what their names say (and edits of F or D behave).
template <int L>
void BlockFit<L>::smith_g_from_d(BlockFactors<L>& f) const {
    const RusinkiewiczGrid& grid = m_o.grid;
    // The D cells as directions with solid angles (isotropic D: spread over 64 azimuths).
    const int azimuths = grid.phi_h == 1 ? 64 : grid.phi_h;
    struct Cell { double x, y, z, solid_angle; std::size_t index; };
    std::vector<Cell> cells;
    const double du = 1.0 / grid.theta_h, dphi = 2.0 * kPiD / azimuths;
    for (int i = 0; i < grid.theta_h; ++i) {
        const double u = (i + 0.5) * du, th = grid.theta_h_at(i);
        for (int j = 0; j < azimuths; ++j) {
            const double ph = (j + 0.5) * dphi;
            const std::size_t index = std::size_t(i) * std::size_t(grid.phi_h) + (grid.phi_h == 1 ? 0 : std::size_t(j));
            cells.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th), std::sin(th) * kPiD * u * du * dphi, index});
        }
    }
    // D's projected area, so that sigma(normal) = 1 whatever D's current scale.
    std::array<double, L> area{};
    for (const Cell& c : cells) {
        for (int l = 0; l < L; ++l) area[std::size_t(l)] += c.z * c.solid_angle * f.D[c.index * L + std::size_t(l)];
    }
    std::vector<float> G(f.G.size());
    parallel_slices(m_s.g_cells, m_threads, [&](int, std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            const int row = int(k / std::size_t(m_o.g_phi)), col = int(k % std::size_t(m_o.g_phi));
            const double t = (row + 0.5) * 0.5 * kPiD / m_o.g_theta, p = m_o.g_phi == 1 ? 0.0 : (col + 0.5) * 2.0 * kPiD / m_o.g_phi;
            const double wx = std::sin(t) * std::cos(p), wy = std::sin(t) * std::sin(p), wz = std::cos(t);
            double sigma[L] = {};
            for (const Cell& c : cells) {
                const double proj = wx * c.x + wy * c.y + wz * c.z;
                if (proj <= 0.0) continue;
                const float* d = &f.D[c.index * L];
                const double a = proj * c.solid_angle;
                for (int l = 0; l < L; ++l) sigma[l] += a * d[l];
            }
            for (int l = 0; l < L; ++l) {
                const double projected = sigma[l] / area[std::size_t(l)];
                G[k * L + std::size_t(l)] = projected > 0.0 ? float(wz / projected) : f.G[k * L + std::size_t(l)];
            }
        }
    });
    f.G = std::move(G);
}

// Moves lane l of `y` into `f`.
template <int L>
void copy_lane(const BlockFactors<L>& y, BlockFactors<L>& f, int l) {
    for (std::size_t k = std::size_t(l); k < f.D.size(); k += L) f.D[k] = y.D[k];
    for (std::size_t k = std::size_t(l); k < f.F.size(); k += L) f.F[k] = y.F[k];
    for (std::size_t k = std::size_t(l); k < f.G.size(); k += L) f.G[k] = y.G[k];
    f.rho_d[std::size_t(l)] = y.rho_d[std::size_t(l)];
    f.rho_s[std::size_t(l)] = y.rho_s[std::size_t(l)];
}

// AWLS sweeps with line-search extrapolation (Bro 1998; Rajih et al. 2008): plain alternation
// crawls along the valleys where D, F and G trade scale with one another (the "swamps" of
// alternating least squares), moving a little further in the same direction each sweep. After
// each sweep the fit tries the point `step` times the last move further on, which costs one
// more pass; a lane keeps it when its error is lower, and its step then grows, otherwise shrinks.
template <int L>
template <typename Progress>
int BlockFit<L>::run(BlockFactors<L>& f, bool cold, std::array<double, L>& error, Progress progress) {
    constexpr int kWindow = 10;
    std::vector<std::array<double, L>> history;
    std::array<double, L> step;
    step.fill(1.0);
    std::array<double, L> e{};
    BlockFactors<L> before, trial;
    int it = 0;
    while (it < m_o.max_iterations) {
        if (m_o.extrapolate) before = f;  // the start of the move to extrapolate
        update_d_and_diffuse(f);
        if (cold && it == 0 && m_o.smith_start) {
            smith_g_from_d(f);
            update_d_and_diffuse(f);
        }
        std::array<double, L> e_d{}, e_f{}, e_g{};
        const bool sub = m_trace && std::getenv("NPF_AWLS_TRACE_SUB");
        if (sub) e_d = update_diffuse_specular(f, false);
        update_f(f);
        if (sub) e_f = update_diffuse_specular(f, false);
        update_g(f);
        if (sub) e_g = update_diffuse_specular(f, false);
        e = update_diffuse_specular(f);
        if (sub) {
            const int l = std::atoi(std::getenv("NPF_AWLS_TRACE_SUB"));
            std::fprintf(stderr, "sub %4d  start %.9e  D %+.2e  F %+.2e  G %+.2e  rho %+.2e\n", it + 1, history.empty() ? 0.0 : history.back()[l] / m_swrr[l],
                         history.empty() ? 0.0 : (e_d[l] - history.back()[l]) / history.back()[l], (e_f[l] - e_d[l]) / e_d[l], (e_g[l] - e_f[l]) / e_f[l], (e[l] - e_g[l]) / e_g[l]);
        }
        normalise(f);
        const std::array<double, L> e_plain = e;
        ++it;
        if (m_o.extrapolate && it > 1) {
            trial = f;
            auto extrapolate = [&](std::vector<float>& t, const std::vector<float>& now, const std::vector<float>& old) {
                for (std::size_t k = 0; k < t.size(); ++k) {
                    t[k] = std::max(0.f, float(now[k] + step[k % L] * (now[k] - old[k])));
                }
            };
            extrapolate(trial.D, f.D, before.D);
            extrapolate(trial.F, f.F, before.F);
            extrapolate(trial.G, f.G, before.G);
            const std::array<double, L> e_trial = update_diffuse_specular(trial);
            normalise(trial);
            for (int l = 0; l < L; ++l) {
                const std::size_t ul = std::size_t(l);
                if (e_trial[ul] < e[ul]) {
                    copy_lane(trial, f, l);
                    e[ul] = e_trial[ul];
                    step[ul] = std::min(step[ul] * 1.5, 64.0);
                } else {
                    step[ul] = std::max(step[ul] * 0.5, 1.0);
                }
            }
        }
        progress(it);
        if (m_trace && it > 1 && std::getenv("NPF_AWLS_TRACE_MOVE")) {
            const int l = std::atoi(std::getenv("NPF_AWLS_TRACE_MOVE"));
            auto mv = [&](const std::vector<float>& a, const std::vector<float>& b, std::size_t& arg, double& rel) {
                double n = 0, d = 0, mx = -1;
                for (std::size_t k = std::size_t(l); k < a.size(); k += L) {
                    const double x = double(a[k]) - double(b[k]);
                    n += x * x, d += double(b[k]) * b[k];
                    if (std::abs(x) > mx) mx = std::abs(x), arg = k / L;
                }
                rel = std::sqrt(n / d);
                return mx;
            };
            std::size_t ad = 0, af = 0, ag = 0;
            double rd = 0, rf = 0, rg = 0;
            const double md = mv(f.D, before.D, ad, rd), mf = mv(f.F, before.F, af, rf), mg = mv(f.G, before.G, ag, rg);
            if (it % 25 == 0) {
                std::fprintf(stderr, "F %4d:", it);
                for (std::size_t k = 0; k < m_s.f_cells; ++k) std::fprintf(stderr, " %.4f", f.F[k * L + std::size_t(l)]);
                std::fprintf(stderr, "\nGcol0 %4d:", it);
                for (int r = 0; r < m_o.g_theta; ++r) std::fprintf(stderr, " %.4f", f.G[std::size_t(r * m_o.g_phi) * L + std::size_t(l)]);
                std::fprintf(stderr, "\nGcolq %4d:", it);
                for (int r = 0; r < m_o.g_theta; ++r) std::fprintf(stderr, " %.4f", f.G[std::size_t(r * m_o.g_phi + m_o.g_phi / 4) * L + std::size_t(l)]);
                std::fprintf(stderr, "\n");
            }
            std::fprintf(stderr, "move %4d D %.3e (max %.3e at %zu) F %.3e (max %.3e at %zu) G %.3e (max %.3e at row %zu col %zu) rho_d %.6e rho_s %.6e\n", it, rd, md, ad, rf, mf, af, rg, mg,
                         ag / std::size_t(m_o.g_phi), ag % std::size_t(m_o.g_phi), f.rho_d[std::size_t(l)], f.rho_s[std::size_t(l)]);
        }
        if (m_trace) {
            std::fprintf(stderr, "awls %4d", it);
            for (int l = 0; l < L; ++l) std::fprintf(stderr, " %.9e", m_swrr[l] > 0.0 ? e[std::size_t(l)] / m_swrr[l] : 0.0);
            std::fprintf(stderr, " |");
            for (int l = 0; l < L; ++l) std::fprintf(stderr, " %.9e", m_swrr[l] > 0.0 ? e_plain[std::size_t(l)] / m_swrr[l] : 0.0);
            std::fprintf(stderr, " |");
            for (int l = 0; l < L; ++l) std::fprintf(stderr, " %.2f", step[std::size_t(l)]);
            std::fprintf(stderr, "\n");
        }
        // Converged when the last kWindow sweeps together lowered the error by less than
        // kWindow x tolerance, relative: a single sweep's gain is a poor guide, as alternation
        // can crawl for many sweeps at a rate near the tolerance while far from the optimum.
        history.push_back(e);
        bool converged = history.size() > std::size_t(kWindow);
        for (int l = 0; l < L && converged; ++l) {
            const double p = history[history.size() - 1 - kWindow][std::size_t(l)], now = e[std::size_t(l)];
            if (p - now > kWindow * m_o.tolerance * p) converged = false;
        }
        if (converged) break;
    }
    for (int l = 0; l < L; ++l) {
        error[std::size_t(l)] = m_swrr[l] > 0.0 ? std::sqrt(e[std::size_t(l)] / m_swrr[l]) : 0.0;
    }
    return it;
}

}  // namespace npf::fit_detail
