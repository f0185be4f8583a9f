// The detail layer (format version 2): its geometry against Rusinkiewicz's parameterisation, the
// model's evaluation against an independent trilinear lookup, the file round trip (version 1 kept
// for files without it), both shading paths, sample weights, the fit (recovery of a known
// residual, energy held, the same on any thread count), and G's horizon rule.

#include "npf_test_factors.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/fit/detail_fit.h>
#include <npf/fit/rusinkiewicz.h>
#include <npf/fit/spectral_compression.h>
#include <npf/edit/albedo_limit.h>
#include <npf/edit/colour_edits.h>
#include <npf/edit/compression.h>
#include <npf/edit/ndf_transform.h>
#include <npf/edit/recipe.h>
#include <npf/edit/thin_film.h>
#include <npf/core/directional_albedo.h>
#include <npf/core/error.h>
#include <npf/shading/detail_grid.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_texture_file.h>

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

using npf::DetailGrid, npf::NpfClosure, npf::NpfModel, npf::Vec3, npf::Vec3d, npf::WavelengthRequest;

constexpr double kHalfPi = 0.5 * npf::kPiD, kTwoPi = 2.0 * npf::kPiD;

const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("npf-detail");
    return dir;
}

Vec3 random_direction(std::mt19937& rng, double min_z = 0.02) {
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const double z = min_z + (1.0 - min_z) * uni(rng), phi = kTwoPi * uni(rng), r = std::sqrt(1.0 - z * z);
    return {float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)};
}

Vec3d to_double(const Vec3& v) { return {v.x, v.y, v.z}; }

// A smooth residual on `grid` for channel c (small beside the test materials' diffuse term, so
// that the clamp at 0 never acts).
double smooth_residual(const DetailGrid& g, int h, int d, int p, std::size_t c) {
    const double u = (h + 0.5) / g.theta_h, td = (d + 0.5) / g.theta_d, pd = kTwoPi * (p + 0.5) / g.phi_d;
    return 0.02 * (1.0 + 0.3 * double(c)) * std::cos(2.0 * u) * (1.0 + td) * (1.0 + 0.5 * std::sin(pd + 0.3 * double(c)));
}

// Adds a known detail layer, compressed across channels as the fit does (full rank).
void add_detail(NpfModel& m, const DetailGrid& g) {
    const std::size_t C = m.channel_count(), cells = g.cells();
    std::vector<float> tables(C * cells);
    for (std::size_t c = 0; c < C; ++c) {
        for (int h = 0; h < g.theta_h; ++h) {
            for (int d = 0; d < g.theta_d; ++d) {
                for (int p = 0; p < g.phi_d; ++p) tables[c * cells + g.index(h, d, p)] = float(smooth_residual(g, h, d, p, c));
            }
        }
    }
    m.detail_grid = g;
    m.detail = npf::compress_tables(tables, C, cells, 1.0, 0);
}

NpfModel test_model(bool anisotropic, std::size_t channels, bool spectral) {
    NpfModel m = npf::compress_factors(npf::testing::make_test_factors({anisotropic, channels, spectral, 3}),
                                       npf::CompressionOptions());
    return m;
}

// The residual of channel c at a pair, computed independently of NpfModel: Rusinkiewicz's angles
// from the converter's parameterisation, a trilinear lookup written out here.
double independent_residual(const NpfModel& m, std::size_t c, const Vec3& wi, const Vec3& wo) {
    const npf::HalfDiff a = npf::half_diff_from_directions(to_double(wi), to_double(wo));
    const DetailGrid& g = m.detail_grid;
    const double x[3] = {std::sqrt(a.theta_h / kHalfPi) * g.theta_h - 0.5, a.theta_d / kHalfPi * g.theta_d - 0.5,
                         a.phi_d / kTwoPi * g.phi_d - 0.5};
    const int n[3] = {g.theta_h, g.theta_d, g.phi_d};
    int i0[3], i1[3];
    double t[3];
    for (int k = 0; k < 3; ++k) {
        double v = x[k];
        if (k < 2) {
            v = std::clamp(v, 0.0, double(n[k] - 1));
            i0[k] = std::min(int(std::floor(v)), n[k] - 1);
            i1[k] = std::min(i0[k] + 1, n[k] - 1);
        } else {
            v = v - std::floor(v / n[k]) * n[k];
            i0[k] = int(std::floor(v)) % n[k];
            i1[k] = (i0[k] + 1) % n[k];
        }
        t[k] = v - std::floor(v);
        if (k < 2 && i0[k] == n[k] - 1) t[k] = 0.0;
    }
    double r = 0.0;
    for (int bits = 0; bits < 8; ++bits) {
        const int h = bits & 4 ? i1[0] : i0[0], d = bits & 2 ? i1[1] : i0[1], p = bits & 1 ? i1[2] : i0[2];
        const double w = (bits & 4 ? t[0] : 1 - t[0]) * (bits & 2 ? t[1] : 1 - t[1]) * (bits & 1 ? t[2] : 1 - t[2]);
        r += w * m.detail.at(c, g.index(h, d, p));
    }
    return r;
}

