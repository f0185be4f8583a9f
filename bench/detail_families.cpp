// npf_bench_detail_families: the detail layer's form chosen by measurement between two families
// (docs/fitting.md, "Two families: grid against low-rank products"; issue 16, item 3).
//
// Per material: one base fit (the production preset without its detail layer, through
// convert_material as `npf convert --detail none` runs it), then the residual r_c(u_h, theta_d,
// phi_d) fitted at several sizes by
//  - grid:   the shipped fitter (fit_detail_layer): a trilinear grid, compressed across channels
//            by the SVD and stored as half;
//  - hybrid: the same fitter on grids fine in u_h (90 rows) and coarse in theta_d and phi_d;
//  - cp:     per channel a sum of K separable products a_k(u_h) b_k(theta_d) c_k(phi_d) (CP /
//            PARAFAC) of 1-D tables with linear interpolation (the grid's cell-centre, clamped
//            and periodic conventions), stored as half: C K (n_u + n_theta_d + n_phi_d) values;
// and per candidate (a) the paired render's PSNR against the raw file (Sphere scene, default
// environment, environment sampling only, seed 1, as npf render + npf compare), (b) the worst
// relative directional-albedo error at 0, 20, 40, 60, 70, 80 degrees over the channels (npf
// albedo --against --samples 64), (c) the fit time, and the bytes the family stores.
//
// The CP fit has the grid fitter's objective, not an imitation of it: a product of 1-D tables
// with linear interpolation IS a trilinear table over the knot grid n_u x n_theta_d x n_phi_d,
// of tensor rank K (r = sum_ijl L_i(u) L_j(d) L_l(p) R_ijl, R = sum_k a_k x b_k x c_k). So the
// detail fitter's own least-squares problem, assembled for that knot grid
// (converter/src/fit/detail_system.h: its samples, 3 per knot and axis, its data weight, its
// energy rows, its smoothness term), is minimised over rank-K tensors: alternating least
// squares from the (unweighted) CP of the unconstrained knot-grid solution; each factor's
// problem, linear in it with the energy term included, solved by conjugate gradients with a
// per-row K x K block preconditioner (to 1e-4 or 25 iterations); an exact line search along
// each sweep's step; until a sweep gains less than 1e-4 of the objective (30 sweeps at most).
// A ridge of 1e-9 of the blocks' mean diagonal keeps each block definite. The channels are
// fitted in parallel, one thread each. Every CP row also checks that the stored products shade
// as the knot grid they were fitted as (NpfModel's trilinear lookup, 20000 random pairs).
// Rows "knots" are that knot grid unconstrained (the grid fitter at 90 x 32 x 64): what the
// products approach as K grows.
//
//   npf_bench_detail_families M.bsdf [M2.bsdf ...] [--work DIR] [--families grid,hybrid,cp]
//       [--grid 16x8x16,...] [--hybrid 90x4x6,...] [--cp-tables 90x32x64] [--cp-ranks 11,22,45,90]
//       [--cp-sweeps N] [--cp-cg N] [--cp-tolerance T] [--cp-reference 0|1] [--cp-unclamped 0|1] [--trace 0|1]
//       [--threads N] [--size N] [--spp N] [--tsv FILE]
//
// The work folder caches the base conversion and the raw render of each material.
#include "detail_system.h"

#include <npf/color/display_image.h>
#include <npf/converter/convert.h>
#include <npf/converter/fit/detail_fit.h>
#include <npf/converter/fit/spectral_compression.h>
#include <npf/converter/open_material.h>
#include <npf/core/directional_albedo.h>
#include <npf/core/error.h>
#include <npf/core/parallel.h>
#include <npf/render/default_environment.h>
#include <npf/render/environment_map.h>
#include <npf/render/image_metrics.h>
#include <npf/render/path_tracer.h>
#include <npf/render/render_output.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_texture_file.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Imath/half.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using npf::DetailGrid;
using npf::NpfModel;
using Clock = std::chrono::steady_clock;
namespace fd = npf::fit_detail;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream in(s);
    for (std::string part; std::getline(in, part, sep);) {
        if (!part.empty()) out.push_back(part);
    }
    return out;
}

int positive(const std::string& what, const std::string& text) {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || v < 1 || v > 1 << 20) throw npf::Error(what, "'" + text + "' is not a whole number >= 1");
    return int(v);
}

DetailGrid parse_grid(const std::string& what, const std::string& text) {
    const std::vector<std::string> p = split(text, 'x');
    if (p.size() != 3) throw npf::Error(what, "'" + text + "' is not THETA_HxTHETA_DxPHI_D");
    return DetailGrid{positive(what, p[0]), positive(what, p[1]), positive(what, p[2])};
}

std::vector<DetailGrid> parse_grids(const std::string& what, const std::string& text) {
    std::vector<DetailGrid> out;
    for (const std::string& g : split(text, ',')) out.push_back(parse_grid(what, g));
    return out;
}

std::string grid_text(const DetailGrid& g) {
    return std::to_string(g.theta_h) + "x" + std::to_string(g.theta_d) + "x" + std::to_string(g.phi_d);
}

// ---- Products of 1-D tables on a knot grid --------------------------------------------------

// Contractions between a knot-grid tensor R[i][j][l] (DetailGrid::index order) and rank-K factor
// tables F_m[n_m][K] (row-major, K contiguous), as matrix products per theta_h slice i. Sums run
// in a fixed order whatever the threads.
class CpKernels {
public:
    using Mat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    using MapC = Eigen::Map<const Mat>;
    using Map = Eigen::Map<Mat>;

    CpKernels(const DetailGrid& g, int rank, int threads)
        : m_n{g.theta_h, g.theta_d, g.phi_d}, m_k(std::size_t(rank)), m_threads(threads) {}

    int n(int mode) const { return m_n[mode]; }
    std::size_t rank() const { return m_k; }
    int threads() const { return m_threads; }
    std::size_t cells() const { return std::size_t(m_n[0]) * std::size_t(m_n[1]) * std::size_t(m_n[2]); }

    // R = sum_k a_k x b_k x c_k: slice i is B diag(a_i) C^T.
    void reconstruct(const double* a, const double* b, const double* c, double* r) const {
        const Eigen::Index K = Eigen::Index(m_k), n1 = m_n[1], n2 = m_n[2];
        const MapC B(b, n1, K), C(c, n2, K);
        npf::parallel_slices(std::size_t(m_n[0]), std::size_t(m_threads), [&](std::size_t, std::size_t begin, std::size_t end) {
            Mat scaled(n1, K);
            for (std::size_t i = begin; i < end; ++i) {
                const Eigen::Map<const Eigen::RowVectorXd> ai(a + i * m_k, K);
                scaled = B.array().rowwise() * ai.array();
                Map(r + i * std::size_t(n1 * n2), n1, n2).noalias() = scaled * C.transpose();
            }
        }, m_threads);
    }

