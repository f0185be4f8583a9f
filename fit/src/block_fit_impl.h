// BlockFit's updates (included by block_fit.h): each streams the samples once through one of
// the passes of block_passes.h (built per instruction set), then solves its cells from the sums;
// and run's sweeps, their acceleration (Anderson mixing: anderson.h) and their stopping test.
#pragma once

#include <npf/core/parallel.h>
#include <npf/core/vec.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace npf::fit_detail {

// The passes' view of a set of factors; rho_d and rho_s as floats in `rho` ([2][L]).
template <int L>
PassFactors pass_factors(const BlockFactors<L>& f, float (&rho)[2][L]) {
    for (int l = 0; l < L; ++l) rho[0][l] = float(f.rho_d[std::size_t(l)]), rho[1][l] = float(f.rho_s[std::size_t(l)]);
    return {f.D.data(), f.F.data(), f.G.data(), rho[0], rho[1]};
}

template <int L>
BlockFit<L>::BlockFit(const SampleSet& samples, const AwlsOptions& options, int threads)
    : m_s(samples),
      m_o(options),
      m_split(balanced_cell_split(samples, kSlices)),
      m_threads(std::clamp(threads, 1, kSlices)),
      m_passes(block_passes<L>()),
      m_trace(std::getenv("NPF_AWLS_TRACE") != nullptr) {
    m_w.resize(samples.size() * L);
    m_cell.resize(samples.d_cells * 3 * L);
    m_g_acc.resize(std::size_t(kSlices));
    m_f_acc.resize(std::size_t(kSlices));
}

template <int L>
template <typename Body>
void BlockFit<L>::for_each_slice(Body body) const {
    npf::parallel_for(std::size_t(kSlices), [&](std::size_t slice) { body(int(slice)); }, m_threads);
}

template <int L>
void BlockFit<L>::evaluate(const SampleSet& samples, const Brdf& source, const std::vector<Channels>& blocks, int threads,
                           std::vector<std::vector<float>>& values) {
    // One query for all the blocks' channels (RGB is always a single block).
    std::vector<std::size_t> offset, count;
    std::vector<float> wavelengths;
    for (const Channels& c : blocks) {
        offset.push_back(c.is_rgb() ? 0 : wavelengths.size());
        count.push_back(c.size());
        if (!c.is_rgb()) wavelengths.insert(wavelengths.end(), c.wavelengths().begin(), c.wavelengths().end());
    }
    const ChannelQuery query = source.query(blocks.size() == 1 ? blocks[0] : Channels::spectral(wavelengths));
    values.resize(blocks.size());
    for (std::vector<float>& v : values) v.resize(samples.size() * L);
    const int slices = std::max(threads, 1);
    npf::parallel_slices(samples.size(), std::size_t(slices), [&](std::size_t, std::size_t b, std::size_t e) {
        std::vector<float> v(query.size());
        for (std::size_t s = b; s < e; ++s) {
            const float* d = &samples.directions[6 * s];
            source.eval_cos(Vec3(d[0], d[1], d[2]), Vec3(d[3], d[4], d[5]), query, v.data());
            for (std::size_t k = 0; k < blocks.size(); ++k) {
                float* out = &values[k][s * L];
                for (int l = 0; l < L; ++l) out[l] = v[offset[k] + std::min(std::size_t(l), count[k] - 1)] / d[5];
            }
        }
    }, slices);
}

