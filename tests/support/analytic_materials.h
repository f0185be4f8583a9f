// Shared by the analytic material tests (test_analytic*.cpp): NDFs and spectra in one line,
// a hemisphere quadrature for sharp lobes, and the materials the AnalyticBrdf tests use. The
// using-declarations are part of the namespace, so that a test's `using namespace` brings them.
#pragma once

#include "chi2.h"

#include <npf/color/spectrum.h>
#include <npf/core/vec.h>
#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/materials/analytic/fresnel.h>
#include <npf/materials/analytic/microfacet.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace npf::testing::analytic {

using npf::AnalyticBrdf, npf::AnalyticMaterial, npf::ChannelQuery, npf::Channels, npf::Fresnel,
      npf::MicrofacetDistribution, npf::MicrofacetNdf, npf::SpecularLobe, npf::Vec2, npf::Vec3,
      npf::color::SampledSpectrum, npf::testing::Chi2Options, npf::testing::Chi2Result,
      npf::testing::Pcg32;

constexpr double kPi = npf::kPiD;

inline SampledSpectrum constant(double v) { return SampledSpectrum::constant(v); }
inline SampledSpectrum ramp(double a, double b) { return SampledSpectrum({400.0, 700.0}, {a, b}); }

inline MicrofacetNdf ndf(MicrofacetDistribution type, float ax, float ay, float rot = 0.f) {
    MicrofacetNdf n;
    n.type = type;
    n.alpha_x = ax;
    n.alpha_y = ay;
    n.rotation = rot;
    return n;
}

inline std::string describe(const MicrofacetNdf& n) {
    return std::string(n.type == MicrofacetDistribution::Ggx ? "GGX" : "Beckmann") + " " +
           std::to_string(n.alpha_x) + " x " + std::to_string(n.alpha_y) + " rot " + std::to_string(n.rotation);
}

inline std::string str(const Vec3& v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

inline Vec3 uniform_hemisphere(Pcg32& rng) {
    const float z = std::max(1e-4f, rng.next_float());
    const float r = std::sqrt(std::max(0.f, 1.f - z * z));
    const float phi = float(2.0 * kPi) * rng.next_float();
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// Midpoint quadrature over the upper hemisphere in (theta = pi/2 v^2, phi): the square-root
// map puts most nodes near the normal, where sharp lobes live.
template <typename F>
inline double hemisphere_integral(F f, int nv = 400, int nphi = 256) {
    double sum = 0.0;
    for (int i = 0; i < nv; ++i) {
        const double v = (i + 0.5) / nv;
        const double theta = 0.5 * kPi * v * v;
        const double w_theta = kPi * v / nv * std::sin(theta);  // dtheta sin(theta)
        for (int j = 0; j < nphi; ++j) {
            const double phi = 2.0 * kPi * (j + 0.5) / nphi;
            const Vec3 m(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                         float(std::cos(theta)));
            sum += f(m, std::cos(theta)) * w_theta * (2.0 * kPi / nphi);
        }
    }
    return sum;
}

inline std::vector<MicrofacetNdf> ndf_cases() {
    std::vector<MicrofacetNdf> out;
    for (MicrofacetDistribution t : {MicrofacetDistribution::Ggx, MicrofacetDistribution::Beckmann}) {
        for (float a : {0.05f, 0.1f, 0.3f, 0.6f, 1.0f}) out.push_back(ndf(t, a, a));
        out.push_back(ndf(t, 0.05f, 0.3f, 0.4f));
        out.push_back(ndf(t, 0.5f, 0.08f, -1.1f));
        out.push_back(ndf(t, 1.0f, 0.2f, 2.0f));
    }
    return out;
}

inline ChannelQuery spectral_query(const AnalyticBrdf& b, std::vector<float> wl) { return b.query(Channels::spectral(wl)); }

inline AnalyticMaterial one_lobe(MicrofacetNdf n, Fresnel f = Fresnel::one(), SampledSpectrum w = constant(1.0)) {
    AnalyticMaterial m;
    m.name = "test lobe";
    m.specular.push_back(SpecularLobe{n, std::move(f), std::move(w)});
    return m;
}

inline Fresnel gold_like() { return Fresnel::conductor(ramp(1.5, 0.15), ramp(1.9, 3.9)); }

inline AnalyticMaterial coated_plastic() {
    AnalyticMaterial m = one_lobe(ndf(MicrofacetDistribution::Ggx, 0.15f, 0.15f), Fresnel::dielectric(constant(1.5)));
    m.name = "coated plastic";
    m.diffuse = ramp(0.6, 0.1);
    return m;
}

inline AnalyticMaterial two_lobes() {
    AnalyticMaterial m = one_lobe(ndf(MicrofacetDistribution::Ggx, 0.08f, 0.08f), gold_like());
    m.name = "two lobes";
    m.specular.push_back(SpecularLobe{ndf(MicrofacetDistribution::Beckmann, 0.6f, 0.2f, 1.0f),
                                      Fresnel::schlick(constant(0.3)), ramp(0.5, 1.0)});
    return m;
}

inline AnalyticMaterial retro_and_sheen() {
    AnalyticMaterial m;
    m.name = "retro and sheen";
    m.retroreflection = ramp(0.3, 0.8);
    m.retro_exponent = 20.f;
    m.sheen = ramp(0.9, 0.4);
    m.sheen_roughness = 0.35f;
    m.diffuse = constant(0.1);
    return m;
}

// Every kind of term, sharp and rotated, for the robustness and reciprocity tests.
inline AnalyticMaterial everything(float alpha) {
    AnalyticMaterial m;
    m.name = "everything";
    m.specular.push_back(SpecularLobe{ndf(MicrofacetDistribution::Ggx, alpha, alpha), gold_like(), constant(1.0)});
    m.specular.push_back(SpecularLobe{ndf(MicrofacetDistribution::Beckmann, alpha, 0.2f, 0.7f),
                                      Fresnel::thin_film(300.0, constant(1.4), ramp(0.3, 1.2), ramp(3.0, 2.0)),
                                      ramp(0.2, 0.8)});
    m.specular.push_back(SpecularLobe{ndf(MicrofacetDistribution::Ggx, 0.3f, alpha, -1.2f),
                                      Fresnel::dielectric(constant(1.5)), constant(1.0)});
    m.diffuse = ramp(0.5, 0.2);
    m.retroreflection = constant(0.4);
    m.retro_exponent = 1000.f;
    m.sheen = constant(0.5);
    m.sheen_roughness = 0.1f;
    return m;
}

}  // namespace npf::testing::analytic