    // G[n_mode][K] = the gradient of <Y, R> with respect to factor `mode` (the other two fixed):
    // sum over the other two indices of Y times their factors.
    void mttkrp(const double* y, int mode, const double* a, const double* b, const double* c, double* g) const {
        const Eigen::Index K = Eigen::Index(m_k), n1 = m_n[1], n2 = m_n[2];
        const std::size_t n0 = std::size_t(m_n[0]), nm = std::size_t(m_n[mode]);
        const MapC B(b, n1, K), C(c, n2, K);
        // Per theta_h slice i a partial result (modes 1 and 2), summed in slice order afterwards.
        std::vector<double> partial(mode == 0 ? 0 : n0 * nm * m_k, 0.0);
        npf::parallel_slices(n0, std::size_t(m_threads), [&](std::size_t, std::size_t begin, std::size_t end) {
            Mat t(n1, K);
            for (std::size_t i = begin; i < end; ++i) {
                const MapC yi(y + i * std::size_t(n1 * n2), n1, n2);
                const Eigen::Map<const Eigen::RowVectorXd> ai(a + i * m_k, K);
                if (mode == 2) {
                    t = B.array().rowwise() * ai.array();
                    Map(partial.data() + i * nm * m_k, n2, K).noalias() = yi.transpose() * t;
                    continue;
                }
                t.noalias() = yi * C;
                if (mode == 0) {
                    Eigen::Map<Eigen::RowVectorXd>(g + i * m_k, K) = (t.array() * B.array()).colwise().sum();
                } else {
                    Map(partial.data() + i * nm * m_k, n1, K) = t.array().rowwise() * ai.array();
                }
            }
        }, m_threads);
        if (mode == 0) return;
        std::fill(g, g + nm * m_k, 0.0);
        for (std::size_t i = 0; i < n0; ++i) {
            const double* part = partial.data() + i * nm * m_k;
            for (std::size_t q = 0; q < nm * m_k; ++q) g[q] += part[q];
        }
    }

    // For each row r of factor `mode`: sum over the cells of its slice of w(cell) g g^T, g the
    // product of the other two factors' rows at the cell (K x K blocks, [n_mode][K][K]).
    void weighted_grams(const double* w, int mode, const double* a, const double* b, const double* c,
                        std::vector<double>& out) const {
        const Eigen::Index K = Eigen::Index(m_k);
        const std::size_t n0 = std::size_t(m_n[0]), n1 = std::size_t(m_n[1]), n2 = std::size_t(m_n[2]);
        const std::size_t nm = std::size_t(m_n[mode]);
        out.assign(nm * m_k * m_k, 0.0);
        // The rows of the Khatri-Rao product of the two other factors, and the cells of slice r.
        const int o1 = mode == 0 ? 1 : 0, o2 = mode == 2 ? 1 : 2;
        const double* f[3] = {a, b, c};
        const std::size_t no1 = std::size_t(m_n[o1]), no2 = std::size_t(m_n[o2]);
        Mat kr(Eigen::Index(no1 * no2), K);
        for (std::size_t u = 0; u < no1; ++u)
            for (std::size_t v = 0; v < no2; ++v)
                for (Eigen::Index k = 0; k < K; ++k)
                    kr(Eigen::Index(u * no2 + v), k) = f[o1][u * m_k + std::size_t(k)] * f[o2][v * m_k + std::size_t(k)];
        npf::parallel_slices(nm, std::size_t(m_threads), [&](std::size_t, std::size_t begin, std::size_t end) {
            Mat weighted(kr.rows(), K);
            for (std::size_t r = begin; r < end; ++r) {
                for (std::size_t u = 0; u < no1; ++u) {
                    for (std::size_t v = 0; v < no2; ++v) {
                        std::size_t idx[3];
                        idx[mode] = r;
                        idx[o1] = u;
                        idx[o2] = v;
                        const double wc = w[(idx[0] * n1 + idx[1]) * n2 + idx[2]];
                        weighted.row(Eigen::Index(u * no2 + v)) = wc * kr.row(Eigen::Index(u * no2 + v));
                    }
                }
                Map(out.data() + r * m_k * m_k, K, K).noalias() = kr.transpose() * weighted;
            }
        }, m_threads);
        (void)n0;
    }

private:
    int m_n[3];
    std::size_t m_k;
    int m_threads;
};

double dot(const std::vector<double>& x, const std::vector<double>& y) {
    double s = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) s += x[i] * y[i];
    return s;
}

// The detail fitter's normal operator A_c applied on `threads` (its stencil rows in slices).
void apply_parallel(const fd::NormalOperator& op, const std::vector<double>& x, std::vector<double>& y, int threads) {
    const double* s = op.stencil->data();
    const std::int32_t* nb = op.neighbour->data();
    const std::size_t S = std::size_t(fd::kDetailStencil);
    npf::parallel_slices(op.cells, std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            double v = 0.0;
            for (std::size_t k = 0; k < S; ++k) {
                const std::int32_t j = nb[i * S + k];
                if (j >= 0) v += s[i * S + k] * x[std::size_t(j)];
            }
            y[i] = v;
        }
    }, threads);
    for (std::size_t v = 0; v < op.rows->size(); ++v) {
        if (!(op.row_weight[v] > 0.0)) continue;
        const std::vector<double>& a = (*op.rows)[v];
        const double d = dot(a, x) * op.row_weight[v];
        for (std::size_t i = 0; i < op.cells; ++i) y[i] += a[i] * d;
    }
}

// The stencil part of A_c in single precision with its neighbours computed from the grid (a third
// of the memory traffic of the fitter's double stencil and index table): the inner solves' operator.
// The objective itself is always evaluated with the fitter's operator. Needs phi_d >= 3.
class CompactStencil {
public:
    CompactStencil(const fd::NormalOperator& op, const DetailGrid& g) : m_g(g), m_s(op.stencil->begin(), op.stencil->end()) {
        if (g.phi_d < 3) throw npf::Error("cp knot grid", "needs at least 3 phi_d knots");
    }

