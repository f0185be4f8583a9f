// BRDF-space comparison of two materials (issue 34, item 3): npf/core/brdf_comparison.h and
// `npf eval TEST --against REF`.
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/core/brdf_comparison.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

namespace {

using npf::BrdfComparison, npf::DirectionPair, npf::Vec3;

Vec3 at(double theta_deg, double phi_deg) {
    const double t = theta_deg * npf::kPiD / 180.0, p = phi_deg * npf::kPiD / 180.0;
    return Vec3(float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)), float(std::cos(t)));
}

// Worked by hand: pooled sqrt(sum d^2 / sum r^2), per channel, the 60-degree subset, the cap.
TEST(BrdfComparison, PoolsChannelsAndHonoursTheCaps) {
    BrdfComparison c(2, 80.0);
    const float t1[2] = {2.f, 1.f}, r1[2] = {1.f, 1.f};  // both within 60 degrees
    const float t2[2] = {0.f, 6.f}, r2[2] = {2.f, 2.f};  // one direction at 70 degrees
    const float t3[2] = {100.f, 0.f}, r3[2] = {0.f, 0.f};  // beyond the cap: not counted
    c.add(at(10, 0), at(20, 180), t1, r1);
    c.add(at(70, 0), at(30, 90), t2, r2);
    c.add(at(85, 0), at(10, 0), t3, r3);
    const npf::BrdfComparisonResult r = c.result();
    EXPECT_EQ(r.pairs, 3u);
    EXPECT_EQ(r.used, 2u);
    // channel 0: d^2 = 1 + 4, r^2 = 1 + 4; channel 1: d^2 = 0 + 16, r^2 = 1 + 4
    EXPECT_NEAR(r.channel_relative_rms[0], 1.0, 1e-12);
    EXPECT_NEAR(r.channel_relative_rms[1], std::sqrt(16.0 / 5.0), 1e-12);
    EXPECT_NEAR(r.relative_rms, std::sqrt(21.0 / 10.0), 1e-12);
    EXPECT_NEAR(r.relative_rms_60, std::sqrt(1.0 / 2.0), 1e-12);
    EXPECT_EQ(r.worst.pair, 1u);
    EXPECT_EQ(r.worst.channel, 1u);
    EXPECT_EQ(r.worst.test, 6.0);
    EXPECT_EQ(r.worst.reference, 2.0);
}

TEST(BrdfComparison, HeldOutPairsAreFixedMirrorFirstAndInsideTheCap) {
    const std::vector<DirectionPair> a = npf::held_out_pairs(), b = npf::held_out_pairs();
    ASSERT_EQ(a.size(), 500u);
    const float cap = float(std::cos(80.0 * npf::kPiD / 180.0)) - 1e-6f;
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].wi.x, b[i].wi.x);
        EXPECT_EQ(a[i].wo.z, b[i].wo.z);
        EXPECT_GE(a[i].wi.z, cap) << i;
        EXPECT_GE(a[i].wo.z, cap) << i;
        if (i < 100) {  // mirror pairs
            EXPECT_EQ(a[i].wo.x, -a[i].wi.x);
            EXPECT_EQ(a[i].wo.z, a[i].wi.z);
        } else if (i < 200) {  // within about 10 degrees of the mirror direction
            const Vec3 m(-a[i].wi.x, -a[i].wi.y, a[i].wi.z);
            const double c = double(m.x) * a[i].wo.x + double(m.y) * a[i].wo.y + double(m.z) * a[i].wo.z;
            EXPECT_GT(c, std::cos(15.0 * npf::kPiD / 180.0)) << i;
        }
    }
    // The cosine-weighted part reaches both the normal and the cap.
    double lowest = 1.0, highest = 0.0;
    for (std::size_t i = 200; i < a.size(); ++i) lowest = std::min(lowest, double(a[i].wi.z)), highest = std::max(highest, double(a[i].wi.z));
    EXPECT_LT(lowest, 0.3);
    EXPECT_GT(highest, 0.98);
}

npf::AnalyticMaterial lambertian(double rho) {
    npf::AnalyticMaterial m;
    m.name = "lambertian";
    m.diffuse = npf::color::SampledSpectrum::constant(rho);
    return m;
}

// Two Lambertian surfaces differ by the ratio of their albedos at every pair.
TEST(BrdfComparison, TwoLambertiansDifferByTheirAlbedoRatio) {
    const npf::AnalyticBrdf a(lambertian(0.6)), b(lambertian(0.5));
    const npf::Channels ch = npf::Channels::spectral({450.f, 550.f, 650.f});
    const npf::BrdfComparisonResult r = npf::compare_brdfs(a, b, ch, npf::held_out_pairs());
    EXPECT_EQ(r.used, 500u);
    EXPECT_NEAR(r.relative_rms, 0.2, 1e-5);
    EXPECT_NEAR(r.relative_rms_60, 0.2, 1e-5);
    EXPECT_NEAR(npf::compare_brdfs(a, a, ch, npf::held_out_pairs()).relative_rms, 0.0, 0.0);
}

std::string write_text(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
    return path;
}

