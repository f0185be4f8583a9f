// Small hand-made NPF factor sets for the compression, model and texture tests: smooth, random,
// strictly positive tables on tiny grids (D 8 x 1 or 8 x 16, F 6, G 8 x 1 or 8 x 12), RGB or
// spectral, in the gauge of the fitter's output (G = 1 and F = 1 at normal incidence are not
// enforced: nothing here depends on it).
#pragma once

#include <npf/fit/npf_factors.h>

#include <cstddef>

namespace npf::testing {

struct TestFactorSpec {
    bool anisotropic = false;
    std::size_t channels = 3;  // 3 with spectral = false: RGB
    bool spectral = false;     // wavelengths 400, 415, ... nm
    unsigned seed = 1;
};

NpfFactors make_test_factors(const TestFactorSpec& spec);

// Factors of an analytic microfacet material, tabulated as the fitter would store them: GGX D
// (alpha_x along the tangent, alpha_y along the bitangent; normalised, integral D cos = 1),
// Schlick F (F0 = 1 in the gauge; rho_s carries the colour), Smith G1 of the same GGX, and a
// Lambertian rho_d. Spectral materials get roughness that varies gently with wavelength, so
// that D and G differ per channel as measured ones do.
struct MicrofacetSpec {
    double alpha_x = 0.3, alpha_y = 0.3;
    double rho_d = 0.1, rho_s = 1.0;
    std::size_t channels = 3;  // 3 with spectral = false: RGB
    bool spectral = false;     // wavelengths spread over 400..700 nm
    int d_theta = 32, d_phi = 1, f_theta = 32, g_theta = 32, g_phi = 1;

    // The tables' sizes in one call: D (theta_h, phi_h), F (theta_d), G (theta, phi).
    void set_grid(int d_theta_, int d_phi_, int f_theta_, int g_theta_, int g_phi_) {
        d_theta = d_theta_, d_phi = d_phi_, f_theta = f_theta_, g_theta = g_theta_, g_phi = g_phi_;
    }
};

NpfFactors make_microfacet_factors(const MicrofacetSpec& spec);

}  // namespace npf::testing
