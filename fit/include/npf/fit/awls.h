// Fitting the NPF factors to any BRDF source by alternating weighted least squares (paper
// sec. 3.2 and 3.3): the source is resampled on the uniform Rusinkiewicz grid, each sample
// weighted by w = w_V w_I w_C, and every factor is updated in closed form per table cell (paper
// Eq. 10) in the order D (jointly with rho_d), F, G, then (rho_d, rho_s) jointly, until the
// weighted error stops falling.
//
// Speed (docs/fitting.md): the geometry of the samples (cells, weights, cosines) is computed
// once and shared by every channel; the source is evaluated for several blocks of channels per
// direction pair; channels are fitted in blocks of 16 (4 for RGB) that run in lock-step through
// the same passes, one SIMD lane per channel; each block starts from the converged factors of
// the previous one; the passes run on all threads.
#pragma once

#include <npf/fit/npf_factors.h>
#include <npf/core/brdf.h>

#include <functional>
#include <string>
#include <vector>

namespace npf {

// w_V: the paper's anisotropic volume form (Eq. 4 with the sqrt-map Jacobian), or Bagher et
// al.'s three-angle form for comparison (paper Table 1; see docs/fitting.md for our reading).
enum class VolumeWeight { Paper, ThreeAngle };

// The fit's own bounds on its options: fit_awls refuses options outside them, and `npf
// convert`'s and the batch's settings take their ranges from here (converter/src/settings/fit_settings.cpp).
namespace awls_limits {
inline constexpr int kMinCells = 2;       // theta_h, theta_d, phi_d and the G table's theta
inline constexpr int kMinPhiCells = 1;    // phi_h and the G table's phi (1: isotropic)
inline constexpr int kMaxCells = 4096;    // any axis
inline constexpr int kMaxPhiDSamples = 4096;
inline constexpr int kMaxIterations = 100000;
}  // namespace awls_limits

struct AwlsOptions {
    RusinkiewiczGrid grid{90, 180, 90, 180};  // phi_h = 1 for isotropic sources
    int g_theta = 90, g_phi = 180;              // G table; g_phi = 1 for isotropic sources
    Channels channels = Channels::rgb();
    // Samples per (theta_h, phi_h, theta_d) ring of phi_d: 0 takes grid.phi_d (every cell
    // centre). Fewer samples, stratified with a rotation per ring, trade accuracy for time and
    // memory on the 4D anisotropic grid; the factor tables keep their full resolution.
    int phi_d_samples = 0;
    VolumeWeight volume_weight = VolumeWeight::Paper;
    // w_I = cos(theta_i)^importance_power_view cos(theta_o)^importance_power_light (0 disables);
    // w_C = (max(rho, 0) + compressive_epsilon)^-compressive_power (0 disables).
    // wi is the side a renderer's camera is on (core/brdf.h), so the two powers say how much
    // grazing views and grazing light matter. A rendered image's squared error weighs the view
    // by cos theta_i (pixels per solid angle of normals) and the light by cos^2 theta_o, so (1, 2)
    // is the render-derived choice; the symmetric (2, 2) fits BRDF values best (docs/fitting.md).
    // Defaults: w_I (2, 2) from the BRDF-space sweep; w_C power 1, chosen on render PSNR of the
    // real measured files (docs/fitting.md, "Judged by renders"; it was 0 before).
    double importance_power_view = 2.0;
    double importance_power_light = 2.0;
    double compressive_power = 1.0;
    double compressive_epsilon = 0.01;
    // Acceleration after each sweep (docs/fitting.md, "Convergence"). Anderson (the default):
    // the Anderson mix of the last sweeps, kept per channel where it lowers the error.
    // LineSearch: the extrapolation along the last sweep's move that the fit used until issue 16,
    // kept for the paper preset so that its figures stay reproducible. None: the paper's plain
    // alternation (`--plain`).
    enum class Acceleration { None, LineSearch, Anderson };
    Acceleration acceleration = Acceleration::Anderson;
    // Holds G near the G of the fit's first sweep (Smith's masking of the data's D, or the
    // converged G of the previous block of channels) with the weight g_pin x the mean weight of
    // a G cell's data. The data hardly constrain the near-symmetry G -> G s, F -> F / s^2 (see
    // smith_start): without the pin the alternation drifts along it for hundreds of sweeps at a
    // constant small gain and stops at its cap, wherever the cap falls. With 1e-2 every fit
    // stops by its tolerance (docs/fitting.md, "Convergence"). 0: no pin.
    double g_pin = 1e-2;
    // Start G from Smith's masking of the first D estimate (docs/fitting.md): the factors then
    // take the physically meaningful split between F and G, which the data hardly constrain.
    bool smith_start = true;
    // G <= 1 (its value at normal incidence) after every sweep: masking only removes light.
    // Right for microfacet materials (their F and G then match the true ones more closely),
    // wrong for fabrics and other materials whose G grows at grazing (docs/fitting.md).
    bool bound_g = false;
    int max_iterations = 300;
    // Stop when the weighted error falls by less than this per sweep, relative (over the last 10
    // sweeps, or a tenth of it over the last 3; docs/fitting.md, "Convergence").
    double tolerance = 1e-5;
    int threads = 0;              // 0: all hardware threads
    // Called with the fraction done in [0, 1] (from the calling thread only).
    std::function<void(double)> progress;
};

struct AwlsReport {
    std::size_t samples = 0;                 // samples with both directions above the horizon
    std::size_t invalid_values = 0;          // NaN or infinite source values, given zero weight
    std::vector<int> iterations;             // per channel (its block's count)
    std::vector<double> relative_error;      // per channel: sqrt(sum w (rho - model)^2 / sum w rho^2)
    double seconds_geometry = 0.0, seconds_resampling = 0.0, seconds_fitting = 0.0;
    double seconds = 0.0;                    // all of it
};

// Throws npf::Error for bad options or a source that cannot give the channels.
NpfFactors fit_npf(const Brdf& source, const AwlsOptions& options, AwlsReport* report = nullptr);

}  // namespace npf
