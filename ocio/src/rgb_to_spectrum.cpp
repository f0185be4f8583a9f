// linear_srgb_to_spectrum: a smooth reflectance spectrum with a given linear sRGB colour.
//
// Method. The unknowns are the values s_0..s_94 of a piecewise-linear spectrum on 360..830 nm
// every 5 nm. Its XYZ under the project's convention is exactly A s, with A = xyz_weights(grid)
// (3 x 95), so matching the colour is the equality constraint A s = t, t = XYZ of `rgb`. Among
// those spectra we take the smoothest: minimise |D s|^2, D the 93 x 95 second-difference
// matrix. Its null space (constant and linear spectra) meets A's only in 0, so the KKT system
//     [ H  -A^T ] [ s  ]   [ 0 ]
//     [ A   0   ] [ mu ] = [ t ]      H = D^T D
// is regular and the solution is linear in t; that matrix (95 x 3) is computed once.
//
// Bounds. A reflectance should lie in [0, 1]. When the unconstrained solution leaves that
// range, an active-set method solves the bounded problem exactly. Phase 1 fixes the values
// outside the bounds at the bound they crossed and solves the reduced KKT system (free values
// only) again, until nothing is outside: a feasible spectrum with the exact colour. Phase 2,
// a primal active-set method (Nocedal & Wright, algorithm 16.3) started there, releases fixed
// values whose multipliers have the wrong sign (phase 1 fixes a few too many) and refixes
// values that reach a bound, until the KKT conditions hold. Checked against general solvers
// (SciPy SLSQP) on random colours: the same objective to 1e-7.
//
// Infeasible bounds. Some colours have no spectrum within [0, 1] at all: components above 1,
// many colours outside the sRGB gamut, and a thin sliver at the white corner, including
// (1, 1, 1) itself and e.g. (0.99, 1, 1), because the standard matrix's white (x, y = 0.3127,
// 0.3290) is not quite the tabulated D65's (2.4e-4 less blue). Phase 1 then runs out of free
// values (the reduced system cannot reach the colour; it retries fixing one value per round
// before giving up, so as not to give up on feasible colours near the edge). Then the bounds
// are relaxed, never the colour: first to s >= 0 only (bright colours such as (2, 2, 2)), and
// if that is infeasible too (outside the spectral locus) to no bounds at all, the unconstrained
// solution. These feasibility decisions agree with an LP feasibility test on 3000 random
// colours in [-0.3, 1.3]^3. So the round trip spectrum_to_xyz -> xyz_to_linear_srgb returns
// `rgb` to rounding for every finite input; only the [0, 1] property may be lost, and for the
// white sliver by at most about 1.5e-3.
//
// Cost: nothing for colours whose smooth solution is already in [0, 1] (greys, pastels);
// about 0.5 to 6 ms otherwise (dense solves of ~100 unknowns): meant for material parameters,
// not per texel.
#include <npf/color/spectrum.h>
#include <npf/core/error.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace npf::color {

namespace {

constexpr int kFirstNm = 360;
constexpr int kStepNm = 5;
constexpr int kN = (830 - kFirstNm) / kStepNm + 1;  // 95
constexpr double kValueTol = 1e-12;  // this far past a bound still counts as inside

struct Setup {
    std::vector<double> grid;
    // Dynamic sizes keep these (and their construction) off the stack.
    Eigen::MatrixXd a;          // 3 x kN: XYZ of the piecewise-linear spectrum
    Eigen::MatrixXd h;          // kN x kN: D^T D
    Eigen::MatrixXd smoothest;  // kN x 3: unbounded solution, s = smoothest * t
};

const Setup& setup() {
    static const Setup su = [] {
        Setup s;
        std::vector<float> grid_f(kN);
        s.grid.resize(kN);
        for (int i = 0; i < kN; ++i) {
            s.grid[i] = kFirstNm + kStepNm * i;
            grid_f[i] = static_cast<float>(s.grid[i]);
        }
        const auto w = xyz_weights(grid_f);
        s.a.resize(3, kN);
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < kN; ++i) s.a(c, i) = w[c][i];
        Eigen::MatrixXd d = Eigen::MatrixXd::Zero(kN - 2, kN);
        for (int r = 0; r < kN - 2; ++r) {
            d(r, r) = 1.0;
            d(r, r + 1) = -2.0;
            d(r, r + 2) = 1.0;
        }
        s.h = d.transpose() * d;
        Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(kN + 3, kN + 3);
        kkt.topLeftCorner(kN, kN) = s.h;
        kkt.topRightCorner(kN, 3) = -s.a.transpose();
        kkt.bottomLeftCorner(3, kN) = s.a;
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(kN + 3, 3);
        rhs.bottomRows(3).setIdentity();
        s.smoothest = kkt.fullPivLu().solve(rhs).topRows(kN);
        return s;
    }();
    return su;
}