TEST(EvalAgainst, ComparesTwoMaterialsAndNamesTheLargestDifference) {
    const std::string dir = npf::testing::temporary_folder("eval-against");
    npf::testing::write_synthetic_rgl({}, dir + "/a.bsdf");
    const std::string bright = write_text(dir + "/bright.yaml", "name: bright\nwavelengths: 400:700:4\ndiffuse: 0.6\n");
    const std::string dim = write_text(dir + "/dim.yaml", "name: dim\nwavelengths: 400:700:4\ndiffuse: 0.5\n");

    npf::testing::ToolRun same = npf::testing::run_tool({"eval", dir + "/a.bsdf", "--against", dir + "/a.bsdf"});
    ASSERT_EQ(same.status, 0) << npf::testing::describe(same);
    EXPECT_NE(same.out.find("relative RMS      0.0000"), std::string::npos) << same.out;
    EXPECT_NE(same.out.find("500 (held out"), std::string::npos) << same.out;

    npf::testing::ToolRun diff = npf::testing::run_tool({"eval", bright, "--against", dim, "--json"});
    ASSERT_EQ(diff.status, 0) << npf::testing::describe(diff);
    EXPECT_NE(diff.out.find("\"relative_rms\": 0.2"), std::string::npos) << diff.out;

    // Given pairs: one inside the cap, one beyond it.
    const std::string pairs = write_text(dir + "/pairs.txt", "0 0 1 0.1 0 1\n# beyond 80 degrees\n1 0 0.05 0 0 1\n");
    npf::testing::ToolRun given = npf::testing::run_tool({"eval", bright, "--against", dim, "--dirs", pairs});
    ASSERT_EQ(given.status, 0) << npf::testing::describe(given);
    EXPECT_NE(given.out.find("2 (" + pairs + "), 1 with both directions within 80 deg"), std::string::npos) << given.out;
    EXPECT_NE(given.out.find("at pair 1:"), std::string::npos) << given.out;
}

TEST(EvalAgainst, RefusesWhatItCannotCompare) {
    const std::string dir = npf::testing::temporary_folder("eval-against-bad");
    npf::testing::write_synthetic_rgl({}, dir + "/a.bsdf");
    const std::string pairs = write_text(dir + "/grazing.txt", "1 0 0.05 0 0 1\n");
    const npf::testing::ToolRun none = npf::testing::run_tool({"eval", dir + "/a.bsdf", "--against", dir + "/a.bsdf", "--dirs", pairs});
    EXPECT_EQ(none.status, 1);
    EXPECT_NE(none.err.find("no pair has both directions within 80 degrees"), std::string::npos) << none.err;
    const npf::testing::ToolRun missing = npf::testing::run_tool({"eval", dir + "/a.bsdf", "--against", dir + "/nothing.bsdf"});
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.err.find("nothing.bsdf"), std::string::npos) << missing.err;
    const npf::testing::ToolRun pdf = npf::testing::run_tool({"eval", dir + "/a.bsdf", "--against", dir + "/a.bsdf", "--pdf"});
    EXPECT_EQ(pdf.status, 1);
    EXPECT_NE(pdf.err.find("--pdf: applies without --against only"), std::string::npos) << pdf.err;
    const npf::testing::ToolRun cap = npf::testing::run_tool({"eval", dir + "/a.bsdf", "--max-theta", "60"});
    EXPECT_EQ(cap.status, 1);
    EXPECT_NE(cap.err.find("--max-theta: applies with --against only"), std::string::npos) << cap.err;
}

}  // namespace

namespace {

// npf convert stores the held-out comparison; npf eval --against on the written file agrees.
TEST(EvalAgainst, ConvertStoresWhatEvalAgainstMeasures) {
    const std::string dir = npf::testing::temporary_folder("convert-held-out");
    npf::testing::write_synthetic_rgl({}, dir + "/a.bsdf");
    const npf::testing::ToolRun conv = npf::testing::run_tool(
        {"convert", dir + "/a.bsdf", "-o", dir + "/a.exr", "--preset", "preview", "--no-predict", "--error-pairs", "500"});
    ASSERT_EQ(conv.status, 0) << npf::testing::describe(conv);
    EXPECT_NE(conv.out.find("held out    relative RMS of f_r cos"), std::string::npos) << conv.out;
    const npf::testing::ToolRun info = npf::testing::run_tool({"info", dir + "/a.exr"});
    const std::size_t at = info.out.find("error_held_out_rel_rms: ");
    ASSERT_NE(at, std::string::npos) << info.out;
    const double stored = std::stod(info.out.substr(at + 24));
    const npf::testing::ToolRun eval = npf::testing::run_tool({"eval", dir + "/a.exr", "--against", dir + "/a.bsdf", "--json"});
    ASSERT_EQ(eval.status, 0) << npf::testing::describe(eval);
    const std::size_t r = eval.out.find("\"relative_rms\": ");
    ASSERT_NE(r, std::string::npos) << eval.out;
    const double measured = std::stod(eval.out.substr(r + 16));
    EXPECT_GT(stored, 0.0);
    EXPECT_NEAR(stored, measured, 1e-4 * measured) << info.out << eval.out;
}

}  // namespace
