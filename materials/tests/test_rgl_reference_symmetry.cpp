// Symmetry facts that follow from the RGL format (RglReferenceSymmetry): folded anisotropic
// files are exactly invariant under their symmetries, isotropic ones under rotation about the
// normal up to float conditioning (support/rgl_reference.h).
#include "rgl_reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using namespace npf::testing::rgl_reference;
using npf::Vec3;
using npf::testing::Vec3d;

// ---- (d) Symmetry facts ---------------------------------------------------------------------

Vec3 rotate_z(const Vec3& w, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return to_f({c * w.x - s * w.y, s * w.x + c * w.y, w.z});
}

// Evaluation, pdf of `m` at (wi, wo) and at (T wi, T wo) agree exactly (folding makes them
// the same computation) for the maps T given.
void expect_exact_invariance(const Material& m, const std::vector<Vec3 (*)(const Vec3&)>& maps,
                             const std::string& what) {
    const auto q = m.brdf->native_query();
    const std::size_t nc = q.size();
    std::vector<float> a(nc), b(nc);
    const auto pairs = comparison_pairs(4000, 31);
    int failures = 0;
    for (const Pair& p : pairs) {
        m.brdf->eval_cos(p.wi, p.wo, q, a.data());
        const float pa = m.brdf->pdf(p.wi, p.wo);
        for (auto T : maps) {
            m.brdf->eval_cos(T(p.wi), T(p.wo), q, b.data());
            const float pb = m.brdf->pdf(T(p.wi), T(p.wo));
            bool same = pa == pb;
            for (std::size_t k = 0; k < nc; ++k) same = same && a[k] == b[k];
            if (!same && ++failures <= 5)
                ADD_FAILURE() << what << ": wi = " << str(p.wi) << ", wo = " << str(p.wo)
                              << " -> " << str(T(p.wi)) << ", " << str(T(p.wo)) << ": eval "
                              << a[0] << " vs " << b[0] << ", pdf " << pa << " vs " << pb;
        }
    }
    EXPECT_EQ(failures, 0) << what;
}

Vec3 rotate_pi(const Vec3& w) { return {-w.x, -w.y, w.z}; }
Vec3 mirror_x(const Vec3& w) { return {-w.x, w.y, w.z}; }  // about the plane x = 0
Vec3 mirror_y(const Vec3& w) { return {w.x, -w.y, w.z}; }  // about the plane y = 0

TEST(RglReferenceSymmetry, Reduction2IsInvariantUnderHalfTurn) {
    for (const char* kind : {"aniso_r2_rgb", "aniso_r2_spectral", "aniso_r2_jacobian0"})
        expect_exact_invariance(synthetic_material(kind), {&rotate_pi}, kind);
}

TEST(RglReferenceSymmetry, Reduction4IsInvariantUnderMirrors) {
    for (const char* kind : {"aniso_r4_rgb", "aniso_r4_spectral"})
        expect_exact_invariance(synthetic_material(kind), {&rotate_pi, &mirror_x, &mirror_y},
                                kind);
}

