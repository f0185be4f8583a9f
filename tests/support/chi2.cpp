#include "chi2.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <cstdio>
#include <limits>
#include <numeric>
#include <sstream>

namespace npf::testing {

// ---- Statistics -------------------------------------------------------------------------

namespace {

constexpr double kEps = 1e-15;       // relative accuracy we iterate to
constexpr double kTiny = 1e-300;     // keeps Lentz's denominators away from zero
constexpr int kMaxIterations = 100000;

// log of the common prefactor x^a e^-x / Gamma(a), in logs so large a and x do not overflow.
double log_prefactor(double a, double x) { return a * std::log(x) - x - std::lgamma(a); }

// P(a, x) by its power series, P = x^a e^-x / Gamma(a + 1) * sum_n x^n / ((a+1)...(a+n)).
// All terms are positive, so it is accurate; it converges fast for x < a + 1.
double gamma_p_series(double a, double x) {
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < kMaxIterations; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::fabs(term) < std::fabs(sum) * kEps) break;
    }
    return sum * std::exp(log_prefactor(a, x));
}

// Q(a, x) by Legendre's continued fraction
//   Q = x^a e^-x / Gamma(a) * 1 / (x + 1 - a - 1(1-a) / (x + 3 - a - 2(2-a) / (x + 5 - a - ...)))
// evaluated with the modified Lentz method. Converges fast for x > a + 1, and gives small Q
// with full relative precision, which 1 - P could not.
double gamma_q_continued_fraction(double a, double x) {
    double b = x + 1.0 - a;
    double c = 1.0 / kTiny;
    double d = 1.0 / b;
    double h = d;
    for (int i = 1; i < kMaxIterations; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < kTiny) d = kTiny;
        c = b + an / c;
        if (std::fabs(c) < kTiny) c = kTiny;
        d = 1.0 / d;
        double delta = d * c;
        h *= delta;
        if (std::fabs(delta - 1.0) < kEps) break;
    }
    return std::exp(log_prefactor(a, x)) * h;
}

}  // namespace

double regularized_gamma_p(double a, double x) {
    if (!(a > 0.0) || !(x >= 0.0)) return std::numeric_limits<double>::quiet_NaN();
    if (x == 0.0) return 0.0;
    if (std::isinf(x)) return 1.0;
    if (x < a + 1.0) return gamma_p_series(a, x);
    return 1.0 - gamma_q_continued_fraction(a, x);
}

double regularized_gamma_q(double a, double x) {
    if (!(a > 0.0) || !(x >= 0.0)) return std::numeric_limits<double>::quiet_NaN();
    if (x == 0.0) return 1.0;
    if (std::isinf(x)) return 0.0;
    if (x < a + 1.0) return 1.0 - gamma_p_series(a, x);
    return gamma_q_continued_fraction(a, x);
}

