#include "npf_test_factors.h"

#include <npf/core/vec.h>

#include <cmath>
#include <algorithm>
#include <random>
#include <vector>

namespace npf::testing {

NpfFactors make_test_factors(const TestFactorSpec& spec) {
    NpfFactors f;
    f.grid = RusinkiewiczGrid{8, spec.anisotropic ? 16 : 1, 6, 8};
    f.g_theta = 8;
    f.g_phi = spec.anisotropic ? 12 : 1;
    const std::size_t C = spec.channels;
    if (spec.spectral) {
        std::vector<float> w;
        for (std::size_t c = 0; c < C; ++c) w.push_back(400.f + 15.f * float(c));
        f.channels = Channels::spectral(w);
    } else {
        f.channels = Channels::rgb();
    }
    std::mt19937 rng(spec.seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    // A smooth shape shared by all channels, a smooth per-channel variation and a little
    // per-cell noise, so that the tables are similar (as measured ones are) yet of full rank.
    auto table = [&](int rows, int cols, double falloff, std::vector<float>& out) {
        const double a0 = uni(rng), p0 = 2.0 * kPiD * uni(rng);
        for (std::size_t c = 0; c < C; ++c) {
            const double a = 0.2 * uni(rng), p = 2.0 * kPiD * uni(rng), tilt = 0.3 * (uni(rng) - 0.5);
            for (int i = 0; i < rows; ++i) {
                const double x = (i + 0.5) / rows;
                for (int j = 0; j < cols; ++j) {
                    const double phi = 2.0 * kPiD * (j + 0.5) / cols;
                    const double shape = std::exp(-falloff * x * x) * (1.0 + 0.3 * a0 * std::cos(phi + p0));
                    const double tint = 1.0 + a * std::cos(2.0 * phi + p) + tilt * x;
                    out.push_back(float(shape * tint * (1.0 + 0.05 * uni(rng)) + 0.01));
                }
            }
        }
    };
    table(f.grid.theta_h, f.grid.phi_h, 6.0, f.D);
    table(f.grid.theta_d, 1, 0.5, f.F);
    table(f.g_theta, f.g_phi, 1.5, f.G);
    for (std::size_t c = 0; c < C; ++c) {
        f.rho_d.push_back(float(0.05 + 0.25 * uni(rng)));
        f.rho_s.push_back(float(0.5 + 1.5 * uni(rng)));
    }
    return f;
}

NpfFactors make_microfacet_factors(const MicrofacetSpec& spec) {
    NpfFactors f;
    f.grid = RusinkiewiczGrid{spec.d_theta, spec.d_phi, spec.f_theta, 8};
    f.g_theta = spec.g_theta;
    f.g_phi = spec.g_phi;
    const std::size_t C = spec.channels;
    if (spec.spectral) {
        std::vector<float> w;
        for (std::size_t c = 0; c < C; ++c) w.push_back(400.f + 300.f * float(c) / float(std::max<std::size_t>(C - 1, 1)));
        f.channels = Channels::spectral(w);
    } else {
        f.channels = Channels::rgb();
    }
    for (std::size_t c = 0; c < C; ++c) {
        // Roughness 10 % larger at the red end than at the blue end.
        const double x = C > 1 ? double(c) / double(C - 1) : 0.0, scale = spec.spectral ? 0.95 + 0.1 * x : 1.0;
        const double ax = spec.alpha_x * scale, ay = spec.alpha_y * scale;
        for (int i = 0; i < spec.d_theta; ++i) {
            const double theta = f.grid.theta_h_at(i), c2 = std::cos(theta) * std::cos(theta);
            const double t2 = std::tan(theta) * std::tan(theta);
            for (int j = 0; j < spec.d_phi; ++j) {
                const double phi = f.grid.phi_h_at(j);
                const double e = t2 * (std::cos(phi) * std::cos(phi) / (ax * ax) + std::sin(phi) * std::sin(phi) / (ay * ay));
                f.D.push_back(float(1.0 / (kPiD * ax * ay * c2 * c2 * (1.0 + e) * (1.0 + e))));
            }
        }
        for (int i = 0; i < spec.f_theta; ++i) {
            const double theta_d = f.grid.theta_d_at(i), m = 1.0 - std::cos(theta_d);
            // Schlick with F0 = 0.5, renormalised to 1 at normal incidence (the gauge).
            f.F.push_back(float((0.5 + 0.5 * std::pow(m, 5.0)) / 0.5));
        }
        for (int i = 0; i < spec.g_theta; ++i) {
            const double theta = kPiD / 2.0 * (i + 0.5) / spec.g_theta, t2 = std::tan(theta) * std::tan(theta);
            for (int j = 0; j < spec.g_phi; ++j) {
                const double phi = spec.g_phi == 1 ? 0.0 : 2.0 * kPiD * (j + 0.5) / spec.g_phi;
                const double a2 = spec.g_phi == 1 ? ax * ay
                                                  : std::cos(phi) * std::cos(phi) * ax * ax + std::sin(phi) * std::sin(phi) * ay * ay;
                const double lambda = 0.5 * (std::sqrt(1.0 + a2 * t2) - 1.0);
                f.G.push_back(float(1.0 / (1.0 + lambda)));
            }
        }
        f.rho_d.push_back(float(spec.rho_d * (spec.spectral ? 0.8 + 0.4 * x : 1.0)));
        f.rho_s.push_back(float(spec.rho_s));
    }
    return f;
}

}  // namespace npf::testing
