// Tests of the MERL `.binary` reader. No real MERL file is available, so every table is written
// here with npf::testing::write_merl (tests/support), and expected values are computed from the format's definition
// (half/difference angles, square-root theta_h grid, reciprocity fold, channel scales) with
// geometry written independently of the reader.
// Here a full 90 x 90 x 180 table whose channels spell out the bin; small tables:
// test_merl_small_tables.cpp; bad input: test_merl_bad_input.cpp.

#include "merl_geometry.h"
#include "merl_writer.h"

#include <npf/core/error.h>
#include <npf/materials/merl_brdf.h>

#include <chi2.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::testing::merl;
using npf::MerlBrdf, npf::MerlLookup, npf::Vec3;

// ---- A full 90 x 90 x 180 table whose channels spell out the bin ------------------------

// Every bin stores R = theta_h index + 1, G = theta_d index + 1, B = phi_d index + 1, except
// one bin with distinctive values, so a lookup shows which bin it used.
constexpr int kSpecialTh = 37, kSpecialTd = 12, kSpecialPd = 101;
constexpr double kSpecialStored[3] = {1234.5, 777.25, 42.125};

class MerlIndexTable : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        s_path = merl_file("index-table.binary");
        npf::testing::write_merl(s_path, 90, 90, 180, [](int ith, int itd, int ipd, double rgb[3]) {
            if (ith == kSpecialTh && itd == kSpecialTd && ipd == kSpecialPd) {
                for (int c = 0; c < 3; ++c) rgb[c] = kSpecialStored[c];
            } else {
                rgb[0] = ith + 1;
                rgb[1] = itd + 1;
                rgb[2] = ipd + 1;
            }
        });
        s_nearest = MerlBrdf::load(s_path).release();
        s_linear = MerlBrdf::load(s_path, {MerlLookup::Linear}).release();
    }
    static void TearDownTestSuite() {
        delete s_nearest;
        delete s_linear;
        s_nearest = s_linear = nullptr;
        std::error_code ec;
        fs::remove(s_path, ec);
    }

    static std::string s_path;
    static MerlBrdf* s_nearest;
    static MerlBrdf* s_linear;
};

std::string MerlIndexTable::s_path;
MerlBrdf* MerlIndexTable::s_nearest = nullptr;
MerlBrdf* MerlIndexTable::s_linear = nullptr;

// (a) The distinctive bin, reached from directions built by hand from its centre angles.
// The square-root theta_h grid matters: a uniform grid would put theta_h = 0.273 in bin 15.
TEST_F(MerlIndexTable, HandComputedBinAllChannels) {
    const double theta_h = theta_h_at(kSpecialTh + 0.5, 90);
    const double theta_d = theta_d_at(kSpecialTd + 0.5, 90);
    const double phi_d = phi_d_at(kSpecialPd + 0.5, 180);
    ASSERT_NEAR(theta_h, 0.27271, 1e-4);
    for (double phi_h : {0.0, 0.8, -2.5, 3.0}) {
        // phi_d - pi is the same configuration with wi and wo exchanged: the reciprocity fold
        // must bring it to the same bin.
        for (double pd : {phi_d, phi_d - kPi}) {
            const DirectionPair p = pair_from_half_diff(theta_h, phi_h, theta_d, pd);
            ASSERT_GT(p.wi.z, 0.f);
            ASSERT_GT(p.wo.z, 0.f);
            float out[3];
            s_nearest->eval_cos(p.wi, p.wo, rgb_query(), out);
            EXPECT_FLOAT_EQ(out[0], static_cast<float>(1234.5 * (1.0 / 1500.0) * p.wo.z));
            EXPECT_FLOAT_EQ(out[1], static_cast<float>(777.25 * (1.15 / 1500.0) * p.wo.z));
            EXPECT_FLOAT_EQ(out[2], static_cast<float>(42.125 * (1.66 / 1500.0) * p.wo.z));
        }
    }
    EXPECT_DOUBLE_EQ(s_nearest->bin_value(1, kSpecialTh, kSpecialTd, kSpecialPd),
                     777.25 * 1.15 / 1500.0);
}