double chi2_sf(double x, double dof) {
    if (!(dof > 0.0) || std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
    if (x <= 0.0) return 1.0;
    return regularized_gamma_q(0.5 * dof, 0.5 * x);
}

// ---- PCG32 --------------------------------------------------------------------------------

Pcg32::Pcg32(std::uint64_t seed, std::uint64_t stream) {
    // The reference seeding sequence: the increment must be odd.
    m_state = 0;
    m_inc = (stream << 1u) | 1u;
    next_u32();
    m_state += seed;
    next_u32();
}

std::uint32_t Pcg32::next_u32() {
    std::uint64_t old = m_state;
    m_state = old * 6364136223846793005ULL + m_inc;
    auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

float Pcg32::next_float() {
    return static_cast<float>(next_u32() >> 8) * (1.0f / 16777216.0f);
}

// ---- The test -----------------------------------------------------------------------------

namespace {

constexpr double kTwoPi = 2.0 * kPiD;

struct Grid {
    int rows = 0, cols = 0;
    int hemi_rows = 0;        // rows per hemisphere
    int upper_first_row = 0;  // first row with z > 0: hemi_rows for the full sphere, else 0
    double z_min = 0.0;       // -1 for the full sphere, 0 for the hemisphere
    double dz = 0.0, dphi = 0.0;

    // Cell of a unit direction, or -1 when it lies outside the grid (below the horizon of a
    // hemisphere-only grid). z = 0 exactly counts as below the horizon: it is not a valid
    // sample direction.
    int cell(const Vec3& w) const {
        double z = std::clamp(static_cast<double>(w.z), -1.0, 1.0);
        int row;
        if (z > 0.0) {
            row = upper_first_row + std::min(static_cast<int>(z / dz), hemi_rows - 1);
        } else {
            if (upper_first_row == 0) return -1;
            row = std::clamp(static_cast<int>((z + 1.0) / dz), 0, hemi_rows - 1);
        }
        double phi = std::atan2(static_cast<double>(w.y), static_cast<double>(w.x));
        if (phi < 0.0) phi += kTwoPi;
        int col = std::clamp(static_cast<int>(phi / dphi), 0, cols - 1);
        return row * cols + col;
    }
};

std::string format_double(double v, int precision = 4) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    return buf;
}

std::string describe_cell(const Grid& g, int index, double observed, double expected) {
    int row = index / g.cols, col = index % g.cols;
    double z0 = g.z_min + row * g.dz, z1 = z0 + g.dz;
    double p0 = col * g.dphi * 180.0 / kPiD, p1 = (col + 1) * g.dphi * 180.0 / kPiD;
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "cos(theta) in [%.3f, %.3f), phi in [%.1f, %.1f) deg: observed %.0f, "
                  "expected %.2f",
                  z0, z1, p0, p1, observed, expected);
    return buf;
}


// The cells: cos(theta) rows (both hemispheres with opt.full_sphere) by phi columns.
Grid make_grid(const Chi2Options& opt) {
    Grid g;
    g.cols = std::max(1, opt.phi_bins);
    g.hemi_rows = std::max(1, opt.cos_theta_bins);
    g.rows = opt.full_sphere ? 2 * g.hemi_rows : g.hemi_rows;
    g.upper_first_row = opt.full_sphere ? g.hemi_rows : 0;
    g.z_min = opt.full_sphere ? -1.0 : 0.0;
    g.dz = 1.0 / g.hemi_rows;
    g.dphi = kTwoPi / g.cols;
    return g;
}

// Draws opt.sample_count samples into r.observed and counts failed, invalid and below-horizon
// ones; every so often compares the sample's pdf with pdf(wi, wo).
void count_samples(const Brdf& brdf, const Vec3& wi, const Chi2Options& opt, const Grid& g, Chi2Result& r) {
    // -- Observed counts. --
    ChannelQuery empty_query;
    const ChannelQuery& query = opt.query ? *opt.query : empty_query;
    std::vector<float> weight(opt.query ? std::max<std::size_t>(1, query.size()) : 0);
    const std::uint64_t check_stride =
        std::max<std::uint64_t>(1, opt.sample_count / std::max<std::uint64_t>(1, opt.pdf_check_count));

    Pcg32 rng(opt.seed);
    for (std::uint64_t i = 0; i < opt.sample_count; ++i) {
        Vec2 u;
        u.x = rng.next_float();
        u.y = rng.next_float();
        BrdfSample s;
        bool ok = brdf.sample(wi, u, query, s, opt.query ? weight.data() : nullptr);
        if (!ok) {
            ++r.failed_samples;
            continue;
        }
        bool valid = std::isfinite(s.wo.x) && std::isfinite(s.wo.y) && std::isfinite(s.wo.z) &&
                     std::fabs(length(s.wo) - 1.f) < 1e-3f && std::isfinite(s.pdf) &&
                     s.pdf > 0.f;
        if (valid && opt.query) {
            for (std::size_t k = 0; k < query.size(); ++k)
                if (!std::isfinite(weight[k])) valid = false;
        }
        if (!valid) {
            ++r.invalid_samples;
            continue;
        }
        ++r.accepted_samples;
        if (s.wo.z <= 0.f) ++r.below_horizon_samples;
        int c = g.cell(s.wo);
        if (c >= 0) r.observed[c] += 1.0;

        if (i % check_stride == 0) {
            ++r.pdf_checked;
            double a = s.pdf, b = brdf.pdf(wi, s.wo);
            double rel = std::fabs(a - b) / std::max(std::fabs(a), std::fabs(b));
            if (!std::isfinite(rel)) rel = std::numeric_limits<double>::infinity();
            r.worst_pdf_rel_error = std::max(r.worst_pdf_rel_error, rel);
            if (!(rel <= opt.pdf_rel_tolerance)) ++r.pdf_mismatches;
        }
    }
}

void integrate_expected(const Brdf& brdf, const Vec3& wi, const Chi2Options& opt, const Grid& g, Chi2Result& r) {
    // -- Expected counts: the pdf integrated over each cell. --
    // Integrated in (s, phi) with z = cos(theta) = 1 - s^2, d(omega) = 2 s ds dphi: uniform
    // steps in s resolve the pole (where measured pdfs have an integrable 1/theta spike at
    // normal incidence) as finely as the rest. Each of res x res sub-cells is refined
    // adaptively (quadrants, midpoint rules compared) where the pdf varies sharply, so mirror-
    // like lobes are integrated accurately. The midpoint rule never evaluates on an edge, so the
    // horizon (where the pdf jumps to 0) and the pole need no special case.
    const int res = std::max(1, opt.integration_resolution);
    auto pdf_at = [&](double s, double phi) {
        const double z = 1.0 - s * s;
        const double sin_theta = std::sqrt(std::max(0.0, 1.0 - z * z));
        const Vec3 wo(static_cast<float>(sin_theta * std::cos(phi)),
                      static_cast<float>(sin_theta * std::sin(phi)), static_cast<float>(z));
        const double p = brdf.pdf(wi, wo);
        return std::isfinite(p) ? p * 2.0 * s : std::numeric_limits<double>::quiet_NaN();
    };
    // 2 x 2 midpoint estimate of the integral over a rectangle in (s, phi).
    auto midpoint = [&](double s0, double s1, double p0, double p1) {
        const double hs = 0.5 * (s1 - s0), hp = 0.5 * (p1 - p0);
        double sum = 0.0;
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) sum += pdf_at(s0 + (i + 0.5) * hs, p0 + (j + 0.5) * hp);
        return sum * hs * hp;
    };
    // Absolute tolerance per sub-cell: at most a fifth of one expected sample per cell.
    const double tolerance = 0.2 / std::max(1.0, static_cast<double>(opt.sample_count)) / (res * res);
    std::function<double(double, double, double, double, double, int)> refine =
        [&](double s0, double s1, double p0, double p1, double whole, int depth) -> double {
        const double sm = 0.5 * (s0 + s1), pm = 0.5 * (p0 + p1);
        const double q[4] = {midpoint(s0, sm, p0, pm), midpoint(sm, s1, p0, pm),
                             midpoint(s0, sm, pm, p1), midpoint(sm, s1, pm, p1)};
        const double parts = q[0] + q[1] + q[2] + q[3];
        if (!std::isfinite(parts) || depth >= opt.integration_max_depth ||
            std::fabs(parts - whole) <= tolerance)
            return parts;
        return refine(s0, sm, p0, pm, q[0], depth + 1) + refine(sm, s1, p0, pm, q[1], depth + 1) +
               refine(s0, sm, pm, p1, q[2], depth + 1) + refine(sm, s1, pm, p1, q[3], depth + 1);
    };
    for (int row = 0; row < g.rows; ++row) {
        const double z0 = g.z_min + row * g.dz, z1 = z0 + g.dz;
        const double s_lo = std::sqrt(std::max(0.0, 1.0 - z1)), s_hi = std::sqrt(std::max(0.0, 1.0 - z0));
        const double hs = (s_hi - s_lo) / res, hphi = g.dphi / res;
        for (int col = 0; col < g.cols; ++col) {
            double mass = 0.0;
            for (int i = 0; i < res; ++i) {
                for (int j = 0; j < res; ++j) {
                    const double a0 = s_lo + i * hs, b0 = col * g.dphi + j * hphi;
                    mass += refine(a0, a0 + hs, b0, b0 + hphi, midpoint(a0, a0 + hs, b0, b0 + hphi), 0);
                }
            }
            r.pdf_integral += mass;
            if (row < g.upper_first_row) r.pdf_integral_below_horizon += mass;
            r.expected[row * g.cols + col] = mass * static_cast<double>(opt.sample_count);
        }
    }
}