// ---- Geometry --------------------------------------------------------------------------------

TEST(DetailLayer, PhiDIsRusinkiewiczs) {
    std::mt19937 rng(4);
    double worst = 0.0;
    for (int n = 0; n < 20000; ++n) {
        const Vec3 wi = random_direction(rng), wo = n % 3 ? random_direction(rng) : Vec3(-wi.x, -wi.y, wi.z);
        const double hx = double(wi.x) + wo.x, hy = double(wi.y) + wo.y, hz = double(wi.z) + wo.z;
        const double fast = npf::detail_phi_d(wi.x, wi.y, wi.z, hx, hy, hz, std::sqrt(hx * hx + hy * hy + hz * hz));
        const double want = npf::half_diff_from_directions(to_double(wi), to_double(wo)).phi_d;
        double diff = std::fabs(fast - want);
        diff = std::min(diff, kTwoPi - diff);
        // phi_d is undefined when wi lies on h (theta_d = 0): skip the mirror pairs' degenerate end.
        if (npf::half_diff_from_directions(to_double(wi), to_double(wo)).theta_d > 1e-4) worst = std::max(worst, diff);
    }
    EXPECT_LT(worst, 1e-6);
}

// ---- Evaluation --------------------------------------------------------------------------------

TEST(DetailLayer, ModelAddsTheTrilinearResidual) {
    for (const bool anisotropic : {false, true}) {
        SCOPED_TRACE(anisotropic ? "anisotropic" : "isotropic");
        const NpfModel base = test_model(anisotropic, anisotropic ? 5 : 3, anisotropic);
        NpfModel detailed = base;
        add_detail(detailed, {5, 4, 7});
        ASSERT_NO_THROW(detailed.validate("test"));
        std::mt19937 rng(11);
        const std::size_t C = base.channel_count();
        std::vector<double> a(C), b(C);
        for (int n = 0; n < 3000; ++n) {
            const Vec3 wi = random_direction(rng), wo = random_direction(rng);
            base.eval_all(wi, wo, a.data());
            detailed.eval_all(wi, wo, b.data());
            for (std::size_t c = 0; c < C; ++c) {
                const double want = independent_residual(detailed, c, wi, wo);
                ASSERT_NEAR(b[c] - a[c], want, 1e-5 * (std::fabs(want) + a[c])) << "pair " << n << " channel " << c;
            }
        }
    }
}

TEST(DetailLayer, NegativeSumsClampAtZero) {
    NpfModel m = test_model(false, 3, false);
    add_detail(m, {2, 2, 2});
    for (float& w : m.detail.weights) w *= -1e4f;  // a residual far below the base everywhere
    std::mt19937 rng(2);
    double v[3];
    for (int n = 0; n < 200; ++n) {
        m.eval_all(random_direction(rng), random_direction(rng), v);
        for (double x : v) ASSERT_EQ(x, 0.0);
    }
}

// ---- The file --------------------------------------------------------------------------------

int format_version_of(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in);
    return in ? in->spec().get_int_attribute("npf:format_version") : -1;
}