// Every channel names the bin the reader used: check many bins, away from their edges.
TEST_F(MerlIndexTable, NearestPicksTheBinOfTheAngles) {
    npf::testing::Pcg32 rng(7);
    int checked = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const int ith = static_cast<int>(rng.next_float() * 90);
        const int itd = static_cast<int>(rng.next_float() * 90);
        const int ipd = static_cast<int>(rng.next_float() * 180);
        if (ith == kSpecialTh && itd == kSpecialTd && ipd == kSpecialPd) continue;
        const double theta_h = theta_h_at(ith + 0.2 + 0.6 * rng.next_float(), 90);
        const double theta_d = theta_d_at(itd + 0.2 + 0.6 * rng.next_float(), 90);
        const double phi_d = phi_d_at(ipd + 0.2 + 0.6 * rng.next_float(), 180);
        if (theta_h + theta_d > kPi / 2 - 0.01) continue;  // keep both above the horizon
        const double phi_h = 2 * kPi * rng.next_float() - kPi;
        const auto stored = stored_numbers(*s_nearest, pair_from_half_diff(theta_h, phi_h,
                                                                           theta_d, phi_d));
        ASSERT_NEAR(stored[0], ith + 1, 1e-3) << "theta_h bin, trial " << trial;
        ASSERT_NEAR(stored[1], itd + 1, 1e-3) << "theta_d bin, trial " << trial;
        ASSERT_NEAR(stored[2], ipd + 1, 1e-3) << "phi_d bin, trial " << trial;
        ++checked;
    }
    EXPECT_GT(checked, 1000);
}

// At the normal, theta_h = 0 and theta_d = 0 must use the first bins.
TEST_F(MerlIndexTable, NormalAndRetroreflection) {
    const Vec3 n{0.f, 0.f, 1.f};
    const auto at_normal = stored_numbers(*s_nearest, {n, n});
    EXPECT_NEAR(at_normal[0], 1.0, 1e-5);
    EXPECT_NEAR(at_normal[1], 1.0, 1e-5);
    // wi = wo away from the normal: theta_d = 0, theta_h = the elevation.
    const Vec3 w = npf::spherical_direction(0.6f, 1.1f);
    const auto retro = stored_numbers(*s_nearest, {w, w});
    EXPECT_NEAR(retro[0], std::floor(std::sqrt(0.6f / (kPi / 2)) * 90) + 1, 1e-4);
    EXPECT_NEAR(retro[1], 1.0, 1e-5);
}

// (b) f_r(wi, wo) = f_r(wo, wi).
TEST_F(MerlIndexTable, Reciprocity) {
    npf::testing::Pcg32 rng(11);
    for (const MerlBrdf* brdf : {s_nearest, s_linear}) {
        for (int i = 0; i < 5000; ++i) {
            const Vec3 a = random_upper_direction(rng), b = random_upper_direction(rng);
            if (a.z <= 0.f || b.z <= 0.f) continue;
            const auto ab = stored_numbers(*brdf, {a, b});
            const auto ba = stored_numbers(*brdf, {b, a});
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(ab[c], ba[c], 1e-5 * std::fabs(ab[c]) + 1e-6)
                    << (brdf == s_nearest ? "nearest" : "linear") << " pair " << i;
        }
    }
}

