// Negative (out-of-gamut) RGB values in measured files (issue 34, item 4): renderers differ on
// them (the RGL loader and npf clamp them to 0, Mitsuba's `measured` keeps them), so `npf info`
// says how many a file holds and how much they weigh, and evaluation's policy is stated.
#include "synthetic_rgl.h"

#include <npf/converter/rgl_brdf.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

std::string negative_detail(const npf::Brdf& b) {
    for (const auto& [key, value] : b.info().details)
        if (key == "negative values") return value;
    return "(no such detail)";
}

TEST(NegativeValues, InfoCountsThemAndWeighsThem) {
    npf::testing::SyntheticRglSpec spec;
    spec.theta_count = 3;
    spec.data_size = 4;
    std::vector<npf::testing::SyntheticField> fields = npf::testing::synthetic_rgl_fields(spec);
    npf::testing::SyntheticField* rgb = npf::testing::find_field(fields, "rgb");
    std::vector<float> v = rgb->floats();
    for (float& x : v) x = std::fabs(x);  // the synthetic lobe dips below 0 in places
    rgb->set_floats(v);
    const std::string dir = npf::testing::temporary_folder("negative-values");
    npf::testing::to_writer(fields).write(dir + "/clean.bsdf");
    EXPECT_EQ(negative_detail(*npf::RglBrdf::load(dir + "/clean.bsdf")), "none");

    double positive = 0.0;
    for (float x : v) positive += x;
    positive -= double(v[0]) + double(v[5]);
    v[0] = -2.f;
    v[5] = -1.f;
    rgb->set_floats(v);
    npf::testing::to_writer(fields).write(dir + "/negative.bsdf");
    const std::unique_ptr<npf::RglBrdf> b = npf::RglBrdf::load(dir + "/negative.bsdf");
    const std::string d = negative_detail(*b);
    EXPECT_NE(d.find("2 of " + std::to_string(v.size()) + " stored values"), std::string::npos) << d;
    EXPECT_NE(d.find("lowest -2,"), std::string::npos) << d;
    char share[32];
    std::snprintf(share, sizeof share, "together %.3g %%", 100.0 * 3.0 / positive);
    EXPECT_NE(d.find(share), std::string::npos) << d << " expected " << share;
}

}  // namespace
