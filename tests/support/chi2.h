// Chi-square goodness-of-fit test for BRDF importance sampling.
//
// The question it answers: does `Brdf::sample` draw wo with the density that `Brdf::pdf`
// claims? It histograms sampled directions on a grid of equal-solid-angle cells (uniform in
// cos(theta) and phi), integrates pdf() over the same cells for the expected counts, pools
// cells whose expected count is too small for the chi-square approximation (as pbrt's
// bsdfs_test and Mitsuba's chi2 module do) and turns the statistic into a p-value.
// On top of the histogram it checks what the histogram cannot see: that the rate of failed
// samples matches the pdf mass missing from the hemisphere, that no sample lands below the
// horizon, and that the pdf reported with each sample equals pdf(wi, wo).
//
// Everything is deterministic for a given seed, so a passing test stays passing.
#pragma once

#include <npf/core/brdf.h>
#include <npf/core/channels.h>
#include <npf/core/vec.h>

#include <cstdint>
#include <string>
#include <vector>

namespace npf::testing {

// ---- Statistics -------------------------------------------------------------------------

// Regularized lower and upper incomplete gamma functions P(a, x) and Q(a, x) = 1 - P(a, x),
// for a > 0 and x >= 0 (NaN otherwise). Q is computed directly (not as 1 - P) where it is
// small, so tiny p-values keep their relative precision.
double regularized_gamma_p(double a, double x);
double regularized_gamma_q(double a, double x);

// Survival function (1 - CDF) of the chi-square distribution with `dof` degrees of freedom:
// the probability of a statistic at least `x` under the null hypothesis.
double chi2_sf(double x, double dof);

// ---- Random numbers -----------------------------------------------------------------------

// PCG32 (O'Neill, "PCG: A family of simple fast space-efficient statistically good
// algorithms for random number generation", the pcg32 / XSH-RR variant). Small, fast,
// well tested, and the same sequence on every platform.
class Pcg32 {
public:
    explicit Pcg32(std::uint64_t seed = 0x853c49e6748fea9bULL,
                   std::uint64_t stream = 0xda3e39cb94b95bdbULL);
    std::uint32_t next_u32();
    // Uniform in [0, 1): the top 24 bits, so the result is exact in float and never 1.
    float next_float();

private:
    std::uint64_t m_state = 0;
    std::uint64_t m_inc = 1;
};

// ---- The test -----------------------------------------------------------------------------

struct Chi2Options {
    // Grid of cells uniform in (cos theta, phi), so every cell has the same solid angle.
    // `cos_theta_bins` rows cover the upper hemisphere; with `full_sphere` as many again cover
    // the lower one, where the expected count is 0, so any sample there fails the test.
    int cos_theta_bins = 10;
    int phi_bins = 20;
    bool full_sphere = true;

    std::uint64_t sample_count = 1000000;
    std::uint64_t seed = 0x5eed5eed12345678ULL;

    // Sub-cells per cell and axis for integrating pdf() (in s = sqrt(1 - cos theta), phi),
    // each refined adaptively up to integration_max_depth times where the pdf varies sharply.
    // Raise the resolution for very sharp lobes that the initial points could miss entirely.
    int integration_resolution = 8;
    int integration_max_depth = 6;

    // Cells with an expected count below this are pooled.
    double min_expected = 5.0;

    // The test passes when p >= significance / trials (Bonferroni correction for callers that
    // run several tests, e.g. one per incident direction or material).
    double significance = 0.01;
    int trials = 1;

    // |observed failure fraction - (1 - pdf_integral)| may be 5 binomial standard deviations
    // plus this much (the quadrature error of pdf_integral).
    double failure_rate_tolerance = 2e-3;

    // Every k-th sample, k = max(1, sample_count / pdf_check_count), has its s.pdf compared
    // with pdf(wi, s.wo): a mismatch is a relative difference above pdf_rel_tolerance.
    // Up to max_pdf_mismatch_fraction of the checked samples may mismatch (float rounding at
    // lobe edges); 0 demands none.
    std::uint64_t pdf_check_count = 10000;
    double pdf_rel_tolerance = 1e-3;
    double max_pdf_mismatch_fraction = 1e-3;

    // When set, sample() is called with this query and a weight buffer, and non-finite
    // weights count as invalid samples. When null, an empty query and no weight buffer are
    // passed, so only directions and pdfs are tested.
    const ChannelQuery* query = nullptr;

    // How many of the worst cells the message lists.
    int report_cells = 5;
};

struct Chi2Result {
    bool passed = false;

    // The chi-square test proper.
    double statistic = 0.0;
    int dof = 0;
    double p_value = 0.0;
    double threshold = 0.0;  // significance / trials
    int pooled_cells = 0;    // cells merged into the low-expectation pool

    // Integral of pdf() over all cells (the whole sphere when full_sphere), and the part of
    // it below the horizon (must be 0 by the project's conventions).
    double pdf_integral = 0.0;
    double pdf_integral_below_horizon = 0.0;

    // Sample accounting. sample_count = accepted + failed + invalid.
    std::uint64_t sample_count = 0;
    std::uint64_t accepted_samples = 0;  // sample() returned true with a valid result
    std::uint64_t failed_samples = 0;    // sample() returned false
    std::uint64_t invalid_samples = 0;   // true, but non-finite / non-unit wo, pdf <= 0 or
                                         // non-finite, or non-finite weights
    std::uint64_t below_horizon_samples = 0;  // true with wo.z <= 0 (also binned if full_sphere)
    double failure_fraction = 0.0;            // failed / sample_count
    double expected_failure_fraction = 0.0;   // 1 - pdf_integral
    bool failure_rate_ok = false;

    // Consistency of s.pdf with pdf(wi, s.wo).
    std::uint64_t pdf_checked = 0;
    std::uint64_t pdf_mismatches = 0;
    double worst_pdf_rel_error = 0.0;

    // Counts per cell, row-major: row r (cos theta ascending, starting at -1 with full_sphere,
    // else at 0), column c (phi ascending from 0). expected[] is pdf mass * sample_count.
    int rows = 0, cols = 0;
    std::vector<double> observed, expected;

    // Summary line on success; on failure the reasons, statistic, dof, p-value and the worst
    // cells.
    std::string message;
};

// Runs the test for one conditioning direction wi (unit, local frame).
Chi2Result run_chi2_test(const Brdf& brdf, const Vec3& wi, const Chi2Options& opt = {});

}  // namespace npf::testing