TEST(DetailLayer, FileRoundTripsAndFilesWithoutDetailStayVersion1) {
    NpfModel m = test_model(true, 6, true);
    const std::string plain = folder() + "/plain.exr", detailed = folder() + "/detailed.exr";
    npf::write_npf_texture(m, plain);
    EXPECT_EQ(format_version_of(plain), 1);
    EXPECT_FALSE(npf::read_npf_texture(plain).has_detail());

    add_detail(m, {6, 5, 9});
    for (float& v : m.detail.basis) v = float(Imath::half(v));  // as the fit stores it
    npf::write_npf_texture(m, detailed);
    EXPECT_EQ(format_version_of(detailed), 2);
    const NpfModel back = npf::read_npf_texture(detailed);
    ASSERT_TRUE(back.has_detail());
    EXPECT_TRUE(back.detail_grid == m.detail_grid);
    EXPECT_EQ(back.detail.rank, m.detail.rank);
    EXPECT_EQ(back.detail.basis, m.detail.basis) << "half-exact values round-trip bit for bit";
    EXPECT_EQ(back.detail.weights, m.detail.weights);
    EXPECT_EQ(back.detail.singular_values, m.detail.singular_values);
    {
        auto in = OIIO::ImageInput::open(detailed);
        ASSERT_TRUE(in);
        bool found = false;
        for (int i = 0; in->seek_subimage(i, 0); ++i) {
            if (in->spec().get_string_attribute("oiio:subimagename") != "detail") continue;
            found = true;
            EXPECT_EQ(in->spec().format, OIIO::TypeHalf) << "a half-exact basis is stored as half";
            EXPECT_EQ(in->spec().width, 9);
            EXPECT_EQ(in->spec().height, 6 * 5);
        }
        EXPECT_TRUE(found);
    }
    // A basis that half cannot hold exactly is stored as float, still losslessly.
    m.detail.basis[3] = 1.f / 3.f;
    npf::write_npf_texture(m, detailed);
    EXPECT_EQ(npf::read_npf_texture(detailed).detail.basis, m.detail.basis);
}

TEST(DetailLayer, BothShadingPathsAgree) {
    struct Case {
        const char* name;
        bool anisotropic;
        std::size_t channels;
        bool spectral;
    };
    for (const Case& k : {Case{"isotropic rgb", false, 3, false}, Case{"anisotropic spectral", true, 7, true}}) {
        SCOPED_TRACE(k.name);
        NpfModel m = test_model(k.anisotropic, k.channels, k.spectral);
        add_detail(m, {7, 5, 11});
        const std::string path = folder() + "/paths_" + std::to_string(k.channels) + ".exr";
        npf::write_npf_texture(m, path);
        const NpfClosure memory(path, NpfClosure::Path::Memory), texture(path, NpfClosure::Path::Texture);
        EXPECT_TRUE(texture.model().detail.basis.empty()) << "the texture path keeps the detail in the TextureSystem";
        const NpfModel reference = npf::read_npf_texture(path);
        std::vector<float> a(k.channels), b(k.channels);
        std::vector<double> want(k.channels);
        std::mt19937 rng(5);
        for (int n = 0; n < 3000; ++n) {
            const Vec3 wo = random_direction(rng), wi = random_direction(rng);
            memory.eval(wo, wi, WavelengthRequest::stored(), a.data());
            texture.eval(wo, wi, WavelengthRequest::stored(), b.data());
            reference.eval_all(wo, wi, want.data());  // the closure's wo is the model's wi
            for (std::size_t c = 0; c < k.channels; ++c) {
                const double w = want[c] * wi.z;
                ASSERT_NEAR(a[c], w, 1e-5 * std::fabs(w) + 1e-7) << "memory, pair " << n;
                ASSERT_NEAR(b[c], w, 1e-5 * std::fabs(w) + 1e-7) << "texture, pair " << n;
            }
        }
    }
}

