// The NPF fitter (AWLS): where the model holds exactly (one microfacet lobe plus a diffuse
// term) the fit recovers the material.
#include <npf/converter/analytic/analytic_brdf.h>
#include <npf/converter/fit/awls.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

namespace {

using npf::AnalyticBrdf;
using npf::Vec3d;

npf::AnalyticMaterial plastic(float ax, float ay) {
    npf::AnalyticMaterial m;
    m.name = "fit test";
    npf::SpecularLobe lobe;
    lobe.ndf.alpha_x = ax;
    lobe.ndf.alpha_y = ay;
    lobe.fresnel = npf::Fresnel::schlick(npf::color::SampledSpectrum({400.0, 700.0}, {0.9, 0.6}));
    m.specular.push_back(lobe);
    m.diffuse = npf::color::SampledSpectrum({400.0, 700.0}, {0.1, 0.3});
    m.wavelengths = {450.f, 550.f, 650.f};
    return m;
}

// Cosine-weighted relative RMS error of f_r over random directions below 80 degrees.
double relative_rms(const npf::Brdf& source, const npf::NpfFactors& f, std::size_t c, int pairs) {
    const npf::ChannelQuery q = source.query(f.channels);
    std::vector<float> v(q.size());
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const double zmin = std::cos(80.0 * npf::kPiD / 180.0);
    auto dir = [&] {
        const double z = std::sqrt(zmin * zmin + (1.0 - zmin * zmin) * uni(rng)), phi = 2.0 * npf::kPiD * uni(rng);
        const double r = std::sqrt(1.0 - z * z);
        return Vec3d{r * std::cos(phi), r * std::sin(phi), z};
    };
    double num = 0.0, den = 0.0;
    for (int i = 0; i < pairs; ++i) {
        const Vec3d wi = dir(), wo = dir();
        source.eval_cos(npf::Vec3(float(wi.x), float(wi.y), float(wi.z)), npf::Vec3(float(wo.x), float(wo.y), float(wo.z)), q,
                        v.data());
        const double truth = v[c] / wo.z, fit = f.eval(c, wi, wo);
        num += (fit - truth) * (fit - truth);
        den += truth * truth;
    }
    return std::sqrt(num / den);
}

TEST(Awls, RecoversAnIsotropicMicrofacetMaterial) {
    const AnalyticBrdf source(plastic(0.2f, 0.2f));
    npf::AwlsOptions o;
    o.grid = {90, 1, 90, 90};
    o.g_phi = 1;
    o.channels = npf::Channels::spectral({450.f, 550.f, 650.f});
    if (const char* it = std::getenv("NPF_AWLS_ITERATIONS")) o.max_iterations = std::atoi(it);
    if (const char* p = std::getenv("NPF_AWLS_IMPORTANCE")) o.importance_power = std::atof(p);
    npf::AwlsReport report;
    const npf::NpfFactors f = npf::fit_npf(source, o, &report);
    for (std::size_t c = 0; c < 3; ++c) {
        const double e = relative_rms(source, f, c, 20000);
        std::printf("[ awls     ] channel %zu: %d iterations, weighted error %.2e, BRDF-space relative RMS %.3f %%, rho_d %.4f\n",
                    c, report.iterations[c], report.relative_error[c], 100.0 * e, f.rho_d[c]);
        EXPECT_LT(e, 0.01) << "channel " << c;
        EXPECT_NEAR(f.rho_d[c] * npf::kPiD, 0.1 + 0.2 * (450.0 + 100.0 * c - 400.0) / 300.0, 0.02) << "diffuse albedo";
    }
}

}  // namespace