// The problems the histogram alone would miss: non-finite or below-horizon pdf, invalid
// samples, a failure rate that disagrees with the pdf's missing mass, pdf mismatches.
void check_sanity(const Chi2Options& opt, Chi2Result& r, std::vector<std::string>& problems) {
    // -- Sanity checks the histogram alone would miss. --
    if (!std::isfinite(r.pdf_integral)) problems.push_back("pdf() returned non-finite values");
    if (r.pdf_integral_below_horizon > 0.0)
        problems.push_back("pdf() is nonzero below the horizon (integral " +
                           format_double(r.pdf_integral_below_horizon) + ")");
    if (r.invalid_samples > 0)
        problems.push_back(std::to_string(r.invalid_samples) +
                           " samples returned true with a non-finite or non-unit wo, a pdf "
                           "<= 0 or non-finite weights");
    if (r.below_horizon_samples > 0)
        problems.push_back(std::to_string(r.below_horizon_samples) +
                           " samples returned true with wo at or below the horizon");

    const double n = static_cast<double>(std::max<std::uint64_t>(1, opt.sample_count));
    r.failure_fraction = static_cast<double>(r.failed_samples) / n;
    r.expected_failure_fraction = 1.0 - r.pdf_integral;
    {
        double p = std::clamp(r.expected_failure_fraction, 0.0, 1.0);
        // The floor 1/n keeps sigma from vanishing when no failures are expected.
        double sigma = std::sqrt(std::max(p * (1.0 - p), 1.0 / n) / n);
        double allowed = 5.0 * sigma + opt.failure_rate_tolerance;
        r.failure_rate_ok =
            std::fabs(r.failure_fraction - r.expected_failure_fraction) <= allowed;
        if (!r.failure_rate_ok)
            problems.push_back("failed-sample fraction " + format_double(r.failure_fraction) +
                               " does not match 1 - pdf_integral = " +
                               format_double(r.expected_failure_fraction) + " (allowed +-" +
                               format_double(allowed, 2) + ")");
    }

    if (r.pdf_checked > 0 &&
        static_cast<double>(r.pdf_mismatches) >
            opt.max_pdf_mismatch_fraction * static_cast<double>(r.pdf_checked))
        problems.push_back(std::to_string(r.pdf_mismatches) + " of " +
                           std::to_string(r.pdf_checked) +
                           " checked samples have s.pdf != pdf(wi, s.wo) (worst relative "
                           "error " + format_double(r.worst_pdf_rel_error) + ")");
}