template <int L>
std::size_t BlockFit<L>::load(std::vector<float>& values, std::size_t channels) {
    m_rho.swap(values);
    std::vector<std::size_t> invalid(std::size_t(m_threads), 0);
    npf::parallel_slices(m_s.size(), invalid.size(), [&](std::size_t t, std::size_t b, std::size_t e) {
        for (std::size_t s = b; s < e; ++s) {
            float* rho = &m_rho[s * L];
            float* w = &m_w[s * L];
            for (int l = 0; l < L; ++l) {
                const float value = rho[l];
                double weight = m_s.geometry[s];
                if (!std::isfinite(value)) {
                    if (std::size_t(l) < channels) ++invalid[t];
                    rho[l] = 0.f;
                    w[l] = 0.f;
                    continue;
                }
                if (m_o.compressive_power == 1.0) {  // the default: a division, not pow (8.8 M x 195 of them)
                    weight /= std::max(0.0, double(value)) + m_o.compressive_epsilon;
                } else if (m_o.compressive_power != 0.0) {
                    weight *= std::pow(std::max(0.0, double(value)) + m_o.compressive_epsilon, -m_o.compressive_power);
                }
                w[l] = float(weight);
            }
        }
    }, m_threads);
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
    float rho[2][L];
    const PassFactors x = pass_factors(f, rho);
    const PassSamples samples = pass_samples(m_s, m_rho.data(), m_w.data());
    for_each_slice([&](int t) { m_passes.d_sums(samples, x, m_split[std::size_t(t)], m_split[std::size_t(t) + 1], m_cell.data()); });
    for (int l = 0; l < L; ++l) {
        // rho_d minimises the error with every D_k at its optimum for that rho_d, clamped at 0:
        // a convex, piecewise quadratic function of rho_d. A cell whose D_k is clamped gives
        // its samples to rho_d alone, so the quadratic piece depends on which cells are; Newton
        // steps from the all-unclamped solution move between the pieces and end on the one
        // whose minimum lies inside it. (Taking the all-unclamped solution and clamping after,
        // as before, put rho_d too high wherever data lie below it, and the joint update then
        // raised the error that the (rho_d, rho_s) update lowered again, every sweep.)
        const auto solve = [&](double rd, bool all) {
            double num = m_swr[l], den = m_sw[l];
            for (std::size_t k = 0; k < m_s.d_cells; ++k) {
                const double* cell = &m_cell[k * 3 * L];
                if (!(cell[L + l] > 1e-30)) continue;
                if (!all && !(cell[2 * L + l] - rd * cell[l] > 0.0)) continue;
                num -= cell[l] * cell[2 * L + l] / cell[L + l];
                den -= cell[l] * cell[l] / cell[L + l];
            }
            return den > 1e-9 * m_sw[l] ? std::max(0.0, num / den) : 0.0;
        };
        double rho_d = solve(0.0, true);
        for (int step = 0; step < 32; ++step) {
            const double next = solve(rho_d, false);
            if (next == rho_d) break;
            rho_d = next;
        }
        f.rho_d[std::size_t(l)] = rho_d;
        for (std::size_t k = 0; k < m_s.d_cells; ++k) {
            const double* cell = &m_cell[k * 3 * L];
            if (cell[L + l] > 1e-30) f.D[k * L + l] = float(std::max(0.0, (cell[2 * L + l] - rho_d * cell[l]) / cell[L + l]));
        }
    }
}

// Cell j's numerator and denominator in lane l ([2][cells][L] in each slice's accumulator), summed
// in slice order.
template <int L, typename T>
void sum_slices(const std::vector<std::vector<T>>& acc, std::size_t j, int l, double& num, double& den) {
    for (const std::vector<T>& a : acc) num += a[j * 2 * L + l], den += a[j * 2 * L + L + l];
}

template <int L>
template <typename T, typename Pass>
void BlockFit<L>::run_pass(Pass pass, const BlockFactors<L>& f, std::size_t size, std::vector<std::vector<T>>& acc) {
    float rho[2][L];
    const PassFactors x = pass_factors(f, rho);
    const PassSamples samples = pass_samples(m_s, m_rho.data(), m_w.data());
    for_each_slice([&](int t) {
        std::vector<T>& a = acc[std::size_t(t)];
        a.assign(size, T(0));
        pass(samples, x, m_split[std::size_t(t)], m_split[std::size_t(t) + 1], a.data());
    });
}