// (c) Isotropy: turning both directions about the normal changes nothing. Nearest uses pairs
// well inside their bins, so that float rounding of the rotation cannot cross a bin edge.
TEST_F(MerlIndexTable, Isotropy) {
    npf::testing::Pcg32 rng(13);
    for (int i = 0; i < 3000; ++i) {
        const double theta_h = theta_h_at(static_cast<int>(rng.next_float() * 60) + 0.5, 90);
        const double theta_d = theta_d_at(static_cast<int>(rng.next_float() * 30) + 0.5, 90);
        const double phi_d = phi_d_at(static_cast<int>(rng.next_float() * 180) + 0.5, 180);
        const DirectionPair p = pair_from_half_diff(theta_h, 0.3, theta_d, phi_d);
        const double angle = 2 * kPi * rng.next_float();
        const DirectionPair turned{rotate_z(p.wi, angle), rotate_z(p.wo, angle)};
        if (p.wo.z <= 0.f || p.wi.z <= 0.f) continue;
        const auto before = stored_numbers(*s_nearest, p);
        const auto after = stored_numbers(*s_nearest, turned);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(before[c], after[c], 1e-3) << "pair " << i;
    }
    for (int i = 0; i < 3000; ++i) {
        const DirectionPair p{random_upper_direction(rng), random_upper_direction(rng)};
        if (p.wo.z <= 0.f || p.wi.z <= 0.f) continue;
        const double angle = 2 * kPi * rng.next_float();
        const auto before = stored_numbers(*s_linear, p);
        const DirectionPair turned{rotate_z(p.wi, angle), rotate_z(p.wo, angle)};
        const auto after = stored_numbers(*s_linear, turned);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(before[c], after[c], 2e-2) << "pair " << i;
    }
}

// (e) Linear: the table is linear in the bin index on each axis, so trilinear interpolation
// between bin centres must reproduce "continuous coordinate + 0.5" exactly, held constant
// beyond the outer centres of theta_h and theta_d.
TEST_F(MerlIndexTable, LinearFollowsTheContinuousCoordinates) {
    npf::testing::Pcg32 rng(17);
    int checked = 0;
    for (int i = 0; i < 3000; ++i) {
        const double uh = 90 * rng.next_float(), ud = 90 * rng.next_float();
        const double up = 0.5 + 179 * rng.next_float();  // away from the wrap-around
        const double theta_h = theta_h_at(uh, 90), theta_d = theta_d_at(ud, 90);
        if (theta_h < 0.01 || theta_h + theta_d > kPi / 2 - 0.01) continue;
        // Keep off the special bin's neighbourhood, whose values are not the linear ramp.
        if (std::fabs(uh - kSpecialTh - 0.5) < 1.2 && std::fabs(ud - kSpecialTd - 0.5) < 1.2 &&
            std::fabs(up - kSpecialPd - 0.5) < 1.2)
            continue;
        const DirectionPair p =
            pair_from_half_diff(theta_h, 2 * kPi * rng.next_float(), theta_d, phi_d_at(up, 180));
        const auto stored = stored_numbers(*s_linear, p);
        ASSERT_NEAR(stored[0], std::clamp(uh, 0.5, 89.5) + 0.5, 2e-3) << "uh " << uh;
        ASSERT_NEAR(stored[1], std::clamp(ud, 0.5, 89.5) + 0.5, 2e-3) << "ud " << ud;
        // phi_d is poorly conditioned by float directions: about 1e-7 / sin(theta_d) radians
        // from d itself, and 1e-7 / (cos(theta_d) sin(theta_h)) through phi_h when both
        // directions graze (|wi + wo| = 2 cos(theta_d)) while the half vector is near the normal.
        const double phi_d_error =
            3e-7 * (1 / std::sin(theta_d) + 1 / (std::cos(theta_d) * std::sin(theta_h)));
        ASSERT_NEAR(stored[2], up + 0.5, 2e-3 + phi_d_error * 180 / kPi)
            << "up " << up << " theta_h " << theta_h << " theta_d " << theta_d;
        ++checked;
    }
    EXPECT_GT(checked, 1000);
}