enum class Bound : char { Free, Lower, Upper };

// Minimises s^T H s subject to A s = t and s_i = bound for the fixed values. Returns false when
// the free values cannot match t (too many fixed, or a colour out of reach). On success, `g`
// holds the gradient of the Lagrangian, H s - A^T mu: zero on free values; a value fixed at
// its lower bound is optimal when g >= 0, at its upper bound when g <= 0.
bool solve_reduced(const Setup& su, const std::array<Bound, kN>& state, double lo, double hi,
                   const Eigen::Vector3d& t, Eigen::Matrix<double, kN, 1>& s,
                   Eigen::Matrix<double, kN, 1>& g) {
    std::vector<int> free;
    for (int i = 0; i < kN; ++i) {
        s[i] = state[i] == Bound::Lower ? lo : state[i] == Bound::Upper ? hi : 0.0;
        if (state[i] == Bound::Free) free.push_back(i);
    }
    const int nf = static_cast<int>(free.size());
    if (nf == 0) return false;
    const Eigen::Matrix<double, kN, 1> h_fixed = su.h * s;  // s holds the fixed values only
    const Eigen::Vector3d t_free = t - su.a * s;
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(nf + 3, nf + 3);
    Eigen::VectorXd rhs(nf + 3);
    for (int p = 0; p < nf; ++p) {
        for (int q = 0; q < nf; ++q) kkt(p, q) = su.h(free[p], free[q]);
        for (int c = 0; c < 3; ++c) {
            kkt(p, nf + c) = -su.a(c, free[p]);
            kkt(nf + c, p) = su.a(c, free[p]);
        }
        rhs[p] = -h_fixed[free[p]];
    }
    rhs.tail(3) = t_free;
    const Eigen::VectorXd x = kkt.partialPivLu().solve(rhs);
    if (!x.allFinite()) return false;
    for (int p = 0; p < nf; ++p) s[free[p]] = x[p];
    // A singular system (fewer usable free values than constraints) still returns something:
    // accept it only if it matches the colour.
    if ((su.a * s - t).norm() > 1e-10 * (1.0 + t.norm())) return false;
    g = su.h * s - su.a.transpose() * x.tail(3);
    return true;
}

// Phase 1 of solve_bounded: fix values that leave the bounds at the bound they crossed and
// solve again, never releasing any; all violators at once, or only the worst one per round
// (slower, but less likely to fix values the colour needs free). The fixed set only grows, so
// this ends, with a feasible spectrum (the best one for its fixed set) or with false when
// the free values can no longer reach the colour.
bool fix_until_feasible(const Setup& su, double lo, double hi, const Eigen::Vector3d& t,
                        bool one_at_a_time, std::array<Bound, kN>& state,
                        Eigen::Matrix<double, kN, 1>& s) {
    Eigen::Matrix<double, kN, 1> g;
    state.fill(Bound::Free);
    for (int iter = 0; iter <= kN; ++iter) {
        if (!solve_reduced(su, state, lo, hi, t, s, g)) return false;
        int worst = -1;
        double worst_excess = kValueTol;
        for (int i = 0; i < kN; ++i) {
            if (state[i] != Bound::Free) continue;
            const double excess = std::max(lo - s[i], s[i] - hi);
            if (excess <= kValueTol) continue;
            if (!one_at_a_time) state[i] = s[i] < lo ? Bound::Lower : Bound::Upper;
            if (excess > worst_excess) worst_excess = excess, worst = i;
        }
        if (worst < 0) {
            s = s.cwiseMax(lo).cwiseMin(hi);
            return true;
        }
        if (one_at_a_time) state[worst] = s[worst] < lo ? Bound::Lower : Bound::Upper;
    }
    return false;
}