TEST(DetailLayer, SampleWeightsIncludeTheDetail) {
    NpfModel m = test_model(false, 3, false);
    add_detail(m, {6, 4, 8});
    const NpfClosure closure(m);
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> uni(0.f, 0.999f);
    int checked = 0;
    for (int n = 0; n < 2000; ++n) {
        const Vec3 wo = random_direction(rng);
        npf::ClosureSample s;
        float weight[3], value[3];
        if (!closure.sample(wo, uni(rng), uni(rng), WavelengthRequest::stored(), s, weight)) continue;
        const float pdf = closure.eval(wo, s.light, WavelengthRequest::stored(), value);
        ASSERT_EQ(pdf, s.pdf);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(weight[c], value[c] / pdf, 1e-5f * value[c] / pdf);
        ++checked;
    }
    EXPECT_GT(checked, 1500);
}

// ---- The fit -----------------------------------------------------------------------------------

// A source that is the base plus a residual the grid can hold exactly: the fit recovers it.
TEST(DetailFit, RecoversAResidualTheGridCanHold) {
    for (const bool anisotropic : {false, true}) {
        SCOPED_TRACE(anisotropic ? "anisotropic" : "isotropic");
        const NpfModel base = test_model(anisotropic, 3, false);
        NpfModel truth = base;
        const DetailGrid g{6, 4, 8};
        add_detail(truth, g);
        const npf::NpfBrdf source(truth);
        npf::DetailOptions o;
        o.grid = g;
        o.energy_weight = 0.0;  // the data alone determine it
        o.smoothness = 1e-9;
        o.half_precision = false;
        o.samples_per_cell = 3;
        o.phi_h_samples = 2;
        o.threads = 2;
        NpfModel fitted = base;
        const npf::DetailReport r = npf::fit_detail_layer(source, fitted, o);
        ASSERT_TRUE(fitted.has_detail());
        double worst = 0.0, largest = 0.0;
        for (std::size_t c = 0; c < 3; ++c) {
            for (std::size_t i = 0; i < g.cells(); ++i) {
                worst = std::max(worst, std::fabs(fitted.detail.at(c, i) - truth.detail.at(c, i)));
                largest = std::max(largest, std::fabs(truth.detail.at(c, i)));
            }
        }
        std::printf("[ figures  ] %s: worst cell error %.2e of the largest residual %.2e; weighted error %.2e -> %.2e\n",
                    anisotropic ? "anisotropic" : "isotropic", worst, largest, r.weighted_error_before,
                    r.weighted_error_after);
        // Cells whose samples all fall below the horizon are set by the smoothness term alone:
        // compare where it matters, through the data.
        EXPECT_LT(r.weighted_error_after, 1e-6 * r.weighted_error_before);
    }
}

// The energy term holds the source's directional albedo at the views (measured independently by
// npf::directional_albedo); without it the same fit leaves it further off.
TEST(DetailFit, HoldsTheSourcesAlbedo) {
    const NpfModel base = npf::compress_factors(
        npf::testing::make_microfacet_factors({0.35, 0.35, 0.05, 0.7, 3, false, 32, 1, 32, 32, 1}), {});
    const NpfModel sharper = npf::compress_factors(
        npf::testing::make_microfacet_factors({0.12, 0.12, 0.08, 1.0, 3, false, 32, 1, 32, 32, 1}), {});
    const npf::NpfBrdf source(sharper);
    const std::vector<double> views = {0, 30, 60, 75, 80};
    auto worst_albedo_error = [&](double energy_weight) {
        npf::DetailOptions o;
        o.grid = {12, 8, 12};
        o.energy_weight = energy_weight;
        o.energy_views_deg = views;
        o.threads = 2;
        NpfModel fitted = base;
        npf::fit_detail_layer(source, fitted, o);
        const npf::NpfBrdf model(fitted);
        double worst = 0.0;
        for (double v : views) {
            const double t = v * npf::kPiD / 180.0;
            const Vec3 wi(float(std::sin(t)), 0.f, float(std::cos(t)));
            const std::vector<double> a = npf::directional_albedo(model, wi, model.native_query());
            const std::vector<double> b = npf::directional_albedo(source, wi, source.native_query());
            for (std::size_t c = 0; c < a.size(); ++c) worst = std::max(worst, std::fabs(a[c] / b[c] - 1.0));
        }
        return worst;
    };
    const double held = worst_albedo_error(1e4), free = worst_albedo_error(0.0);
    std::printf("[ figures  ] worst albedo error at 0..80 degrees: %.3f %% with the energy term, %.3f %% without\n",
                100.0 * held, 100.0 * free);
    EXPECT_LT(held, 0.01);
    EXPECT_GT(free, 2.0 * held);
}