    void apply(const double* x, double* y) const {
        const int n0 = m_g.theta_h, n1 = m_g.theta_d, n2 = m_g.phi_d;
        for (int h = 0; h < n0; ++h) {
            for (int d = 0; d < n1; ++d) {
                const std::size_t row0 = (std::size_t(h) * std::size_t(n1) + std::size_t(d)) * std::size_t(n2);
                double* out = y + row0;
                for (int p = 0; p < n2; ++p) out[p] = 0.0;
                for (int dh = -1; dh <= 1; ++dh) {
                    const int hh = h + dh;
                    if (hh < 0 || hh >= n0) continue;
                    for (int dd = -1; dd <= 1; ++dd) {
                        const int ddd = d + dd;
                        if (ddd < 0 || ddd >= n1) continue;
                        const double* xr = x + (std::size_t(hh) * std::size_t(n1) + std::size_t(ddd)) * std::size_t(n2);
                        const std::size_t slot = std::size_t((dh + 1) * 9 + (dd + 1) * 3);
                        for (int p = 0; p < n2; ++p) {
                            const float* st = m_s.data() + (row0 + std::size_t(p)) * std::size_t(fd::kDetailStencil) + slot;
                            const int pm = p == 0 ? n2 - 1 : p - 1, pp = p == n2 - 1 ? 0 : p + 1;
                            out[p] += double(st[0]) * xr[pm] + double(st[1]) * xr[p] + double(st[2]) * xr[pp];
                        }
                    }
                }
            }
        }
    }

private:
    DetailGrid m_g;
    std::vector<float> m_s;
};

// Solves the K x K system V x = g (V symmetric positive definite after a small ridge) for each of
// `rows` right-hand sides, in place: Cholesky.
void solve_spd_rows(std::vector<double> v, std::size_t K, double* g, std::size_t rows) {
    double trace = 0.0;
    for (std::size_t k = 0; k < K; ++k) trace += v[k * K + k];
    const double ridge = 1e-10 * (trace > 0.0 ? trace / double(K) : 1.0);
    for (std::size_t k = 0; k < K; ++k) v[k * K + k] += ridge;
    for (std::size_t j = 0; j < K; ++j) {  // v = L L^T, L in the lower triangle
        double d = v[j * K + j];
        for (std::size_t k = 0; k < j; ++k) d -= v[j * K + k] * v[j * K + k];
        d = std::sqrt(std::max(d, 1e-300));
        v[j * K + j] = d;
        for (std::size_t i = j + 1; i < K; ++i) {
            double s = v[i * K + j];
            for (std::size_t k = 0; k < j; ++k) s -= v[i * K + k] * v[j * K + k];
            v[i * K + j] = s / d;
        }
    }
    for (std::size_t r = 0; r < rows; ++r) {
        double* x = g + r * K;
        for (std::size_t i = 0; i < K; ++i) {
            double s = x[i];
            for (std::size_t k = 0; k < i; ++k) s -= v[i * K + k] * x[k];
            x[i] = s / v[i * K + i];
        }
        for (std::size_t i = K; i-- > 0;) {
            double s = x[i];
            for (std::size_t k = i + 1; k < K; ++k) s -= v[k * K + i] * x[k];
            x[i] = s / v[i * K + i];
        }
    }
}

struct CpFactors {
    std::vector<double> f[3];  // [n_m][K]
};

// Scales each rank-one term's three columns to equal norms (the product unchanged): keeps the
// alternating solves well scaled and each table's values in half's range.
void balance(CpFactors& cp, const CpKernels& ker) {
    const std::size_t K = ker.rank();
    for (std::size_t k = 0; k < K; ++k) {
        double norm[3];
        for (int m = 0; m < 3; ++m) {
            double s = 0.0;
            for (int i = 0; i < ker.n(m); ++i) s += cp.f[m][std::size_t(i) * K + k] * cp.f[m][std::size_t(i) * K + k];
            norm[m] = std::sqrt(s);
        }
        if (!(norm[0] > 0.0 && norm[1] > 0.0 && norm[2] > 0.0)) continue;
        const double target = std::cbrt(norm[0] * norm[1] * norm[2]);
        for (int m = 0; m < 3; ++m) {
            for (int i = 0; i < ker.n(m); ++i) cp.f[m][std::size_t(i) * K + k] *= target / norm[m];
        }
    }
}