template <int L>
void BlockFit<L>::update_f(BlockFactors<L>& f) {
    run_pass(m_passes.f_sums, f, 2 * m_s.f_cells * L, m_f_acc);
    for (std::size_t j = 0; j < m_s.f_cells; ++j) {
        for (int l = 0; l < L; ++l) {
            double num = 0.0, den = 0.0;
            sum_slices<L>(m_f_acc, j, l, num, den);
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
    run_pass(m_passes.g_sums, f, 2 * m_s.g_cells * L, m_g_acc);
    std::vector<double> sums(2 * m_s.g_cells * L, 0.0);
    std::array<double, L> mean_den{};
    for (std::size_t j = 0; j < m_s.g_cells; ++j) {
        for (int l = 0; l < L; ++l) {
            double num = 0.0, den = 0.0;
            sum_slices<L>(m_g_acc, j, l, num, den);
            sums[j * 2 * L + l] = num, sums[j * 2 * L + L + l] = den;
            mean_den[std::size_t(l)] += den / double(m_s.g_cells);
        }
    }
    const double pin = m_o.g_pin;
    const bool pinned = pin > 0.0 && m_g_ref.size() == f.G.size();
    for (std::size_t j = 0; j < m_s.g_cells; ++j) {
        for (int l = 0; l < L; ++l) {
            double num = sums[j * 2 * L + l], den = sums[j * 2 * L + L + l];
            if (pinned) {
                const double m = pin * mean_den[std::size_t(l)];
                num += m * m_g_ref[j * L + l], den += m;
            }
            if (den > 1e-30) f.G[j * L + l] = float(0.5 * (f.G[j * L + l] + std::max(0.0, num / den)));
        }
    }
}

// rho_d and rho_s jointly: the model is rho_d + rho_s m with m = D F G G / cc fixed, a
// two-parameter weighted least-squares problem solved in closed form (with the non-negativity
// constraints), whose sums also give the error.
//
// The sums are taken of the residual r = rho - rho_d - rho_s m at the current (rho_d, rho_s),
// and the solution is the change from there: the error is then sum w r^2 plus a small
// correction, not the difference of sums as large as the data's energy (sum w rho^2 - 2 rho_s
// sum w rho m + ...), whose float rounding was ~1e-5 of the error, as large as a sweep's gain
// near convergence: it made the line search accept and reject at random and the stopping test
// see noise (docs/fitting.md, "Convergence").
template <int L>
std::array<double, L> BlockFit<L>::update_diffuse_specular(BlockFactors<L>& f) {
    BlockFactors<L>* const one[1] = {&f};
    std::array<double, L> error[1];
    update_diffuse_specular(one, 1, error);
    return error[0];
}

template <int L>
void BlockFit<L>::update_diffuse_specular(BlockFactors<L>* const* candidates, int N, std::array<double, L>* error) {
    constexpr int kSums = 5;  // w m, w m^2, w r, w r m, w r^2
    std::vector<std::array<double, kMaxCandidates * kSums * L>> sums(static_cast<std::size_t>(kSlices));
    float rho[kMaxCandidates][2][L];
    PassFactors views[kMaxCandidates];
    for (int c = 0; c < N; ++c) views[c] = pass_factors(*candidates[c], rho[c]);
    const PassSamples samples = pass_samples(m_s, m_rho.data(), m_w.data());
    for_each_slice([&](int t) {
        auto& out = sums[std::size_t(t)];
        out.fill(0.0);
        m_passes.error_sums(samples, views, N, m_split[std::size_t(t)], m_split[std::size_t(t) + 1], out.data());
    });
    for (int c = 0; c < N; ++c) {
        BlockFactors<L>& x = *candidates[c];
        for (int l = 0; l < L; ++l) {
            double swm = 0.0, swmm = 0.0, g_d = 0.0, g_s = 0.0, e0 = 0.0;
            for (const auto& slice : sums) {
                const double* o = &slice[std::size_t(c) * kSums * L];
                swm += o[l], swmm += o[L + l], g_d += o[2 * L + l], g_s += o[3 * L + l], e0 += o[4 * L + l];
            }
            const double sw = m_sw[l], a = rho[c][0][l], b = rho[c][1][l];
            // The error at (rd, rs), from the residual sums at (a, b).
            const auto error_at = [&](double rd, double rs) {
                const double dd = rd - a, ds = rs - b;
                return e0 - 2.0 * dd * g_d - 2.0 * ds * g_s + dd * dd * sw + 2.0 * dd * ds * swm + ds * ds * swmm;
            };
            double rd = a, rs = b;
            const double det = sw * swmm - swm * swm;
            const bool regular = det > 1e-12 * sw * swmm;
            if (regular) {
                rd = a + (g_d * swmm - swm * g_s) / det;
                rs = b + (sw * g_s - swm * g_d) / det;
            }
            if (!regular || rd < 0.0 || rs < 0.0) {
                // The constrained optimum lies on a boundary: try each, keep the better.
                const double swrm = g_s + a * swm + b * swmm;  // sum w rho m
                const double rs_only = swmm > 0.0 ? std::max(0.0, swrm / swmm) : 0.0;
                const double rd_only = sw > 0.0 ? std::max(0.0, m_swr[l] / sw) : 0.0;
                if (error_at(0.0, rs_only) < error_at(rd_only, 0.0)) rd = 0.0, rs = rs_only;
                else rd = rd_only, rs = 0.0;
            }
            x.rho_d[std::size_t(l)] = rd;
            x.rho_s[std::size_t(l)] = rs;
            error[c][std::size_t(l)] = std::max(0.0, error_at(rd, rs));
        }
    }
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
    npf::parallel_slices(m_s.g_cells, std::size_t(m_threads), [&](std::size_t, std::size_t b, std::size_t e) {
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
    }, m_threads);
    f.G = std::move(G);
}

// One sweep: D with rho_d, F, G, then the tables' gauge (which needs no rho_d, rho_s: rho_s
// follows the scales). With `smith`, G restarts from Smith's masking of the first D.
template <int L>
void BlockFit<L>::sweep(BlockFactors<L>& f, bool smith) {
    update_d_and_diffuse(f);
    if (smith) {
        smith_g_from_d(f);
        update_d_and_diffuse(f);
    }
    update_f(f);
    update_g(f);
    normalise(f);
}

// The gauge's pin: a cold block pins G to Smith's masking of its first D (set by run); every
// later block of a spectral fit to the G the first of them started from, the cold block's
// converged G. (Until issue 19 each block was pinned to its predecessor's converged G: a chain
// along which G drifted by the pin's allowance per block, every block crawling 17 sweeps after
// it, and the drifted G across wavelengths cost the SVD compression: brushed copper 0.49 %
// BRDF-space error in the file against 0.18 % now, docs/fitting.md.)
template <int L>
void BlockFit<L>::pin_gauge(const BlockFactors<L>& f, bool cold) {
    if (!cold) {
        if (m_g_anchor.empty()) m_g_anchor = f.G;
        m_g_ref = m_g_anchor;
    } else {
        m_g_ref.clear();
        m_g_anchor.clear();
    }
}

// The accelerated candidate after sweep `it` (x = a.before, its result f) in a.mix; the lanes
// it proposes for (none: no candidate this sweep).
template <int L>
std::array<bool, L> BlockFit<L>::propose(Acceleration& a, const BlockFactors<L>& f, bool smith, int it) const {
    std::array<bool, L> mixed{};
    if (m_o.acceleration == AwlsOptions::Acceleration::Anderson && !smith) {
        a.anderson.push(a.before, f);
        a.mix = f;
        mixed = a.anderson.mix(a.mix);
    } else if (m_o.acceleration == AwlsOptions::Acceleration::LineSearch && it > 1) {
        // Extrapolate the last sweep's move by a step per lane that grows while it pays.
        a.mix = f;
        const auto extrapolate = [&](std::vector<float>& t, const std::vector<float>& now, const std::vector<float>& old) {
            for (std::size_t k = 0; k < t.size(); ++k) t[k] = std::max(0.f, float(now[k] + a.step[k % L] * (now[k] - old[k])));
        };
        extrapolate(a.mix.D, f.D, a.before.D);
        extrapolate(a.mix.F, f.F, a.before.F);
        extrapolate(a.mix.G, f.G, a.before.G);
        mixed.fill(true);
    }
    return mixed;
}

// Solves (rho_d, rho_s) for the sweep's result f and, in the same pass over the samples, for the
// candidate a.mix where `mixed`; each lane keeps the better ('*' in `kept` where it is the mix).
// The error per lane.
template <int L>
std::array<double, L> BlockFit<L>::keep_better(BlockFactors<L>& f, Acceleration& a, const std::array<bool, L>& mixed,
                                               std::array<char, L>& kept) {
    kept.fill(' ');
    if (std::none_of(mixed.begin(), mixed.end(), [](bool m) { return m; })) return update_diffuse_specular(f);
    normalise(a.mix);  // the mix keeps the gauge up to its clamp at 0
    BlockFactors<L>* const candidates[2] = {&f, &a.mix};
    std::array<double, L> errors[2];
    update_diffuse_specular(candidates, 2, errors);
    std::array<double, L> e = errors[0];
    for (int l = 0; l < L; ++l) {
        const std::size_t ul = std::size_t(l);
        const bool better = mixed[ul] && errors[1][ul] < e[ul];
        if (better) {
            copy_lane(a.mix, f, l);
            e[ul] = errors[1][ul];
            kept[ul] = '*';
        }
        if (m_o.acceleration == AwlsOptions::Acceleration::LineSearch) {
            a.step[ul] = better ? std::min(a.step[ul] * 1.5, 64.0) : std::max(a.step[ul] * 0.5, 1.0);
        }
    }
    return e;
}

// NPF_AWLS_TRACE: the relative weighted squared error per lane; '*' where the mix was kept.
template <int L>
void BlockFit<L>::trace(int it, const std::array<double, L>& e, const std::array<char, L>& kept) const {
    if (!m_trace) return;
    std::fprintf(stderr, "awls %4d", it);
    for (int l = 0; l < L; ++l) {
        std::fprintf(stderr, " %.9e%c", m_swrr[l] > 0.0 ? e[std::size_t(l)] / m_swrr[l] : 0.0, kept[std::size_t(l)]);
    }
    std::fprintf(stderr, "\n");
}

// Converged when the last kWindow sweeps together lowered the error by less than kWindow x
// tolerance, relative: a single sweep's gain is a poor guide, as alternation can crawl for many
// sweeps at a rate near the tolerance while far from the optimum (and a rejected mix followed by
// a slow sweep looks like convergence). Or when the last kShortWindow sweeps lowered it by less
// than a tenth of that rate: a block warm-started from its converged neighbour is done after a
// few sweeps, and waiting for the long window cost the 12 warm blocks of 195 wavelengths a third
// of all sweeps, while a stall at the tolerance's rate does not pass the stricter test.
// An error below kErrorFloor of the data's weighted energy (a relative RMS error below 1 %:
// analytic materials the model represents almost exactly) is judged against that floor instead:
// its relative gains can stay above the tolerance for hundreds of sweeps while the RMS error
// moves in the fifth decimal. (1e-5, a 0.3 % RMS error, until issue 19: red_plastic.yaml, fitted
// to 4e-6 of its energy, still drifted by 3e-9 per 10 sweeps and ran into the cap of 200; with
// 1e-4 it stops at 119, its render unchanged. The five real materials and the brushed copper
// stay above 1e-4: their fits did not move.)
template <int L>
bool BlockFit<L>::converged(const std::vector<std::array<double, L>>& history) const {
    constexpr std::size_t kWindow = 10, kShortWindow = 3;
    constexpr double kErrorFloor = 1e-4;
    const std::array<double, L>& e = history.back();
    const auto gained_less = [&](std::size_t window, double rate) {
        if (history.size() <= window) return false;
        for (int l = 0; l < L; ++l) {
            const double p = history[history.size() - 1 - window][std::size_t(l)], now = e[std::size_t(l)];
            if (p - now > double(window) * rate * std::max(p, kErrorFloor * m_swrr[l])) return false;
        }
        return true;
    };
    return gained_less(kWindow, m_o.tolerance) || gained_less(kShortWindow, 0.1 * m_o.tolerance);
}

// AWLS sweeps with Anderson acceleration. Plain alternation crawls along the valleys where the
// factors trade with one another (the "swamps" of alternating least squares): on brushed
// copper with the compressive weight, F rising and G falling together towards grazing angles,
// the near-symmetry G -> G s, F -> F / s^2, for hundreds of sweeps at ~3e-5 of the error per
// sweep (docs/fitting.md, "Convergence"). After each sweep the fit tries the Anderson mix of
// its last sweeps, which costs one more pass; a lane keeps it where its error is lower.
// (Tried and dropped, docs/fitting.md: forgetting a lane's sweeps when its mix is worse, and the
// line search along the last move as a third candidate.)
template <int L>
template <typename Progress>
int BlockFit<L>::run(BlockFactors<L>& f, bool cold, std::array<double, L>& error, Progress progress) {
    std::vector<std::array<double, L>> history;
    Acceleration a;
    a.step.fill(1.0);
    pin_gauge(f, cold);
    int it = 0;
    while (it < m_o.max_iterations) {
        if (m_o.acceleration != AwlsOptions::Acceleration::None) a.before = f;  // x of the pair (x, sweep(x))
        const bool smith = cold && it == 0 && m_o.smith_start;
        sweep(f, smith);
        ++it;
        if (smith) m_g_ref = f.G;
        // The mix of the last sweeps (the Smith start is no sweep of the map).
        const std::array<bool, L> mixed = propose(a, f, smith, it);
        std::array<char, L> kept;
        history.push_back(keep_better(f, a, mixed, kept));
        progress(it);
        trace(it, history.back(), kept);
        if (converged(history)) break;
    }
    for (int l = 0; l < L; ++l) {
        const double e = history.empty() ? 0.0 : history.back()[std::size_t(l)];
        error[std::size_t(l)] = m_swrr[l] > 0.0 ? std::sqrt(e / m_swrr[l]) : 0.0;
    }
    return it;
}

}  // namespace npf::fit_detail
