// RglBrdf at numerical extremes (RglExtremes): no NaN, Inf or negative values anywhere over
// 1e6 pairs on the real and synthetic files (support/rgl_reference.h).
#include "rgl_reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using namespace npf::testing::rgl_reference;
using npf::Vec2;
using npf::Vec3;

// ---- Numerical extremes ---------------------------------------------------------------------

struct ExtremeStats {
    std::size_t evals = 0, samples_ok = 0, bad = 0;
    std::string first_bad;
};

void record_bad(ExtremeStats& st, const std::string& msg) {
    if (st.bad++ == 0) st.first_bad = msg;
}

// `count` pairs on one material: grazing (z in [1e-7, 1e-6] and 1e-6..1e-3), exactly the
// normal, exact mirror pairs, wo = wi, the horizon itself and below it, and uniform pairs;
// u includes 0 and the largest float below 1.
void run_extremes(const Material& m, std::size_t count, std::uint64_t seed, ExtremeStats& st) {
    Rng rng(seed);
    const auto q = m.brdf->native_query();
    const std::size_t nc = q.size();
    std::vector<float> out(nc), weight(nc);
    const Vec3 normal(0.f, 0.f, 1.f);
    auto pick = [&](int kind) -> Vec3 {
        switch (kind) {
            case 0: return near_horizon(rng, 1e-7, 1e-6);
            case 1: return near_horizon(rng, 1e-6, 1e-3);
            case 2: return normal;
            case 3: return direction_with_z(0.0, 2.0 * kPi * rng.uniform());  // on the horizon
            case 4: return direction_with_z(1.0 - 1e-7 * rng.uniform(), 2.0 * kPi * rng.uniform());
            default: return uniform_hemisphere(rng);
        }
    };
    for (std::size_t i = 0; i < count; ++i) {
        Vec3 wi, wo;
        const std::size_t kind = i % 16;
        if (kind == 0) {
            wi = pick(static_cast<int>(rng.next() % 7));
            wo = mirror(wi);
        } else if (kind == 1) {
            wi = pick(static_cast<int>(rng.next() % 7));
            wo = wi;
        } else if (kind == 2) {  // one direction below the horizon
            wi = pick(static_cast<int>(rng.next() % 7));
            wo = pick(static_cast<int>(rng.next() % 7));
            wo.z = -wo.z;
            if (rng.next() & 1) std::swap(wi, wo);
        } else {
            wi = pick(static_cast<int>(rng.next() % 7));
            wo = pick(static_cast<int>(rng.next() % 7));
        }
        Vec2 u{rng.uniform_float(), rng.uniform_float()};
        if (i % 97 == 0) u.x = 0.f;
        if (i % 89 == 0) u.y = 0.f;
        if (i % 83 == 0) u.x = 1.f - 0x1.0p-24f;
        if (i % 79 == 0) u.y = 1.f - 0x1.0p-24f;

        auto where = [&] {
            return m.name + ": wi = " + str(wi) + ", wo = " + str(wo) + ", u = (" +
                   std::to_string(u.x) + ", " + std::to_string(u.y) + ")";
        };
        m.brdf->eval_cos(wi, wo, q, out.data());
        ++st.evals;
        for (std::size_t k = 0; k < nc; ++k)
            if (!std::isfinite(out[k]) || out[k] < 0.f)
                record_bad(st, "eval_cos " + std::to_string(out[k]) + " at " + where());
        const float p = m.brdf->pdf(wi, wo);
        if (!std::isfinite(p) || p < 0.f)
            record_bad(st, "pdf " + std::to_string(p) + " at " + where());
        if (wi.z <= 0.f || wo.z <= 0.f) {
            bool zero = p == 0.f;
            for (std::size_t k = 0; k < nc; ++k) zero = zero && out[k] == 0.f;
            if (!zero) record_bad(st, "nonzero below the horizon at " + where());
        }

        npf::BrdfSample s;
        if (m.brdf->sample(wi, u, q, s, weight.data())) {
            ++st.samples_ok;
            const double len = std::sqrt(double(s.wo.x) * s.wo.x + double(s.wo.y) * s.wo.y +
                                         double(s.wo.z) * s.wo.z);
            if (!(std::isfinite(s.pdf) && s.pdf > 0.f) || !(s.wo.z > 0.f) ||
                !(std::fabs(len - 1.0) < 1e-4))
                record_bad(st, "sample wo " + str(s.wo) + " pdf " + std::to_string(s.pdf) +
                                   " at " + where());
            for (std::size_t k = 0; k < nc; ++k)
                if (!std::isfinite(weight[k]) || weight[k] < 0.f)
                    record_bad(st, "sample weight " + std::to_string(weight[k]) + " at " +
                                       where());
        } else {
            for (std::size_t k = 0; k < nc; ++k)
                if (weight[k] != 0.f)
                    record_bad(st, "failed sample left weight " + std::to_string(weight[k]) +
                                       " at " + where());
        }
    }
}

void run_all_extremes(std::size_t total) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<const Material*> materials;
    for (const auto& name : real_materials()) {
        std::string missing;
        if (const Material* m = real_material(name, missing)) materials.push_back(m);
    }
    for (const auto& k : synthetic_kinds()) materials.push_back(&synthetic_material(k));
    ExtremeStats st;
    const std::size_t per = total / materials.size() + 1;
    std::uint64_t seed = 1000;
    for (const Material* m : materials) run_extremes(*m, per, seed++, st);
    std::printf("[ extremes ] %zu pairs over %zu materials, %zu successful samples, %.2f s\n",
                st.evals, materials.size(), st.samples_ok, seconds_since(t0));
    EXPECT_EQ(st.bad, 0u) << "first: " << st.first_bad;
}

// 1e6 pairs take about 1 s (Release), so no reduced version is needed.
TEST(RglExtremes, NoNanInfOrNegative) { run_all_extremes(1000000); }

}  // namespace