// The unweighted CP of a tensor by plain alternating least squares from a seeded random start:
// the starting point of the weighted fit.
CpFactors unweighted_cp(const std::vector<double>& t, const CpKernels& ker, int iterations, unsigned seed) {
    const std::size_t K = ker.rank();
    CpFactors cp;
    std::mt19937 rng(seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (int m = 0; m < 3; ++m) {
        cp.f[m].resize(std::size_t(ker.n(m)) * K);
        for (double& v : cp.f[m]) v = normal(rng);
    }
    auto gram = [&](int m) {
        std::vector<double> g(K * K, 0.0);
        for (int i = 0; i < ker.n(m); ++i) {
            const double* row = cp.f[m].data() + std::size_t(i) * K;
            for (std::size_t a = 0; a < K; ++a)
                for (std::size_t b = 0; b < K; ++b) g[a * K + b] += row[a] * row[b];
        }
        return g;
    };
    for (int it = 0; it < iterations; ++it) {
        for (int m = 0; m < 3; ++m) {
            const int o1 = (m + 1) % 3, o2 = (m + 2) % 3;
            std::vector<double> v = gram(o1);
            const std::vector<double> v2 = gram(o2);
            for (std::size_t q = 0; q < K * K; ++q) v[q] *= v2[q];
            ker.mttkrp(t.data(), m, cp.f[0].data(), cp.f[1].data(), cp.f[2].data(), cp.f[m].data());
            solve_spd_rows(v, K, cp.f[m].data(), std::size_t(ker.n(m)));
        }
        balance(cp, ker);
    }
    return cp;
}

struct CpFitStats {
    int sweeps = 0;
    double objective = 0.0;  // x^T A x - 2 b^T x of the stored (half) tables
};

// Exact line search along the last sweep's step (Rajih, Comon and Harshman 2008): the tensor of
// (a + t da, b + t db, c + t dc) is a cubic in t, so the objective is a polynomial of degree 6
// in t, minimised here over t in [0, 8] (t = 0 keeps the sweep's result). Returns the best t.
double exact_line_search(const fd::NormalOperator& op, const std::vector<double>& rhs, const CpFactors& cp,
                         const CpFactors& step, const CpKernels& ker, int threads) {
    const std::size_t cells = ker.cells();
    std::vector<std::vector<double>> r(4, std::vector<double>(cells, 0.0)), mr(4, std::vector<double>(cells));
    std::vector<double> term(cells);
    // r[n]: the sum over the ways of taking n of the three factors from the step.
    for (int mask = 0; mask < 8; ++mask) {
        const double* f[3];
        int n = 0;
        for (int m = 0; m < 3; ++m) {
            const bool from_step = (mask >> m) & 1;
            f[m] = from_step ? step.f[m].data() : cp.f[m].data();
            n += from_step;
        }
        ker.reconstruct(f[0], f[1], f[2], term.data());
        for (std::size_t i = 0; i < cells; ++i) r[std::size_t(n)][i] += term[i];
    }
    for (int n = 0; n < 4; ++n) apply_parallel(op, r[std::size_t(n)], mr[std::size_t(n)], threads);
    double poly[7] = {0, 0, 0, 0, 0, 0, 0};
    for (int i = 0; i < 4; ++i) {
        poly[i] -= 2.0 * dot(rhs, r[std::size_t(i)]);
        for (int j = 0; j < 4; ++j) poly[i + j] += dot(r[std::size_t(i)], mr[std::size_t(j)]);
    }
    auto value = [&](double t) {
        double v = 0.0;
        for (int n = 6; n >= 0; --n) v = v * t + poly[n];
        return v;
    };
    double best = 0.0, best_value = value(0.0);
    for (int k = 1; k <= 800; ++k) {
        const double t = 0.01 * k;
        const double v = value(t);
        if (v < best_value) best_value = v, best = t;
    }
    return best;
}

// Minimises channel ch's detail objective over rank-K tensors, from `cp`, by alternating least
// squares. Each factor's problem (the others fixed; the energy rows projected onto it) is solved
// by conjugate gradients, preconditioned per table row by the K x K block that the absolute row
// sums of the stencil (a diagonal bound of it) and the projected energy rows give, until the
// residual falls by `cg_tolerance` or after cg_iterations. After each sweep, an exact line search
// along the sweep's step. Stops when a sweep lowers the objective by less than `tolerance` of it.
CpFitStats weighted_als(const fd::DetailSystem& sys, std::size_t ch, CpFactors& cp, const CpKernels& ker, int sweeps,
                        int cg_iterations, double tolerance, double optimum, int threads, bool trace) {
    const fd::NormalOperator op = fd::NormalOperator::of(sys, ch);
    const std::vector<double>& rhs = sys.rhs[ch];
    const std::size_t K = ker.rank(), cells = ker.cells(), V = sys.views();
    const double cg_tolerance = 1e-4;
    std::vector<double> bound(cells, 0.0);  // absolute row sums of the stencil part
    {
        const std::size_t S = std::size_t(fd::kDetailStencil);
        for (std::size_t i = 0; i < cells; ++i)
            for (std::size_t k = 0; k < S; ++k)
                if ((*op.neighbour)[i * S + k] >= 0) bound[i] += std::fabs((*op.stencil)[i * S + k]);
    }
    std::vector<double> r_full(cells), mr(cells);
    auto objective = [&]() {
        ker.reconstruct(cp.f[0].data(), cp.f[1].data(), cp.f[2].data(), r_full.data());
        apply_parallel(op, r_full, mr, threads);
        return dot(r_full, mr) - 2.0 * dot(rhs, r_full);
    };
    const CompactStencil compact(op, sys.grid);
    CpFitStats stats;
    double previous = objective();
    int cg_total = 0;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        const CpFactors before = cp;
        for (int m = 0; m < 3; ++m) {
            const std::size_t rows = std::size_t(ker.n(m)), nm = rows * K;
            const double* fixed[3] = {cp.f[0].data(), cp.f[1].data(), cp.f[2].data()};
            // The energy rows seen by factor m: a_v . R = (P_m^T a_v) . x.
            std::vector<std::vector<double>> projected;
            std::vector<double> projected_weight;
            for (std::size_t v = 0; v < V; ++v) {
                if (!(op.row_weight[v] > 0.0)) continue;
                projected.emplace_back(nm);
                projected_weight.push_back(op.row_weight[v]);
                ker.mttkrp(sys.rows[v].data(), m, fixed[0], fixed[1], fixed[2], projected.back().data());
            }
            // A x: the tensor with factor m = x, through A_c, back onto factor m.
            auto block = [&](const std::vector<double>& x, std::vector<double>& out) {
                const double* f[3] = {fixed[0], fixed[1], fixed[2]};
                f[m] = x.data();
                ker.reconstruct(f[0], f[1], f[2], r_full.data());
                compact.apply(r_full.data(), mr.data());
                ker.mttkrp(mr.data(), m, f[0], f[1], f[2], out.data());
                for (std::size_t v = 0; v < projected.size(); ++v) {
                    const double d = dot(projected[v], x) * projected_weight[v];
                    for (std::size_t i = 0; i < nm; ++i) out[i] += projected[v][i] * d;
                }
            };
            // The preconditioner: a Cholesky factor per table row.
            std::vector<double> grams;
            ker.weighted_grams(bound.data(), m, fixed[0], fixed[1], fixed[2], grams);
            std::vector<Eigen::LLT<CpKernels::Mat>> chol(rows);
            double gram_trace = 0.0;
            for (std::size_t i = 0; i < grams.size(); i += K + 1) gram_trace += grams[i];
            const double ridge = 1e-9 * (gram_trace > 0.0 ? gram_trace / double(nm) : 1.0);
            for (std::size_t r = 0; r < rows; ++r) {
                CpKernels::Mat blk = CpKernels::MapC(grams.data() + r * K * K, Eigen::Index(K), Eigen::Index(K));
                for (std::size_t v = 0; v < projected.size(); ++v) {
                    const Eigen::Map<const Eigen::VectorXd> pv(projected[v].data() + r * K, Eigen::Index(K));
                    blk.noalias() += projected_weight[v] * pv * pv.transpose();
                }
                blk.diagonal().array() += ridge;
                chol[r].compute(blk);
            }
            auto precondition = [&](const std::vector<double>& in, std::vector<double>& out) {
                for (std::size_t r = 0; r < rows; ++r) {
                    Eigen::Map<Eigen::VectorXd>(out.data() + r * K, Eigen::Index(K)) =
                        chol[r].solve(Eigen::Map<const Eigen::VectorXd>(in.data() + r * K, Eigen::Index(K)));
                }
            };
            std::vector<double> g(nm), x = cp.f[m];
            ker.mttkrp(rhs.data(), m, fixed[0], fixed[1], fixed[2], g.data());
            std::vector<double> ax(nm), r(nm), z(nm), p(nm), q(nm);
            block(x, ax);
            for (std::size_t i = 0; i < nm; ++i) r[i] = g[i] - ax[i] - ridge * x[i];
            precondition(r, z);
            p = z;
            double rz = dot(r, z);
            const double rz_start = rz;
            for (int it = 0; it < cg_iterations; ++it) {
                if (!(rz > cg_tolerance * cg_tolerance * rz_start)) break;
                block(p, q);
                ++cg_total;
                for (std::size_t i = 0; i < nm; ++i) q[i] += ridge * p[i];
                const double pq = dot(p, q);
                if (!(pq > 0.0)) break;
                const double alpha = rz / pq;
                for (std::size_t i = 0; i < nm; ++i) {
                    x[i] += alpha * p[i];
                    r[i] -= alpha * q[i];
                }
                precondition(r, z);
                const double rz_next = dot(r, z);
                const double beta = rz_next / rz;
                rz = rz_next;
                for (std::size_t i = 0; i < nm; ++i) p[i] = z[i] + beta * p[i];
            }
            cp.f[m] = x;
        }
        double t = 0.0;
        if (sweep > 0) {  // the first sweep's step is mostly the start's own correction
            CpFactors step;
            for (int m = 0; m < 3; ++m) {
                step.f[m] = cp.f[m];
                for (std::size_t i = 0; i < step.f[m].size(); ++i) step.f[m][i] -= before.f[m][i];
            }
            t = exact_line_search(op, rhs, cp, step, ker, threads);
            for (int m = 0; m < 3; ++m)
                for (std::size_t i = 0; i < cp.f[m].size(); ++i) cp.f[m][i] += t * step.f[m][i];
        }
        balance(cp, ker);
        stats.sweeps = sweep + 1;
        const double now = objective();
        if (trace)
            std::printf("    channel %zu rank %zu sweep %d: objective %.8g (line search %.2f, %d CG iterations so far)\n",
                        ch, K, sweep + 1, now, t, cg_total);
        // The objective's size is mostly the energy term's; the gap to the unconstrained knot grid's
        // optimum is the scale that shows the data term's progress.
        const bool converged = previous - now <= tolerance * std::max(now - optimum, 0.0);
        previous = now;
        if (converged) break;
    }
    for (int m = 0; m < 3; ++m) {
        for (double& v : cp.f[m]) v = double(float(Imath::half(float(v))));
    }
    stats.objective = objective();
    return stats;
}