// The bounded problem lo <= s <= hi (hi may be infinite). Returns false if infeasible, as far
// as phase 1 can tell.
bool solve_bounded(const Setup& su, double lo, double hi, const Eigen::Vector3d& t,
                   Eigen::Matrix<double, kN, 1>& s) {
    constexpr double kGradTol = 1e-9;
    std::array<Bound, kN> state;
    if (!fix_until_feasible(su, lo, hi, t, false, state, s) &&
        !fix_until_feasible(su, lo, hi, t, true, state, s))
        return false;
    Eigen::Matrix<double, kN, 1> g, next;

    // Phase 2: phase 1 may have fixed values that the optimum leaves free. Primal active set
    // (Nocedal & Wright, algorithm 16.3) from that feasible start: release the fixed value
    // whose multiplier has the most wrong sign, move towards the new optimum until a free
    // value meets a bound, fix that one, and so on. Every step stays feasible and keeps the
    // colour, so stopping early (iteration cap, singular system) still returns a valid answer.
    for (int iter = 0; iter < 4 * kN; ++iter) {
        if (!solve_reduced(su, state, lo, hi, t, next, g)) break;
        double alpha = 1.0;
        int blocking = -1;
        for (int i = 0; i < kN; ++i) {
            if (state[i] != Bound::Free) continue;
            const double step = next[i] - s[i];
            if (next[i] < lo - kValueTol && step < 0.0 && (lo - s[i]) / step < alpha)
                alpha = (lo - s[i]) / step, blocking = i;
            else if (next[i] > hi + kValueTol && step > 0.0 && (hi - s[i]) / step < alpha)
                alpha = (hi - s[i]) / step, blocking = i;
        }
        if (blocking >= 0) {
            const bool low = next[blocking] < lo;
            s = (s + alpha * (next - s)).cwiseMax(lo).cwiseMin(hi);
            s[blocking] = low ? lo : hi;
            state[blocking] = low ? Bound::Lower : Bound::Upper;
            continue;
        }
        s = next.cwiseMax(lo).cwiseMin(hi);
        int release = -1;
        double worst = kGradTol;
        for (int i = 0; i < kN; ++i) {
            const double wrong = state[i] == Bound::Lower ? -g[i] : state[i] == Bound::Upper ? g[i] : 0.0;
            if (wrong > worst) worst = wrong, release = i;
        }
        if (release < 0) break;  // KKT conditions hold: the optimum
        state[release] = Bound::Free;
    }
    return true;
}

}  // namespace

SampledSpectrum linear_srgb_to_spectrum(const Rgb& rgb) {
    if (!std::isfinite(rgb[0]) || !std::isfinite(rgb[1]) || !std::isfinite(rgb[2]))
        throw Error("linear_srgb_to_spectrum", "non-finite colour");
    const Setup& su = setup();
    const Xyz xyz = linear_srgb_to_xyz(rgb);
    const Eigen::Vector3d t(xyz[0], xyz[1], xyz[2]);
    Eigen::Matrix<double, kN, 1> s = su.smoothest * t;
    const double inf = std::numeric_limits<double>::infinity();
    if (s.minCoeff() < 0.0 || s.maxCoeff() > 1.0) {
        if (!solve_bounded(su, 0.0, 1.0, t, s) && !solve_bounded(su, 0.0, inf, t, s))
            s = su.smoothest * t;  // no bounds: exact colour, values of either sign
    }
    return SampledSpectrum(su.grid, std::vector<double>(s.data(), s.data() + kN));
}

SampledSpectrum srgb_to_spectrum(double r, double g, double b) {
    return linear_srgb_to_spectrum({srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b)});
}

}  // namespace npf::color
