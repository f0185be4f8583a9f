// Chi-square goodness of fit of RglBrdf::sample against RglBrdf::pdf (as pbrt-v4 and
// Mitsuba 3 test their BSDFs), for every real measured file and every synthetic kind, and
// the normalisation of pdf over the hemisphere.
#include "chi2.h"
#include "synthetic_rgl.h"

#include <npf/materials/rgl_brdf.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

using npf::Vec3, npf::testing::Chi2Options, npf::testing::Chi2Result;

// Incident directions: the normal, moderate and grazing elevations, at azimuths that land in
// every quadrant (they exercise the folding of reduced anisotropic files).
std::vector<Vec3> incident_directions() {
    const float thetas[] = {0.f, 0.45f, 1.0f, 1.35f};
    const float phis[] = {0.3f, 2.2f, -1.1f, -2.6f};
    std::vector<Vec3> out;
    for (int i = 0; i < 4; ++i) out.push_back(npf::spherical_direction(thetas[i], phis[i]));
    return out;
}

void expect_sampling_matches_pdf(const npf::RglBrdf& brdf, const std::string& name) {
    const std::vector<Vec3> wis = incident_directions();
    const npf::ChannelQuery query = brdf.native_query();
    for (const Vec3& wi : wis) {
        Chi2Options opt;
        opt.sample_count = 400000;
        opt.trials = int(wis.size());
        opt.query = &query;
        // Peaked lobes (the sharpest real file has an NDF peak near 600) need a fine start grid.
        opt.integration_resolution = 16;
        const Chi2Result r = npf::testing::run_chi2_test(brdf, wi, opt);
        EXPECT_TRUE(r.passed) << name << ", wi = (" << wi.x << ", " << wi.y << ", " << wi.z << "): "
                              << r.message;
        EXPECT_EQ(r.invalid_samples, 0u) << name;
    }
}

class RglSamplingReal : public ::testing::TestWithParam<std::string> {};

TEST_P(RglSamplingReal, SampleDrawsFromPdf) {
    const std::string path = npf::testing::shared_data_file("rgl/" + GetParam() + ".bsdf");
    if (path.empty()) GTEST_SKIP() << "rgl/" << GetParam() << ".bsdf not found in the shared data folder";
    auto brdf = npf::RglBrdf::load(path);
    expect_sampling_matches_pdf(*brdf, GetParam());
}

// The pdf is normalised: its integral over the upper hemisphere plus the fraction of samples
// that fail (half vectors that send wo below the horizon) is 1, and at normal incidence,
// where the materials reflect (nearly) everything, the integral itself is about 1.
TEST_P(RglSamplingReal, PdfIntegratesToOneAtNormalIncidence) {
    const std::string path = npf::testing::shared_data_file("rgl/" + GetParam() + ".bsdf");
    if (path.empty()) GTEST_SKIP() << "rgl/" << GetParam() << ".bsdf not found in the shared data folder";
    auto brdf = npf::RglBrdf::load(path);
    Chi2Options opt;
    opt.sample_count = 200000;
    opt.integration_resolution = 16;
    const Chi2Result r = npf::testing::run_chi2_test(*brdf, Vec3(0.f, 0.f, 1.f), opt);
    EXPECT_TRUE(r.passed) << GetParam() << ": " << r.message;
    EXPECT_NEAR(r.pdf_integral + r.failure_fraction, 1.0, 0.003) << GetParam() << ": " << r.message;
    EXPECT_GT(r.pdf_integral, 0.98) << GetParam() << ": " << r.message;
}

INSTANTIATE_TEST_SUITE_P(Files, RglSamplingReal,
                         ::testing::Values("acrylic_felt_green_rgb", "cg_sunflower_rgb", "ilm_l3_37_metallic_rgb",
                                           "paper_white_rgb", "vch_golden_yellow_rgb"));

struct SyntheticCase {
    std::string name;
    npf::testing::SyntheticRglSpec spec;
};

std::vector<SyntheticCase> synthetic_cases() {
    std::vector<SyntheticCase> cases;
    auto add = [&](const std::string& name, auto&& edit) {
        npf::testing::SyntheticRglSpec s;
        edit(s);
        cases.push_back({name, s});
    };
    add("isotropic_rgb", [](auto&) {});
    add("isotropic_spectral", [](auto& s) { s.spectral = true; });
    add("isotropic_two_phi", [](auto& s) { s.phi_count = 2; });
    add("anisotropic_full_circle_rgb", [](auto& s) { s.phi_count = 9; s.alpha_x = 0.12f; s.alpha_y = 0.45f; });
    add("anisotropic_half_circle_spectral", [](auto& s) {
        s.phi_count = 5; s.reduction = 2; s.spectral = true; s.alpha_x = 0.45f; s.alpha_y = 0.12f;
    });
    add("anisotropic_quarter_circle_rgb", [](auto& s) { s.phi_count = 3; s.reduction = 4; s.alpha_x = 0.2f; s.alpha_y = 0.5f; });
    add("sharp_isotropic", [](auto& s) { s.alpha_x = s.alpha_y = 0.03f; s.ndf_size = 128; s.vndf_size = 64; });
    add("no_jacobian", [](auto& s) { s.jacobian = false; });
    return cases;
}

class RglSamplingSynthetic : public ::testing::TestWithParam<SyntheticCase> {};

TEST_P(RglSamplingSynthetic, SampleDrawsFromPdf) {
    const std::string dir = npf::testing::temporary_folder("rgl_sampling");
    const std::string path =
        npf::testing::write_synthetic_rgl(GetParam().spec, dir + "/" + GetParam().name + ".bsdf");
    auto brdf = npf::RglBrdf::load(path);
    expect_sampling_matches_pdf(*brdf, GetParam().name);
}

INSTANTIATE_TEST_SUITE_P(Kinds, RglSamplingSynthetic, ::testing::ValuesIn(synthetic_cases()),
                         [](const auto& test_info) { return test_info.param.name; });

}  // namespace