// The statistic over the cells (r.statistic, r.dof, r.pooled_cells); returns the cells that
// hold samples where pdf() says none can be.
std::vector<int> chi2_statistic(const Chi2Options& opt, Chi2Result& r, int cells) {
    // -- Chi-square statistic with pooling. Cells in ascending order of expected count:
    // those below min_expected go into one pool, and while the pool itself is still below
    // min_expected the next cells join it, so it ends up a valid cell of its own. --
    std::vector<int> order(cells);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return r.expected[a] < r.expected[b]; });

    std::vector<int> impossible;  // samples where pdf() says none can be
    double pooled_obs = 0.0, pooled_exp = 0.0;
    int terms = 0;
    for (int idx : order) {
        double o = r.observed[idx], e = r.expected[idx];
        if (!(e > 0.0)) {
            if (o > 0.0) impossible.push_back(idx);
            continue;
        }
        if (e < opt.min_expected || (pooled_exp > 0.0 && pooled_exp < opt.min_expected)) {
            pooled_obs += o;
            pooled_exp += e;
            ++r.pooled_cells;
            continue;
        }
        r.statistic += (o - e) * (o - e) / e;
        ++terms;
    }
    if (pooled_exp > 0.0) {
        r.statistic += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        ++terms;
    }
    r.dof = terms - 1;
    return impossible;
}