// 20 channels: more than the weight groups, so one group solved in chains that the threads share.
TEST(DetailFit, SameOnAnyThreadCount) {
    const NpfModel base = test_model(true, 20, true);
    NpfModel truth = base;
    add_detail(truth, {4, 3, 6});
    const npf::NpfBrdf source(truth);
    npf::DetailOptions o;
    o.grid = {5, 4, 6};
    o.phi_h_samples = 3;
    NpfModel one = base, two = base;
    o.threads = 1;
    npf::fit_detail_layer(source, one, o);
    o.threads = 2;
    npf::fit_detail_layer(source, two, o);
    EXPECT_EQ(one.detail.basis, two.detail.basis);
    EXPECT_EQ(one.detail.weights, two.detail.weights);
}

TEST(DetailFit, RejectsBadOptions) {
    NpfModel m = test_model(false, 3, false);
    const npf::NpfBrdf source(m);
    npf::DetailOptions o;
    o.grid = {0, 4, 4};
    EXPECT_THROW(npf::fit_detail_layer(source, m, o), npf::Error);
    o.grid = {4, 4, 4};
    o.display_power = -1.0;
    EXPECT_THROW(npf::fit_detail_layer(source, m, o), npf::Error);
    o.display_power = 0.4;
    o.energy_views_deg = {90.0};
    EXPECT_THROW(npf::fit_detail_layer(source, m, o), npf::Error);
}

// ---- Edits on detailed files (docs/editing.md, "Edits and the detail layer") -----------------

bool same_detail(const NpfModel& a, const NpfModel& b) {
    return a.detail_grid == b.detail_grid && a.detail.rank == b.detail.rank && a.detail.basis == b.detail.basis &&
           a.detail.weights == b.detail.weights;
}

bool warned_of_drop(const npf::edit::EditRecord& r) {
    for (const std::string& w : r.warnings) {
        if (w.find("detail layer was dropped") != std::string::npos) return true;
    }
    return false;
}

TEST(DetailEdits, EachKindKeepsOrDropsTheDetailAsDocumented) {
    NpfModel m = npf::compress_factors(
        npf::testing::make_microfacet_factors({0.15, 0.3, 0.1, 0.5, 3, false, 16, 24, 16, 16, 12}), {});
    add_detail(m, {6, 4, 8});
    namespace ed = npf::edit;
    struct Case {
        const char* name;
        std::function<NpfModel(ed::EditRecord*)> edit;
        bool kept;
    };
    const NpfModel other = npf::compress_factors(
        npf::testing::make_microfacet_factors({0.3, 0.3, 0.2, 0.8, 3, false, 16, 1, 16, 16, 1}), {});
    ed::ThinFilm film;
    film.thickness_nm = 350.0;
    ed::Mat3 mirror;
    mirror(1, 1) = -1.0;
    ed::AlbedoLimit cap;
    cap.cap = 0.5;
    const std::vector<Case> cases = {
        {"rotation about the normal", [&](ed::EditRecord* r) { return ed::transform_ndf(m, ed::rotation_matrix(30.0), {}, r); }, true},
        {"stretch", [&](ed::EditRecord* r) { return ed::transform_ndf(m, ed::stretch_matrix(1.5, 1.0), {}, r); }, false},
        {"roughness", [&](ed::EditRecord* r) { return ed::transform_ndf(m, ed::roughness_matrix(0.7), {}, r); }, false},
        {"mirror", [&](ed::EditRecord* r) { return ed::transform_ndf(m, mirror, {}, r); }, false},
        {"re-compression", [&](ed::EditRecord* r) { return ed::compress_model(m, npf::CompressionOptions{0.9, 0.9, 0, 0}, r); }, true},
        {"diffuse colour", [&](ed::EditRecord* r) { return ed::replace_diffuse_albedo(m, npf::color::Rgb{0.5, 0.1, 0.1}, r); }, true},
        {"diffuse from another", [&](ed::EditRecord* r) { return ed::replace_diffuse(m, other, 1.0, r); }, true},
        {"specular from another", [&](ed::EditRecord* r) { return ed::replace_specular(m, other, {}, r); }, false},
        {"thin film", [&](ed::EditRecord* r) { return ed::apply_thin_film(m, film, r); }, false},
        {"albedo cap", [&](ed::EditRecord* r) { return ed::limit_albedo(m, cap, r); }, true},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        ed::EditRecord record;
        const NpfModel out = c.edit(&record);
        if (c.kept) {
            EXPECT_TRUE(same_detail(out, m));
            EXPECT_FALSE(warned_of_drop(record));
        } else {
            EXPECT_FALSE(out.has_detail());
            EXPECT_TRUE(warned_of_drop(record)) << "a dropped layer is said in the record";
        }
    }
}