// (e) At bin centres Linear and Nearest agree, the distinctive bin included.
TEST_F(MerlIndexTable, LinearEqualsNearestAtBinCentres) {
    npf::testing::Pcg32 rng(19);
    std::vector<std::array<int, 3>> bins = {{kSpecialTh, kSpecialTd, kSpecialPd}, {0, 0, 0},
                                            {89, 0, 179}, {5, 80, 3}};
    for (int i = 0; i < 2000; ++i)
        bins.push_back({static_cast<int>(rng.next_float() * 90),
                        static_cast<int>(rng.next_float() * 90),
                        static_cast<int>(rng.next_float() * 180)});
    int checked = 0;
    for (const auto& bin : bins) {
        const double theta_h = theta_h_at(bin[0] + 0.5, 90), theta_d = theta_d_at(bin[1] + 0.5, 90);
        if (theta_h + theta_d > kPi / 2 - 0.01) continue;
        const DirectionPair p =
            pair_from_half_diff(theta_h, 1.7, theta_d, phi_d_at(bin[2] + 0.5, 180));
        const auto nearest = stored_numbers(*s_nearest, p);
        const auto linear = stored_numbers(*s_linear, p);
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(linear[c], nearest[c], 2e-3 * std::fabs(nearest[c]))
                << "bin " << bin[0] << " " << bin[1] << " " << bin[2] << " channel " << c;
        ++checked;
    }
    EXPECT_GT(checked, 500);
}

// (f) Sampling: cosine-weighted, consistent with pdf, weight = eval / pdf.
TEST_F(MerlIndexTable, SampleMatchesPdfAndEval) {
    npf::testing::Pcg32 rng(23);
    const npf::ChannelQuery q = rgb_query();
    double sum_z = 0, sum_z2 = 0;
    int accepted = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 wi = random_upper_direction(rng);
        if (wi.z <= 0.f) continue;
        npf::BrdfSample s;
        float weight[3], eval[3];
        if (!s_nearest->sample(wi, {rng.next_float(), rng.next_float()}, q, s, weight)) continue;
        ++accepted;
        ASSERT_GT(s.wo.z, 0.f);
        ASSERT_NEAR(npf::length(s.wo), 1.f, 1e-5f);
        ASSERT_EQ(s.pdf, s_nearest->pdf(wi, s.wo));
        ASSERT_FLOAT_EQ(s.pdf, static_cast<float>(s.wo.z / kPi));
        s_nearest->eval_cos(wi, s.wo, q, eval);
        for (int c = 0; c < 3; ++c) ASSERT_FLOAT_EQ(weight[c], eval[c] / s.pdf);
        sum_z += s.wo.z;
        sum_z2 += s.wo.z * s.wo.z;
    }
    EXPECT_GT(accepted, 19900);
    // Cosine-weighted hemisphere: E[cos] = 2/3, E[cos^2] = 1/2.
    EXPECT_NEAR(sum_z / accepted, 2.0 / 3.0, 0.01);
    EXPECT_NEAR(sum_z2 / accepted, 0.5, 0.01);

    // Below the horizon: no sample, zero weights, zero pdf.
    npf::BrdfSample s;
    float weight[3] = {1.f, 1.f, 1.f};
    EXPECT_FALSE(s_nearest->sample({0.f, 0.6f, -0.8f}, {0.3f, 0.4f}, q, s, weight));
    for (float w : weight) EXPECT_EQ(w, 0.f);
    EXPECT_EQ(s_nearest->pdf({0.f, 0.6f, -0.8f}, {0.f, 0.f, 1.f}), 0.f);
    EXPECT_EQ(s_nearest->pdf({0.f, 0.f, 1.f}, {0.f, 0.6f, -0.8f}), 0.f);
}

// (f) The pdf integrates to one over the hemisphere (midpoint rule in theta and phi), and the
// chi-square test agrees that sample() draws from it.
TEST_F(MerlIndexTable, PdfIntegratesToOne) {
    for (const Vec3 wi : {Vec3(0.f, 0.f, 1.f), npf::spherical_direction(1.2f, 0.4f),
                          npf::spherical_direction(1.5707f, -2.f)}) {
        const int n_theta = 256, n_phi = 256;
        double integral = 0;
        for (int i = 0; i < n_theta; ++i) {
            const double theta = (i + 0.5) / n_theta * (kPi / 2);
            for (int j = 0; j < n_phi; ++j) {
                const double phi = (j + 0.5) / n_phi * 2 * kPi;
                const Vec3 wo = npf::spherical_direction(static_cast<float>(theta),
                                                         static_cast<float>(phi));
                integral += s_nearest->pdf(wi, wo) * std::sin(theta);
            }
        }
        integral *= (kPi / 2 / n_theta) * (2 * kPi / n_phi);
        EXPECT_NEAR(integral, 1.0, 1e-4);

        npf::testing::Chi2Options opt;
        opt.sample_count = 100000;
        const npf::testing::Chi2Result r = npf::testing::run_chi2_test(*s_nearest, wi, opt);
        EXPECT_TRUE(r.passed) << r.message;
    }
}