// The weighted data misfit of knot-grid values r for channel c, over sum w f_source^2 (as the
// fitter's DetailReport::weighted_error_after, here through the normal equations: the smoothness
// term, 1e-4 of the data term's scale, is included).
double weighted_error(const fd::DetailSystem& sys, std::size_t c, const std::vector<double>& r) {
    fd::NormalOperator data = fd::NormalOperator::of(sys, c);
    std::vector<double> rhs_data = sys.rhs[c];
    const std::size_t C = sys.channels;
    for (std::size_t v = 0; v < sys.views(); ++v) {  // take the energy targets out again
        const double target = sys.albedo_source[v * C + c] - sys.albedo_base[v * C + c];
        for (std::size_t i = 0; i < sys.cells; ++i) rhs_data[i] -= data.row_weight[v] * sys.rows[v][i] * target;
        data.row_weight[v] = 0.0;
    }
    std::vector<double> sr(sys.cells);
    data.apply(r, sr);
    const double e = sys.data_error[c] + dot(r, sr) - 2.0 * dot(rhs_data, r);
    return sys.data_norm[c] > 0.0 ? e / sys.data_norm[c] : 0.0;
}

// The base model plus a CP residual, behind npf::Brdf: f = max(0, NPF + r_c) per stored channel
// (the detail layer's rule), the base's sampler.
class CpDetailBrdf final : public npf::Brdf {
public:
    static constexpr std::size_t kMaxChannels = 16;

    // clamp false: NPF + r_c unclamped (a diagnostic of what the clamp adds; not a material).
    CpDetailBrdf(const NpfModel& base, const DetailGrid& knots, int rank, std::vector<std::vector<float>> tables,
                 bool clamp = true)
        : m_base(base), m_model(base), m_knots(knots), m_k(std::size_t(rank)), m_tables(std::move(tables)),
          m_clamp(clamp) {
        if (base.channel_count() > kMaxChannels) throw npf::Error("cp detail", "too many channels");
    }

    const npf::BrdfInfo& info() const override { return m_base.info(); }

    void eval_cos(const npf::Vec3& wi, const npf::Vec3& wo, const npf::ChannelQuery& query, float* out) const override {
        const std::size_t C = m_model.channel_count();
        double v[kMaxChannels];
        m_model.eval_all(wi, wo, v);
        if (wi.z > 0.f && wo.z > 0.f) {
            const double ix = wi.x, iy = wi.y, iz = wi.z, ox = wo.x, oy = wo.y, oz = wo.z;
            // NpfModel::prepare's angles for the detail layer.
            const double hx = ix + ox, hy = iy + oy, hz = iz + oz;
            const double length = std::sqrt(hx * hx + hy * hy + hz * hz);
            const double theta_h = npf::table::polar_of(std::sqrt(hx * hx + hy * hy), hz);
            const double u_h = std::sqrt(theta_h * (2.0 / npf::kPiD));
            const double cx = iy * oz - iz * oy, cy = iz * ox - ix * oz, cz = ix * oy - iy * ox;
            const double theta_d =
                npf::table::polar_of(std::sqrt(cx * cx + cy * cy + cz * cz), 1.0 + (ix * ox + iy * oy + iz * oz));
            const double phi_d = npf::detail_phi_d(ix, iy, iz, hx, hy, hz, length);
            const npf::DetailPosition at = npf::detail_position(m_knots, u_h, theta_d, phi_d);
            const npf::table::Lerp* lerp[3] = {&at.h, &at.d, &at.p};
            const std::size_t K = m_k;
            for (std::size_t c = 0; c < C; ++c) {
                const float* t = m_tables[c].data();
                const float* rows[3][2];
                std::size_t offset = 0;
                const int n[3] = {m_knots.theta_h, m_knots.theta_d, m_knots.phi_d};
                for (int m = 0; m < 3; ++m) {
                    rows[m][0] = t + offset + std::size_t(lerp[m]->i0) * K;
                    rows[m][1] = t + offset + std::size_t(lerp[m]->i1) * K;
                    offset += std::size_t(n[m]) * K;
                }
                const double ta = at.h.t, td = at.d.t, tp = at.p.t;
                double r = 0.0;
                for (std::size_t k = 0; k < K; ++k) {
                    const double a = rows[0][0][k] + ta * (rows[0][1][k] - rows[0][0][k]);
                    const double b = rows[1][0][k] + td * (rows[1][1][k] - rows[1][0][k]);
                    const double p = rows[2][0][k] + tp * (rows[2][1][k] - rows[2][0][k]);
                    r += a * b * p;
                }
                v[c] = m_clamp ? std::max(0.0, v[c] + r) : v[c] + r;
            }
        }
        for (std::size_t q = 0; q < query.size(); ++q) {
            const double w = query.weight1.empty() ? 0.0 : query.weight1[q];
            const double f = (1.0 - w) * v[query.index0[q]] + w * v[query.index1[q]];
            out[q] = float(f * double(std::max(wo.z, 0.f)));
        }
    }

    float pdf(const npf::Vec3& wi, const npf::Vec3& wo) const override { return m_base.pdf(wi, wo); }