// Isotropic files (nP = 1) use only the azimuth of wh relative to wi, so rotating both
// directions about the normal changes the value only through float rounding of the rotated
// directions (allowed for as in compare_with_naive, with twice NaiveRgl's spread, as both
// evaluations round). Not near wh = normal: there the azimuth of wh comes from the rounding
// residue of wi + wo, and the tables need not be continuous in it (the u_theta = 0 column of
// the VNDF inverts to a whole column of data nodes).
void expect_rotation_invariance(const Material& m) {
    const auto q = m.brdf->native_query();
    const std::size_t nc = q.size();
    std::vector<float> a(nc), b(nc);
    Rng rng(77);
    const auto pairs = comparison_pairs(4000, 41);
    Agreement ev{"rotated eval"}, pd{"rotated pdf"};
    const auto perturbations = conditioning_perturbations(false);
    std::vector<double> all_a, all_p;
    struct Row {
        std::vector<float> a, b;
        float pa, pb;
        Pair p;
        double angle;
    };
    std::vector<Row> rows;
    for (const Pair& p : pairs) {
        // At wi = normal, phi_i = atan2(0, 0) = 0 whatever the rotation, so rotating wo alone
        // changes the relative azimuth: no invariance to expect there.
        if (p.wi.x == 0.f && p.wi.y == 0.f) continue;
        const double hx = double(p.wi.x) + p.wo.x, hy = double(p.wi.y) + p.wo.y,
                     hz = double(p.wi.z) + p.wo.z;
        if (std::sqrt(hx * hx + hy * hy) < 1e-2 * std::sqrt(hx * hx + hy * hy + hz * hz)) continue;
        const double angle = 2.0 * kPi * rng.uniform();
        Row r;
        r.p = p;
        r.angle = angle;
        m.brdf->eval_cos(p.wi, p.wo, q, a.data());
        m.brdf->eval_cos(rotate_z(p.wi, angle), rotate_z(p.wo, angle), q, b.data());
        r.a = a;
        r.b = b;
        r.pa = m.brdf->pdf(p.wi, p.wo);
        r.pb = m.brdf->pdf(rotate_z(p.wi, angle), rotate_z(p.wo, angle));
        for (float v : a) all_a.push_back(v);
        all_p.push_back(r.pa);
        rows.push_back(r);
    }
    ev.tiny = 1e-4 * max_abs(all_a);
    pd.tiny = 1e-4 * max_abs(all_p);
    for (const Row& r : rows) {
        auto where = [&] {
            return "wi = " + str(r.p.wi) + ", wo = " + str(r.p.wo) + ", angle " +
                   std::to_string(r.angle);
        };
        const Vec3d wi = to_d(r.p.wi), wo = to_d(r.p.wo);
        std::vector<double> spread;
        auto eval_spread = [&](std::size_t k) {
            if (spread.empty()) {
                spread.assign(nc, 0.0);
                const auto v0 = m.naive->eval_cos(wi, wo, {}, true);
                for (const auto& pt : perturbations) {
                    const auto v = m.naive->eval_cos(wi, wo, {}, true, pt);
                    for (std::size_t j = 0; j < nc; ++j)
                        spread[j] = std::max(spread[j], 2.0 * std::fabs(v[j] - v0[j]));
                }
            }
            return spread[k];
        };
        for (std::size_t k = 0; k < nc; ++k)
            ev.add(r.b[k], r.a[k], [&] { return eval_spread(k); }, where);
        pd.add(r.pb, r.pa,
               [&] {
                   const double p0 = m.naive->pdf(wi, wo);
                   double sp = 0.0;
                   for (const auto& pt : perturbations)
                       sp = std::max(sp, 2.0 * std::fabs(m.naive->pdf(wi, wo, pt) - p0));
                   return sp;
               },
               where);
    }
    std::printf("[ rotation ] %-22s eval max rel %.2g, pdf max rel %.2g; %zu of %zu within "
                "float conditioning only\n",
                m.name.c_str(), ev.max_rel, pd.max_rel, ev.conditioned + pd.conditioned,
                ev.count + pd.count);
    EXPECT_EQ(ev.bad, 0u) << m.name << ": " << ev.summary();
    EXPECT_EQ(pd.bad, 0u) << m.name << ": " << pd.summary();
    EXPECT_LE(ev.conditioned + pd.conditioned, (ev.count + pd.count) / 100 + 1) << m.name;
}

TEST(RglReferenceSymmetry, IsotropicIsInvariantUnderRotation) {
    expect_rotation_invariance(synthetic_material("iso_rgb"));
    expect_rotation_invariance(synthetic_material("iso_spectral"));
    for (const auto& name : real_materials()) {
        std::string missing;
        if (const Material* m = real_material(name, missing)) expect_rotation_invariance(*m);
    }
}

}  // namespace