// The shipped identity recipe (every step an identity) leaves a detailed file bit for bit.
TEST(DetailEdits, IdentityRecipeIsBitExact) {
    NpfModel m = test_model(false, 3, false);
    add_detail(m, {6, 4, 8});
    const npf::edit::EditRecipe recipe = npf::edit::load_edit_recipe(std::string(NPF_SOURCE_DIR) + "/configs/edits/identity.yaml");
    const npf::edit::EditResult r = npf::edit::apply_edits(m, recipe.steps, recipe.options);
    EXPECT_TRUE(same_detail(r.model, m));
    EXPECT_EQ(r.model.D.basis, m.D.basis);
    EXPECT_EQ(r.model.G.basis, m.G.basis);
    EXPECT_EQ(r.model.F, m.F);
}

// ---- G's horizon rule ----------------------------------------------------------------------

TEST(HorizonRule, ClosingGBoundsTheAlbedoAndKeepsEveryOtherView) {
    // Microfacet factors whose G is well above 0 in its last rows: open at the horizon.
    NpfModel m = npf::compress_factors(
        npf::testing::make_microfacet_factors({0.4, 0.4, 0.05, 1.0, 3, false, 32, 1, 32, 32, 1}), {});
    ASSERT_TRUE(m.g_open_at_horizon());
    NpfModel closed = m;
    EXPECT_EQ(closed.close_g_at_horizon(), 1);
    EXPECT_FALSE(closed.g_open_at_horizon());
    EXPECT_EQ(closed.close_g_at_horizon(), 0) << "closing twice changes nothing";
    // Directions up to the centre of the row before the last (85.78 degrees on 32 rows) are
    // unchanged to the bit; the last row weighs in beyond it.
    std::mt19937 rng(3);
    const double last_centre = kHalfPi * (30.5 / 32.0);
    double a[3], b[3];
    for (int n = 0; n < 2000; ++n) {
        const Vec3 wi = random_direction(rng, std::cos(last_centre) + 1e-4), wo = random_direction(rng, std::cos(last_centre) + 1e-4);
        m.eval_all(wi, wo, a);
        closed.eval_all(wi, wo, b);
        for (int c = 0; c < 3; ++c) ASSERT_EQ(a[c], b[c]);
    }
    // Open, the albedo grows like 1 / cos(theta_view) in the last fraction of a degree (ten times
    // from 89.9 to 89.99 degrees); closed, it stays bounded.
    const npf::NpfBrdf open_brdf(m), closed_brdf(closed);
    auto albedo = [](const npf::NpfBrdf& material, double degrees) {
        const double t = degrees * npf::kPiD / 180.0;
        return npf::directional_albedo(material, Vec3(float(std::sin(t)), 0.f, float(std::cos(t))), material.native_query())[1];
    };
    const double open_growth = albedo(open_brdf, 89.99) / albedo(open_brdf, 89.9);
    const double closed_growth = albedo(closed_brdf, 89.99) / albedo(closed_brdf, 89.9);
    std::printf("[ figures  ] albedo from 89.9 to 89.99 degrees: x%.2f open, x%.3f closed\n", open_growth, closed_growth);
    EXPECT_GT(open_growth, 5.0);
    EXPECT_LT(closed_growth, 1.05);
}

}  // namespace