    bool sample(const npf::Vec3& wi, const npf::Vec2& u, const npf::ChannelQuery& query, npf::BrdfSample& s,
                float* weight) const override {
        if (!m_base.sample(wi, u, query, s, nullptr) || !(s.pdf > 0.f)) {
            if (weight) std::fill(weight, weight + query.size(), 0.f);
            return false;
        }
        if (weight) {
            eval_cos(wi, s.wo, query, weight);
            for (std::size_t q = 0; q < query.size(); ++q) weight[q] /= s.pdf;
        }
        return true;
    }

    npf::ChannelQuery query(const npf::Channels& requested) const override { return m_base.query(requested); }

private:
    npf::NpfBrdf m_base;
    NpfModel m_model;
    DetailGrid m_knots;
    std::size_t m_k;
    std::vector<std::vector<float>> m_tables;  // per channel: [n_u][K], [n_theta_d][K], [n_phi_d][K]
    bool m_clamp = true;
};

// ---- Measurements -----------------------------------------------------------------------------

struct Settings {
    std::string work = "/tmp/npf_detail_families";
    std::vector<std::string> families = {"grid", "hybrid", "cp"};
    std::vector<DetailGrid> grids = {{16, 8, 16}, {20, 10, 20}, {28, 10, 28}, {32, 12, 32}, {32, 16, 32}};
    std::vector<DetailGrid> hybrids = {{90, 4, 6}, {90, 6, 8}, {90, 8, 12}, {90, 8, 16}, {90, 12, 16}};
    DetailGrid cp_tables{90, 32, 64};
    std::vector<int> cp_ranks = {11, 22, 45, 90};
    int cp_sweeps = 30, cp_cg = 25, cp_init_iterations = 30;
    double cp_tolerance = 0.01;  // a sweep closing less of the gap to the unconstrained optimum ends the fit
    bool trace = false;
    bool cp_reference = true;  // also render the unconstrained knot grid
    bool cp_unclamped = false;  // diagnostic: also measure the products without the clamp at 0
    int threads = 0;
    std::size_t size = 256;
    std::uint32_t spp = 128;
    std::string tsv;
};

const std::vector<double> kAlbedoThetas = {0, 20, 40, 60, 70, 80};

std::vector<npf::AlbedoRow> albedo_of(const npf::Brdf& b, const Settings& s) {
    npf::AlbedoTableOptions a;
    a.theta_deg = kAlbedoThetas;
    a.estimator.samples = 64;
    a.threads = s.threads;
    return npf::directional_albedo_table(b, b.native_query(), a);
}

// The largest relative albedo error over the views and channels, and its view (degrees).
double worst_albedo_error(const std::vector<npf::AlbedoRow>& model, const std::vector<npf::AlbedoRow>& raw,
                          double& theta_deg) {
    double worst = 0.0;
    for (std::size_t r = 0; r < raw.size(); ++r) {
        for (std::size_t c = 0; c < raw[r].albedo.size(); ++c) {
            if (!(raw[r].albedo[c] > 0.0)) continue;
            const double e = std::fabs(model[r].albedo[c] / raw[r].albedo[c] - 1.0);
            if (e > worst) worst = e, theta_deg = raw[r].theta_deg;
        }
    }
    return worst;
}

npf::render::RenderOptions render_options(const Settings& s) {
    npf::render::RenderOptions o;
    o.width = o.height = s.size;
    o.spp = s.spp;
    o.seed = 1;
    o.threads = unsigned(s.threads);
    o.sampling = npf::render::Sampling::Environment;
    return o;
}

struct Row {
    std::string family, shape, note;
    std::size_t bytes = 0;
    double fit_seconds = 0.0, psnr = 0.0, albedo = 0.0, render_seconds = 0.0;
};

class Material {
public:
    Material(const std::string& path, const Settings& s, const npf::render::EnvironmentMap& env)
        : m_settings(s), m_env(env) {
        m_name = std::filesystem::path(path).stem().string();
        m_source = npf::open_material(path);
        const std::string base_path = s.work + "/" + m_name + ".base.npf.exr";
        if (!std::filesystem::exists(base_path)) {
            npf::ConvertSettings cs = npf::preset_settings(npf::ConvertPreset::Production, m_source->info().isotropic);
            cs.detail.grid = DetailGrid{};  // npf convert --detail none
            cs.fit.threads = s.threads;
            const auto t = Clock::now();
            const npf::ConvertReport r = npf::convert_material(*m_source, base_path, cs);
            std::printf("%s: base fit (production, --detail none) %.1f s, wrote %s\n", m_name.c_str(), seconds_since(t),
                        base_path.c_str());
            (void)r;
        }
        m_base = npf::read_npf_texture(base_path);
        m_detail_options = npf::preset_settings(npf::ConvertPreset::Production, m_source->info().isotropic).detail;
        m_detail_options.threads = s.threads;

        const std::string raw_path = s.work + "/" + m_name + ".raw." + std::to_string(s.size) + "." +
                                     std::to_string(s.spp) + "spp.seed1.env.exr";
        if (std::filesystem::exists(raw_path)) {
            m_raw_image = npf::color::read_scene_image(raw_path);
        } else {
            const npf::render::RenderOptions o = render_options(s);
            const npf::render::RenderResult r = npf::render::render(*m_source, m_env, o);
            npf::render::write_render_exr(raw_path, r, npf::render::describe_render(r, o, m_env));
            m_raw_image = r.image;
            std::printf("%s: raw render %.1f s, wrote %s\n", m_name.c_str(), r.stats.seconds, raw_path.c_str());
        }
        m_raw_albedo = albedo_of(*m_source, s);
    }

    const std::string& name() const { return m_name; }
    const npf::Brdf& source() const { return *m_source; }
    const NpfModel& base() const { return m_base; }
    const npf::DetailOptions& detail_options() const { return m_detail_options; }

    Row measure(const npf::Brdf& b, Row row) const {
        const npf::render::RenderResult r = npf::render::render(b, m_env, render_options(m_settings));
        row.render_seconds = r.stats.seconds;
        row.psnr = npf::render::compare_images(m_raw_image, r.image).psnr;
        double theta = 0.0;
        row.albedo = worst_albedo_error(albedo_of(b, m_settings), m_raw_albedo, theta);
        row.note += (row.note.empty() ? "" : "; ") + std::string("albedo worst at ") + std::to_string(int(theta)) + " deg";
        return row;
    }

private:
    const Settings& m_settings;
    const npf::render::EnvironmentMap& m_env;
    std::string m_name;
    std::unique_ptr<npf::Brdf> m_source;
    NpfModel m_base;
    npf::DetailOptions m_detail_options;
    npf::color::FloatImage m_raw_image;
    std::vector<npf::AlbedoRow> m_raw_albedo;
};

