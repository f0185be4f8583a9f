// Negative (out-of-gamut) RGB values in measured files (issue 34, item 4): renderers differ on
// them (the RGL loader and npf clamp them to 0, Mitsuba's `measured` keeps them), so `npf info`
// says how many a file holds and how much they weigh, and evaluation's policy is stated.
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/materials/rgl_brdf.h>

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

// A small synthetic file's fields with every stored RGB value made non-negative (the synthetic
// lobe dips below 0 in places); `values` gets those values.
std::vector<npf::testing::SyntheticField> non_negative_fields(std::vector<float>& values) {
    npf::testing::SyntheticRglSpec spec;
    spec.theta_count = 3;
    spec.data_size = 4;
    std::vector<npf::testing::SyntheticField> fields = npf::testing::synthetic_rgl_fields(spec);
    npf::testing::SyntheticField* rgb = npf::testing::find_field(fields, "rgb");
    values = rgb->floats();
    for (float& x : values) x = std::fabs(x);
    rgb->set_floats(values);
    return fields;
}

TEST(NegativeValues, InfoCountsThemAndWeighsThem) {
    std::vector<float> v;
    std::vector<npf::testing::SyntheticField> fields = non_negative_fields(v);
    npf::testing::SyntheticField* rgb = npf::testing::find_field(fields, "rgb");
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

// The policy: clamped by default (the RGL group's loader), kept with --raw (Mitsuba's measured):
// the two renders differ exactly when the file holds negative values.
TEST(NegativeValues, RenderClampsThemUnlessRaw) {
    const std::string dir = npf::testing::temporary_folder("negative-render");
    std::vector<float> v;
    std::vector<npf::testing::SyntheticField> fields = non_negative_fields(v);
    npf::testing::SyntheticField* rgb = npf::testing::find_field(fields, "rgb");
    npf::testing::to_writer(fields).write(dir + "/clean.bsdf");
    for (std::size_t i = 0; i < v.size(); i += 3) v[i] = -v[i];  // a third of the values below 0
    rgb->set_floats(v);
    npf::testing::to_writer(fields).write(dir + "/negative.bsdf");
    const auto render = [&](const std::string& material, const std::string& out, bool raw) {
        std::vector<std::string> args = {"render", dir + "/" + material, "-o", dir + "/" + out, "--size", "16", "--spp", "4", "--quiet"};
        if (raw) args.push_back("--raw");
        const npf::testing::ToolRun r = npf::testing::run_tool(args);
        EXPECT_EQ(r.status, 0) << npf::testing::describe(r);
    };
    const auto psnr_line = [&](const std::string& a, const std::string& b) {
        const npf::testing::ToolRun r = npf::testing::run_tool({"compare", dir + "/" + a, dir + "/" + b});
        return npf::testing::lines_of(r.out).empty() ? std::string() : npf::testing::lines_of(r.out)[0];
    };
    render("negative.bsdf", "c.exr", false);
    render("negative.bsdf", "k.exr", true);
    render("clean.bsdf", "c2.exr", false);
    render("clean.bsdf", "k2.exr", true);
    EXPECT_NE(psnr_line("c.exr", "k.exr"), "PSNR inf");
    EXPECT_EQ(psnr_line("c2.exr", "k2.exr"), "PSNR inf");
}

}  // namespace