TEST_F(MerlIndexTable, AlwaysFiniteAndNonNegative) {
    check_always_finite(*s_nearest, 29, 50000);
    check_always_finite(*s_linear, 30, 50000);
}

TEST_F(MerlIndexTable, HonoursChannelQueryMapping) {
    const DirectionPair p = pair_from_half_diff(theta_h_at(kSpecialTh + 0.5, 90), 0.1,
                                                theta_d_at(kSpecialTd + 0.5, 90),
                                                phi_d_at(kSpecialPd + 0.5, 180));
    npf::ChannelQuery q = rgb_query();
    q.index0 = {2, 0};
    q.index1 = {1, 0};
    q.weight1 = {0.25f, 0.f};
    float out[2];
    s_nearest->eval_cos(p.wi, p.wo, q, out);
    const double r = kSpecialStored[0] * kScale[0], g = kSpecialStored[1] * kScale[1],
                 b = kSpecialStored[2] * kScale[2];
    EXPECT_FLOAT_EQ(out[0], static_cast<float>((0.75 * b + 0.25 * g) * p.wo.z));
    EXPECT_FLOAT_EQ(out[1], static_cast<float>(r * p.wo.z));
}

TEST_F(MerlIndexTable, Info) {
    const npf::BrdfInfo& info = s_nearest->info();
    EXPECT_EQ(info.format, "merl");
    EXPECT_EQ(info.path, s_path);
    EXPECT_EQ(info.description, "index-table");
    EXPECT_TRUE(info.isotropic);
    EXPECT_TRUE(info.channels.is_rgb());
    EXPECT_EQ(info.file_bytes, 12u + 90u * 90u * 180u * 3u * 8u);
    EXPECT_EQ(fs::file_size(s_path), info.file_bytes);
    auto detail = [&](const npf::BrdfInfo& i, const std::string& key) {
        for (const auto& kv : i.details)
            if (kv.first == key) return kv.second;
        return std::string("<missing>");
    };
    EXPECT_EQ(detail(info, "grid"), "90 x 90 x 180 (theta_h x theta_d x phi_d)");
    EXPECT_EQ(detail(info, "lookup"), "nearest");
    EXPECT_EQ(detail(info, "invalid samples"), "0 of 1458000");
    EXPECT_EQ(detail(s_linear->info(), "lookup"), "linear");
    EXPECT_EQ(s_nearest->theta_h_bins(), 90);
    EXPECT_EQ(s_nearest->theta_d_bins(), 90);
    EXPECT_EQ(s_nearest->phi_d_bins(), 180);
}

TEST_F(MerlIndexTable, SniffsTheFormat) {
    std::uint8_t head[16];
    std::ifstream in(s_path, std::ios::binary);
    in.read(reinterpret_cast<char*>(head), sizeof head);
    const std::uint64_t size = fs::file_size(s_path);
    EXPECT_TRUE(MerlBrdf::looks_like_merl(head, sizeof head, size));
    EXPECT_FALSE(MerlBrdf::looks_like_merl(head, sizeof head, size - 8));
    EXPECT_FALSE(MerlBrdf::looks_like_merl(head, sizeof head, size + 1));
    EXPECT_FALSE(MerlBrdf::looks_like_merl(head, 11, size));
    head[0] = 0;  // theta_h dimension 0 (90 = 0x5a in the low byte)
    EXPECT_FALSE(MerlBrdf::looks_like_merl(head, sizeof head, size));
}

}  // namespace