void print_row(const std::string& material, const Row& r, std::FILE* tsv) {
    std::printf("%-28s %-7s %-12s %9.1f %8.2f %8.2f %9.2f  %s\n", material.c_str(), r.family.c_str(), r.shape.c_str(),
                double(r.bytes) / 1000.0, r.fit_seconds, r.psnr, 100.0 * r.albedo, r.note.c_str());
    std::fflush(stdout);
    if (tsv) {
        std::fprintf(tsv, "%s\t%s\t%s\t%zu\t%.3f\t%.3f\t%.4f\t%.2f\t%s\n", material.c_str(), r.family.c_str(),
                     r.shape.c_str(), r.bytes, r.fit_seconds, r.psnr, 100.0 * r.albedo, r.render_seconds, r.note.c_str());
        std::fflush(tsv);
    }
}

bool wants(const Settings& s, const std::string& family) {
    return std::find(s.families.begin(), s.families.end(), family) != s.families.end();
}

void grid_rows(const Material& mat, const std::string& family, const std::vector<DetailGrid>& grids, std::FILE* tsv) {
    for (const DetailGrid& g : grids) {
        npf::DetailOptions o = mat.detail_options();
        o.grid = g;
        NpfModel model = mat.base();
        const npf::DetailReport rep = npf::fit_detail_layer(mat.source(), model, o);
        const std::size_t C = model.channel_count(), rank = std::size_t(model.detail.rank);
        Row row;
        row.family = family;
        row.shape = grid_text(g);
        // The half basis tables and the per-channel weights (float).
        row.bytes = rank * g.cells() * 2 + C * rank * 4;
        row.fit_seconds = rep.seconds;
        char note[160];
        std::snprintf(note, sizeof note, "rank %zu; fit's albedo error %.2f %%; weighted error %.4g -> %.4g", rank,
                      100.0 * rep.energy_error_after, rep.weighted_error_before, rep.weighted_error_after);
        row.note = note;
        const npf::NpfBrdf brdf(model);
        print_row(mat.name(), mat.measure(brdf, row), tsv);
    }
}

void cp_rows(const Material& mat, const Settings& s, int threads, std::FILE* tsv) {
    npf::DetailOptions o = mat.detail_options();
    o.grid = s.cp_tables;
    const NpfModel& base = mat.base();
    const std::size_t C = base.channel_count();

    // The detail fitter's problem on the knot grid, and its unconstrained solution (each channel).
    auto t = Clock::now();
    const fd::DetailSystem sys = fd::assemble_detail_system(mat.source(), base, o, threads);
    const double assembly_seconds = seconds_since(t);
    t = Clock::now();
    std::vector<std::vector<double>> free_solution(C, std::vector<double>(sys.cells, 0.0));
    std::vector<double> free_objective(C);
    std::vector<int> free_iterations(C, 0);
    // Channels in parallel, each on one thread (as the fitter runs its weight groups).
    npf::parallel_slices(C, std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c) {
            const fd::NormalOperator op = fd::NormalOperator::of(sys, c);
            free_iterations[c] = fd::solve(op, sys.rhs[c], free_solution[c], o.max_iterations, o.tolerance);
            std::vector<double> ax(sys.cells);
            op.apply(free_solution[c], ax);
            free_objective[c] = dot(free_solution[c], ax) - 2.0 * dot(sys.rhs[c], free_solution[c]);
        }
    }, threads);
    const double free_seconds = seconds_since(t);
    std::printf("%s: cp knot grid %s: %zu samples, assembly %.1f s; unconstrained solve %.1f s (%d CG iterations)\n",
                mat.name().c_str(), grid_text(s.cp_tables).c_str(), sys.samples_valid, assembly_seconds, free_seconds,
                *std::max_element(free_iterations.begin(), free_iterations.end()));

    if (s.cp_reference) {  // the knot grid itself, unconstrained: what rank K approaches
        std::vector<float> tables(C * sys.cells);
        for (std::size_t c = 0; c < C; ++c)
            for (std::size_t i = 0; i < sys.cells; ++i) tables[c * sys.cells + i] = float(free_solution[c][i]);
        NpfModel model = base;
        model.detail_grid = s.cp_tables;
        model.detail = npf::compress_tables(tables, C, sys.cells, o.ratio, o.rank);
        for (float& v : model.detail.basis) v = float(Imath::half(v));
        Row row;
        row.family = "knots";
        row.shape = grid_text(s.cp_tables);
        row.bytes = std::size_t(model.detail.rank) * sys.cells * 2 + C * std::size_t(model.detail.rank) * 4;
        row.fit_seconds = assembly_seconds + free_seconds;
        double before = 0.0, after = 0.0;
        for (std::size_t c = 0; c < C; ++c) {
            before += sys.data_norm[c] > 0.0 ? sys.data_error[c] / sys.data_norm[c] / double(C) : 0.0;
            after += weighted_error(sys, c, free_solution[c]) / double(C);
        }
        char note[160];
        std::snprintf(note, sizeof note, "the knot grid unconstrained, rank %d; weighted error %.4g -> %.4g",
                      model.detail.rank, before, after);
        row.note = note;
        const npf::NpfBrdf brdf(model);
        print_row(mat.name(), mat.measure(brdf, row), tsv);
    }
    for (const int rank : s.cp_ranks) {
        t = Clock::now();
        // Channels in parallel, each fitted on one thread: the alternating solves are many small
        // steps, which on shared cores lose more to handing work between threads than they gain.
        const CpKernels ker(s.cp_tables, rank, 1);
        std::vector<std::vector<float>> tables(C);
        std::vector<double> albedo(sys.albedo_base), shares(C, 1.0), errors(C, 0.0);
        std::vector<int> sweeps(C, 0);
        std::vector<float> knot_values(C * sys.cells);  // the stored products on the knot grid, for the check below
        npf::parallel_slices(C, std::size_t(threads), [&](std::size_t, std::size_t begin, std::size_t end) {
            for (std::size_t c = begin; c < end; ++c) {
                CpFactors cp = unweighted_cp(free_solution[c], ker, s.cp_init_iterations,
                                             1234u + unsigned(c) * 7919u + unsigned(rank));
                const CpFitStats st =
                    weighted_als(sys, c, cp, ker, s.cp_sweeps, s.cp_cg, s.cp_tolerance, free_objective[c], 1, s.trace);
                sweeps[c] = st.sweeps;
                if (free_objective[c] < 0.0) shares[c] = st.objective / free_objective[c];
                for (int m = 0; m < 3; ++m)
                    for (double v : cp.f[m]) tables[c].push_back(float(v));
                std::vector<double> r(sys.cells);
                ker.reconstruct(cp.f[0].data(), cp.f[1].data(), cp.f[2].data(), r.data());
                for (std::size_t v = 0; v < sys.views(); ++v) albedo[v * C + c] += dot(sys.rows[v], r);
                for (std::size_t i = 0; i < sys.cells; ++i) knot_values[c * sys.cells + i] = float(r[i]);
                errors[c] = weighted_error(sys, c, r);
            }
        }, threads);
        double share = 0.0, error = 0.0;
        for (std::size_t c = 0; c < C; ++c) {
            share += shares[c] / double(C);
            error += errors[c] / double(C);
        }
        Row row;
        row.family = "cp";
        row.shape = "K=" + std::to_string(rank) + " " + grid_text(s.cp_tables);
        row.bytes = C * std::size_t(rank) *
                    std::size_t(s.cp_tables.theta_h + s.cp_tables.theta_d + s.cp_tables.phi_d) * 2;
        row.fit_seconds = assembly_seconds + free_seconds + seconds_since(t);
        char note[200];
        std::snprintf(note, sizeof note,
                      "%d sweeps max; fit's albedo error %.2f %%; weighted error %.4g; objective %.4f of the knot grid's",
                      *std::max_element(sweeps.begin(), sweeps.end()), 100.0 * sys.energy_error(albedo), error, share);
        row.note = note;
        const CpDetailBrdf brdf(base, s.cp_tables, rank, tables);
        {  // The products shade as the trilinear knot grid the fit optimised (NpfModel's own lookup).
            NpfModel as_grid = base;
            as_grid.detail_grid = s.cp_tables;
            as_grid.detail = npf::compress_tables(knot_values, C, sys.cells, 1.0, 0);
            const npf::NpfBrdf grid_brdf(as_grid);
            std::mt19937 rng(7);
            std::uniform_real_distribution<float> uni(0.f, 1.f);
            auto direction = [&]() {
                const float z = uni(rng), phi = 2.f * float(npf::kPiD) * uni(rng), r = std::sqrt(std::max(0.f, 1.f - z * z));
                return npf::Vec3(r * std::cos(phi), r * std::sin(phi), z);
            };
            const npf::ChannelQuery q = brdf.native_query();
            std::vector<float> x(q.size()), y(q.size());
            double worst = 0.0;
            for (int n = 0; n < 20000; ++n) {
                const npf::Vec3 wi = direction(), wo = direction();
                brdf.eval_cos(wi, wo, q, x.data());
                grid_brdf.eval_cos(wi, wo, q, y.data());
                for (std::size_t c = 0; c < q.size(); ++c)
                    worst = std::max(worst, double(std::fabs(x[c] - y[c])) / (std::fabs(double(y[c])) + 1e-3));
            }
            row.note += "; shading check " + std::to_string(worst);
        }
        print_row(mat.name(), mat.measure(brdf, row), tsv);
        if (s.cp_unclamped) {  // diagnostic: the same products without the clamp at 0
            const CpDetailBrdf unclamped(base, s.cp_tables, rank, tables, false);
            Row diag = row;
            diag.family = "cp-noclamp";
            diag.note.clear();
            print_row(mat.name(), mat.measure(unclamped, diag), tsv);
        }
    }
}

}  // namespace

