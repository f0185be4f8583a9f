// The detail layer's fit (docs/fitting.md, "Detail layer"): what the NPF factors miss, fitted as an
// additive residual r_c(u_h, theta_d, phi_d) on a trilinear grid (npf/shading/detail_grid.h), so
// that the converted material renders like its measurement.
//
// Per channel c, a weighted linear least-squares fit of the grid values x to the residual
// y = f_source - f_NPF at a regular grid of samples in (u_h, theta_d, phi_d) (and phi_h for
// anisotropic sources), with
//  - the data weight of a sample: its Rusinkiewicz cell measure x cos theta_i cos theta_o x
//    (f_source + eps)^-p, which discounts errors where the BRDF is large (a display curve
//    compresses them: v^(1/2.4) gives p = 1.17 to first order);
//  - an energy term: the directional albedo of NPF + r at a set of views (quadratures over the
//    half vector, linear in x) is held to the source's, relative error squared times a weight
//    that makes a 1 % albedo error cost as much as the base's whole misfit.
//    With the energy term, a milder display weight renders best: p = 1.17 let the energy be
//    made up by a spread-out halo around the peak (renders 3 to 10 dB lower), p = 0.3 to 0.45
//    shaped the peak itself (docs/fitting.md, "Detail layer", has the sweep);
//  - a small smoothness term (differences of neighbouring cells), which also defines cells no
//    sample reaches.
// The normal equations (a 27-point stencil plus the energy rows) are solved by preconditioned
// conjugate gradients per channel. The channels' grids are then compressed across channels by the
// SVD (as D and G are) and, by default, rounded to half precision (the basis columns have unit
// length, so half keeps every value to 5e-4 of itself and the file stores them losslessly).
// Sums are made in a fixed order, so the result is the same to the bit on any number of threads.
#pragma once

#include <npf/core/brdf.h>
#include <npf/shading/npf_model.h>

#include <functional>
#include <vector>

namespace npf {

// The detail fit's bounds on the options `npf convert` and the batch offer
// (converter/src/settings/detail_settings.cpp takes its ranges from here).
namespace detail_limits {
inline constexpr double kMaxDisplayPower = 4.0;  // display_power
inline constexpr int kMaxClampPasses = 16;
}  // namespace detail_limits

struct DetailOptions {
    DetailGrid grid;                // empty: no detail layer (the paper's model)
    int samples_per_cell = 3;       // per axis: the data samples, a regular grid of this many per cell
    int phi_h_samples = 8;          // anisotropic models: half-vector azimuths the residual averages over
    double display_power = 0.4;     // p of the data weight (0: plain cosine-weighted least squares)
    // How a sample's share of the data term is measured along theta_h. SolidAngle: Rusinkiewicz's
    // cell measure, sin(theta_h) d(theta_h) ...: a glossy peak narrower than a degree then weighs
    // almost nothing, so its height is free (cg_sunflower's mirror peak came out at half its height)
    // although a small light, a point light or a mirror pair sees exactly that height. HalfAngle
    // (the default): d(theta_h) without the sin(theta_h), every half-vector angle on an equal
    // footing (docs/fitting.md, "The peak: measured per half-vector angle").
    enum class Measure { SolidAngle, HalfAngle };
    Measure measure = Measure::HalfAngle;
    // Passes that refit the energy targets to the clamped model (f_r = max(0, NPF + r): where the
    // layer drives a dark channel below 0, the clamp adds light the linear energy rows cannot
    // see). 0: the linear fit alone.
    int clamp_passes = 8;
    double display_epsilon = 0.01;  // eps of the data weight, 1/sr
    double energy_weight = 1e4;     // 0 disables the energy term
    std::vector<double> energy_views_deg = {0, 10, 20, 30, 40, 50, 60, 65, 70, 75, 80};
    double smoothness = 1e-4;       // relative to the mean diagonal of the data term
    double ratio = 0.99999;         // cumulative contribution ratio kept across channels
    int rank = 0;                   // > 0 fixes the rank across channels
    bool half_precision = true;     // round the basis to half (stored losslessly as HALF)
    int max_iterations = 2000;      // of conjugate gradients, per channel
    double tolerance = 1e-7;        // relative residual norm that ends them
    int threads = 0;                // 0: all hardware threads
};

struct DetailReport {
    std::size_t samples = 0;        // data samples (direction pairs) above the horizon
    int iterations_max = 0;         // conjugate-gradient iterations, the most of any channel
    // Weighted data error sum w (f_model - f_source)^2 over sum w f_source^2, mean over channels,
    // before (NPF alone) and after adding the detail layer.
    double weighted_error_before = 0.0, weighted_error_after = 0.0;
    // Largest relative directional-albedo error over the energy views and channels, before and
    // after (by the fit's own quadrature; npf albedo measures independently).
    double energy_error_before = 0.0, energy_error_after = 0.0;
    double seconds = 0.0;
};

// Fits and sets model.detail_grid and model.detail from `source` (queried at model.channels),
// replacing any detail the model had. Throws npf::Error for options out of range.
DetailReport fit_detail_layer(const Brdf& source, NpfModel& model, const DetailOptions& options,
                              const std::function<void(double)>& progress = {});

}  // namespace npf
