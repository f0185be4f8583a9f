// Fitting the NPF factors to any BRDF source by alternating weighted least squares (paper
// sec. 3.2 and 3.3): the source is resampled on the uniform Rusinkiewicz grid, each sample
// weighted by w = w_V w_I w_C, and every factor is updated in closed form per table cell (paper
// Eq. 10) in the order D, F, G, rho_d, rho_s until the weighted error stops falling.
#pragma once

#include <npf/converter/fit/npf_factors.h>
#include <npf/core/brdf.h>

#include <functional>
#include <string>
#include <vector>

namespace npf {

struct AwlsOptions {
    RusinkiewiczGrid grid{90, 180, 90, 180};  // phi_h = 1 for isotropic sources
    int g_theta = 90, g_phi = 180;              // G table; g_phi = 1 for isotropic sources
    Channels channels = Channels::rgb();
    // w_I: cos(theta_i) cos(theta_o) to this power (0 disables); w_C = (rho + epsilon)^-p.
    double importance_power = 1.0;
    double compressive_power = 0.0;
    double compressive_epsilon = 0.01;
    int max_iterations = 300;
    double tolerance = 1e-5;      // stop when the weighted error falls by less than this, relative
    int threads = 0;              // 0: all hardware threads
    std::function<void(double)> progress;
};

struct AwlsReport {
    std::size_t samples = 0;                 // grid samples with both directions above the horizon
    std::vector<int> iterations;             // per channel
    std::vector<double> relative_error;      // per channel: sqrt(sum w (rho - model)^2 / sum w rho^2)
    double seconds = 0.0;
};

// Throws npf::Error for bad options or a source that cannot give the channels.
NpfFactors fit_npf(const Brdf& source, const AwlsOptions& options, AwlsReport* report = nullptr);

}  // namespace npf