int main(int argc, char** argv) try {
    Settings s;
    std::vector<std::string> materials;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("--", 0) != 0) {
            materials.push_back(a);
            continue;
        }
        if (i + 1 >= argc) throw npf::Error(a, "needs a value");
        const std::string v = argv[++i];
        if (a == "--work") s.work = v;
        else if (a == "--families") s.families = split(v, ',');
        else if (a == "--grid") s.grids = parse_grids(a, v);
        else if (a == "--hybrid") s.hybrids = parse_grids(a, v);
        else if (a == "--cp-tables") s.cp_tables = parse_grid(a, v);
        else if (a == "--cp-ranks") {
            s.cp_ranks.clear();
            for (const std::string& r : split(v, ',')) s.cp_ranks.push_back(positive(a, r));
        } else if (a == "--cp-sweeps") s.cp_sweeps = positive(a, v);
        else if (a == "--cp-cg") s.cp_cg = positive(a, v);
        else if (a == "--threads") s.threads = positive(a, v);
        else if (a == "--size") s.size = std::size_t(positive(a, v));
        else if (a == "--spp") s.spp = std::uint32_t(positive(a, v));
        else if (a == "--tsv") s.tsv = v;
        else if (a == "--cp-tolerance") s.cp_tolerance = std::atof(v.c_str());
        else if (a == "--trace") s.trace = v == "1";
        else if (a == "--cp-reference") s.cp_reference = v == "1";
        else if (a == "--cp-unclamped") s.cp_unclamped = v == "1";
        else throw npf::Error(a, "unknown option");
    }
    if (materials.empty()) {
        std::fprintf(stderr,
                     "usage: npf_bench_detail_families M.bsdf [M2.bsdf ...] [--work DIR] [--families grid,hybrid,cp]\n"
                     "       [--grid 16x8x16,...] [--hybrid 90x4x6,...] [--cp-tables 90x32x64] [--cp-ranks 11,22,45,90]\n"
                     "       [--cp-sweeps N] [--cp-cg N] [--cp-tolerance T] [--cp-reference 0|1] [--cp-unclamped 0|1]\n"
                     "       [--trace 0|1] [--threads N] [--size N] [--spp N] [--tsv FILE]\n");
        return 2;
    }
    const int threads = npf::thread_count(s.threads);
    std::filesystem::create_directories(s.work);
    std::FILE* tsv = s.tsv.empty() ? nullptr : std::fopen(s.tsv.c_str(), "a");
    if (!s.tsv.empty() && !tsv) throw npf::Error(s.tsv, "cannot open for appending");
    const npf::render::EnvironmentMap env = npf::render::EnvironmentMap::load(npf::render::default_environment_map_path());
    std::printf("renders: Sphere %zux%zu, %u spp, env sampling, seed 1, %s; albedo: views 0,20,40,60,70,80, "
                "64 x 64 cells; %d threads\n",
                s.size, s.size, s.spp, env.source().c_str(), threads);
    std::printf("%-28s %-7s %-12s %9s %8s %8s %9s  %s\n", "material", "family", "shape", "kB", "fit s", "PSNR",
                "albedo %", "notes");
    for (const std::string& path : materials) {
        const Material mat(path, s, env);
        {
            Row row;
            row.family = "base";
            row.shape = "none";
            const npf::NpfBrdf brdf(mat.base());
            print_row(mat.name(), mat.measure(brdf, row), tsv);
        }
        if (wants(s, "grid")) grid_rows(mat, "grid", s.grids, tsv);
        if (wants(s, "hybrid")) grid_rows(mat, "hybrid", s.hybrids, tsv);
        if (wants(s, "cp")) cp_rows(mat, s, threads, tsv);
    }
    if (tsv) std::fclose(tsv);
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "npf_bench_detail_families: %s\n", e.what());
    return 1;
}
