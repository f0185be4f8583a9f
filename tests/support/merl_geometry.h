// Shared by the MERL reader tests (test_merl_*.cpp): the format's geometry written
// independently of the reader (half/difference angles to directions, bin coordinates to
// angles, channel scales), a folder for the tables the tests write, and the check that a table
// gives finite, non-negative values everywhere.
#pragma once

#include "chi2.h"
#include "synthetic_rgl.h"

#include <npf/core/channels.h>
#include <npf/core/vec.h>
#include <npf/materials/merl_brdf.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>

namespace npf::testing::merl {

constexpr double kPi = 3.14159265358979323846;
constexpr double kScale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

// A file in the tables' folder (one per test process, removed when the process ends).
inline std::string merl_file(const std::string& name) {
    static const std::string dir = temporary_folder("merl");
    return dir + "/" + name;
}

inline npf::ChannelQuery rgb_query(bool clamp_negative = true) {
    npf::ChannelQuery q;
    q.requested = npf::Channels::rgb();
    q.index0 = {0, 1, 2};
    q.index1 = {0, 1, 2};
    q.weight1 = {0.f, 0.f, 0.f};
    q.clamp_negative = clamp_negative;
    return q;
}

struct DirectionPair {
    Vec3 wi, wo;
};

// The inverse of the MERL parameterisation: the difference vector d (polar theta_d, azimuth
// phi_d about the half vector) is rotated about y by theta_h, then about z by phi_h; wo is d
// mirrored about the half vector (-d.x, -d.y, d.z) taken through the same rotations.
inline DirectionPair pair_from_half_diff(double theta_h, double phi_h, double theta_d, double phi_d) {
    const double dx = std::sin(theta_d) * std::cos(phi_d);
    const double dy = std::sin(theta_d) * std::sin(phi_d);
    const double dz = std::cos(theta_d);
    auto to_local = [&](double x, double y, double z) {
        const double x1 = x * std::cos(theta_h) + z * std::sin(theta_h);
        const double z1 = -x * std::sin(theta_h) + z * std::cos(theta_h);
        const double y1 = y;
        return Vec3(static_cast<float>(x1 * std::cos(phi_h) - y1 * std::sin(phi_h)),
                    static_cast<float>(x1 * std::sin(phi_h) + y1 * std::cos(phi_h)),
                    static_cast<float>(z1));
    };
    return {to_local(dx, dy, dz), to_local(-dx, -dy, dz)};
}

// Continuous bin coordinates (bin k covers [k, k+1)) -> angles, per the format's index rules.
inline double theta_h_at(double coord, int n) { return (coord / n) * (coord / n) * (kPi / 2); }
inline double theta_d_at(double coord, int n) { return coord / n * (kPi / 2); }
inline double phi_d_at(double coord, int n) { return coord / n * kPi; }

inline Vec3 rotate_z(const Vec3& v, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return {static_cast<float>(c * v.x - s * v.y), static_cast<float>(s * v.x + c * v.y), v.z};
}

inline Vec3 random_upper_direction(Pcg32& rng) {
    const double z = rng.next_float();
    const double phi = 2 * kPi * rng.next_float();
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    return {static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
            static_cast<float>(z)};
}

// f_r / channel scale: the stored number the reader picked (or blended) for channel c.
inline std::array<double, 3> stored_numbers(const MerlBrdf& brdf, const DirectionPair& p) {
    float out[3];
    brdf.eval_cos(p.wi, p.wo, rgb_query(false), out);
    std::array<double, 3> stored{};
    for (int c = 0; c < 3; ++c) stored[c] = out[c] / p.wo.z / kScale[c];
    return stored;
}

// (h) No NaN, Inf or negative value anywhere, including grazing and normal directions.
inline void check_always_finite(const MerlBrdf& brdf, std::uint64_t seed, int pairs) {
    Pcg32 rng(seed);
    auto direction = [&](int kind) {
        const double phi = 2 * kPi * rng.next_float();
        double z = rng.next_float();
        if (kind == 1) z = 1e-6;                    // just above the horizon
        if (kind == 2) return Vec3(0.f, 0.f, 1.f);  // exactly the normal
        if (kind == 3) z = 0.0;                     // on the horizon: must give 0
        if (kind == 4) z = 1.0 - 1e-7;              // next to the normal
        const double r = std::sqrt(1 - z * z);
        return Vec3(static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi)),
                    static_cast<float>(z));
    };
    const npf::ChannelQuery clamped = rgb_query(true), raw = rgb_query(false);
    for (int i = 0; i < pairs; ++i) {
        const Vec3 wi = direction(static_cast<int>(rng.next_float() * 5));
        const Vec3 wo = direction(static_cast<int>(rng.next_float() * 5));
        const bool below = wi.z <= 0.f || wo.z <= 0.f;
        float out[3], out_raw[3];
        brdf.eval_cos(wi, wo, clamped, out);
        brdf.eval_cos(wi, wo, raw, out_raw);
        for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(out[c])) << i;
            ASSERT_TRUE(std::isfinite(out_raw[c])) << i;
            ASSERT_GE(out[c], 0.f) << i;
            if (below) {
                ASSERT_EQ(out[c], 0.f) << i;
                ASSERT_EQ(out_raw[c], 0.f) << i;
            }
        }
        const float p = brdf.pdf(wi, wo);
        ASSERT_TRUE(std::isfinite(p) && p >= 0.f) << i;
        if (below) {
            ASSERT_EQ(p, 0.f) << i;
        }
        npf::BrdfSample s;
        float weight[3];
        if (brdf.sample(wi, {rng.next_float(), rng.next_float()}, clamped, s, weight)) {
            ASSERT_TRUE(std::isfinite(s.pdf) && s.pdf > 0.f) << i;
            for (float w : weight) ASSERT_TRUE(std::isfinite(w) && w >= 0.f) << i;
        }
    }
}

}  // namespace npf::testing::merl