// The verdict on the histogram: no impossible samples, enough usable cells, a p-value above
// the threshold.
void judge_histogram(Chi2Result& r, const std::vector<int>& impossible, std::vector<std::string>& problems) {
    if (!impossible.empty()) {
        double total = 0.0;
        for (int idx : impossible) total += r.observed[idx];
        problems.push_back(format_double(total, 10) + " samples in " +
                           std::to_string(impossible.size()) +
                           " cells where pdf() integrates to 0");
    }

    if (r.dof < 1) {
        r.p_value = 0.0;
        problems.push_back("too few usable cells for a chi-square test (dof " +
                           std::to_string(r.dof) +
                           "); use more samples or a finer grid");
    } else {
        r.p_value = chi2_sf(r.statistic, r.dof);
        if (!(r.p_value >= r.threshold))
            problems.push_back("chi-square rejects the sampler: p-value " +
                               format_double(r.p_value) + " < " + format_double(r.threshold));
    }
}

std::string report(const Chi2Options& opt, const Grid& g, const Chi2Result& r, const std::vector<int>& impossible,
                   const std::vector<std::string>& problems) {
    const int cells = g.rows * g.cols;
    // -- The report. --
    std::ostringstream msg;
    msg << "chi2 = " << format_double(r.statistic, 6) << ", dof = " << r.dof
        << ", p = " << format_double(r.p_value) << " (threshold " << format_double(r.threshold)
        << "), pdf integral = " << format_double(r.pdf_integral, 6)
        << ", failed samples = " << r.failed_samples << "/" << r.sample_count
        << ", pdf checked = " << r.pdf_checked << " (mismatches " << r.pdf_mismatches << ")";
    if (!r.passed) {
        msg << "\nFAILED:";
        for (const std::string& p : problems) msg << "\n  - " << p;
        // Worst cells, when the histogram is what objects: impossible ones first, then by
        // contribution to the statistic.
        bool histogram_failed = !impossible.empty() || !(r.p_value >= r.threshold);
        std::vector<int> worst = impossible;
        std::vector<int> rest;
        for (int idx = 0; idx < cells; ++idx)
            if (r.expected[idx] > 0.0) rest.push_back(idx);
        auto contribution = [&](int idx) {
            double d = r.observed[idx] - r.expected[idx];
            return d * d / r.expected[idx];
        };
        std::stable_sort(rest.begin(), rest.end(),
                         [&](int a, int b) { return contribution(a) > contribution(b); });
        worst.insert(worst.end(), rest.begin(), rest.end());
        int shown = histogram_failed ? std::min<int>(std::max(0, opt.report_cells),
                                                     static_cast<int>(worst.size()))
                                     : 0;
        if (shown > 0) msg << "\n  worst cells:";
        for (int k = 0; k < shown; ++k) {
            int idx = worst[k];
            msg << "\n    " << describe_cell(g, idx, r.observed[idx], r.expected[idx]);
        }
    }
    return msg.str();
}

}  // namespace

Chi2Result run_chi2_test(const Brdf& brdf, const Vec3& wi, const Chi2Options& opt) {
    Chi2Result r;
    std::vector<std::string> problems;
    const Grid g = make_grid(opt);
    const int cells = g.rows * g.cols;
    r.rows = g.rows;
    r.cols = g.cols;
    r.observed.assign(cells, 0.0);
    r.expected.assign(cells, 0.0);
    r.sample_count = opt.sample_count;
    r.threshold = opt.significance / std::max(1, opt.trials);

    count_samples(brdf, wi, opt, g, r);
    integrate_expected(brdf, wi, opt, g, r);
    check_sanity(opt, r, problems);
    const std::vector<int> impossible = chi2_statistic(opt, r, cells);
    judge_histogram(r, impossible, problems);
    r.passed = problems.empty();
    r.message = report(opt, g, r, impossible, problems);
    return r;
}

}  // namespace npf::testing
