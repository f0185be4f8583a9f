// The RGL writer ("virtual acquisition"): files it writes are read back by our reader (and
// by Mitsuba 3 in the opt-in cross-check) as the analytic source, exactly at the data nodes
// and closely between them; they sample correctly; anisotropy and isotropy come out right.
#include "chi2.h"
#include "synthetic_rgl.h"

#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/materials/material_recipe.h>
#include <npf/materials/piecewise_linear_2d.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/materials/rgl_writer.h>
#include <npf/materials/tensor_file.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sys/stat.h>
#include <string>

namespace {

using npf::AnalyticBrdf, npf::AnalyticMaterial, npf::Channels, npf::RglBrdf, npf::RglWriterOptions,
      npf::Vec3, npf::color::SampledSpectrum;

const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("rgl-writer");
    return dir;
}

AnalyticMaterial copper(float ax, float ay, float rotation = 0.f) {
    AnalyticMaterial m;
    m.name = "test copper";
    npf::SpecularLobe lobe;
    lobe.ndf.alpha_x = ax;
    lobe.ndf.alpha_y = ay;
    lobe.ndf.rotation = rotation;
    lobe.fresnel = npf::Fresnel::schlick(SampledSpectrum({400.0, 550.0, 700.0}, {0.5, 0.6, 0.95}));
    m.specular.push_back(lobe);
    m.diffuse = SampledSpectrum::constant(0.02);
    m.wavelengths = {400.f, 450.f, 500.f, 550.f, 600.f, 650.f, 700.f};
    return m;
}

RglWriterOptions small_grid(const Channels& channels) {
    RglWriterOptions o;
    o.channels = channels;
    o.phi_count = 9;
    o.theta_count = 6;
    o.ndf_size = 64;
    o.ndf_rows = 24;
    o.vndf_size = 48;
    o.data_size = 16;
    return o;
}

std::string write(const AnalyticBrdf& brdf, const std::string& name, RglWriterOptions o) {
    o.ndf = brdf.ndf_function();
    const std::string path = folder() + "/" + name + ".bsdf";
    npf::write_rgl(brdf, path, o);
    return path;
}

// Every data node of every slice (but the grazing theta_i = pi/2 one, where wi.z = 0 and
// readers return 0): the reader's value must equal the source's to float precision.
void expect_exact_at_nodes(const npf::Brdf& source, const std::string& path, const Channels& channels) {
    const npf::TensorFile file = npf::TensorFile::read(path);
    const std::vector<float> phi = file.to_float(file.require("phi_i"));
    const std::vector<float> theta = file.to_float(file.require("theta_i"));
    const npf::TensorField& vf = file.require("vndf");
    const npf::PiecewiseLinear2D vndf(vf.shape[3], vf.shape[2], phi.size() * theta.size(), file.to_float(vf), true, path);
    const std::size_t S = file.require("luminance").shape[3];
    const bool iso = phi.size() == 1;
    const auto reader = RglBrdf::load(path);
    const npf::ChannelQuery rq = reader->query(channels), sq = source.query(channels);
    std::vector<float> got(rq.size()), want(sq.size());
    double worst = 0.0;
    std::size_t compared = 0;
    for (std::size_t p = 0; p < phi.size(); ++p) {
        for (std::size_t t = 0; t + 1 < theta.size(); ++t) {
            const Vec3 wi = npf::spherical_direction(theta[t], phi[p]);
            npf::SliceBlend b;
            b.slice[0] = std::uint32_t(p * theta.size() + t);
            for (std::size_t r = 0; r < S; ++r) {
                for (std::size_t c = 0; c < S; ++c) {
                    const npf::Vec2 u = vndf.sample({float(c) / float(S - 1), float(r) / float(S - 1)}, b, nullptr);
                    const Vec3 wh = npf::spherical_direction(0.5f * npf::kPi * u.x * u.x,
                                                             (2.f * u.y - 1.f) * npf::kPi + (iso ? phi[p] : 0.f));
                    const Vec3 wo = wh * (2.f * npf::dot(wi, wh)) - wi;
                    // f cos(theta_o) is proportional to wo.z: near the horizon float rounding of
                    // the directions alone moves it by more than float precision.
                    if (!(wo.z > 0.02f)) continue;
                    reader->eval_cos(wi, wo, rq, got.data());
                    source.eval_cos(wi, wo, sq, want.data());
                    for (std::size_t k = 0; k < got.size(); ++k) {
                        if (want[k] < 1e-4f) continue;
                        const double e = std::fabs(double(got[k]) - want[k]) / want[k];
                        worst = std::max(worst, e);
                        ++compared;
                    }
                }
            }
        }
    }
    std::printf("[ writer   ] %s: worst relative error at %zu node values: %.2e\n", path.c_str(), compared, worst);
    EXPECT_GT(compared, 100u) << path;
    // Float32 tables and a float32 VNDF inversion: agreement to a few 1e-5 relative.
    EXPECT_LT(worst, 1e-4) << path << ": worst relative error at the data nodes over " << compared << " values";
}

// A direction with cos(theta) uniform in [min_cos, 1] and phi uniform.
Vec3 direction_above(std::mt19937& rng, float min_cos) {
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    return npf::spherical_direction(std::acos(min_cos + (1.f - min_cos) * uni(rng)), 2.f * npf::kPi * uni(rng));
}

TEST(RglWriter, IsotropicSpectralIsExactAtNodes) {
    const AnalyticBrdf brdf(copper(0.25f, 0.25f));
    const Channels ch = Channels::spectral(brdf.material().wavelengths);
    const std::string path = write(brdf, "iso_spectral", small_grid(ch));
    const auto reader = RglBrdf::load(path);
    EXPECT_TRUE(reader->info().isotropic);
    EXPECT_EQ(reader->phi_i().size(), 1u) << "isotropic inputs are written with one phi_i entry";
    expect_exact_at_nodes(brdf, path, ch);
}

TEST(RglWriter, AnisotropicRgbIsExactAtNodes) {
    const AnalyticBrdf brdf(copper(0.1f, 0.4f, 0.3f));
    const std::string path = write(brdf, "aniso_rgb", small_grid(Channels::rgb()));
    const auto reader = RglBrdf::load(path);
    EXPECT_FALSE(reader->info().isotropic);
    EXPECT_EQ(reader->phi_i().size(), 9u);
    EXPECT_EQ(reader->reduction(), 1);
    expect_exact_at_nodes(brdf, path, Channels::rgb());
}

TEST(RglWriter, PowerIterationNdfIsExactAtNodesToo) {
    // Two lobes with crossed anisotropy: no single NDF, D comes from retro-reflection.
    AnalyticMaterial m = copper(0.1f, 0.4f);
    npf::SpecularLobe second = m.specular.front();
    second.ndf.rotation = 0.5f * npf::kPi;
    second.weight = SampledSpectrum::constant(0.5);
    m.specular.push_back(second);
    const AnalyticBrdf brdf(m);
    ASSERT_EQ(brdf.single_ndf(), nullptr);
    const std::string path = write(brdf, "two_lobes", small_grid(Channels::rgb()));
    expect_exact_at_nodes(brdf, path, Channels::rgb());
}

// Between the nodes the file interpolates: measure the error over random directions and
// check it is small for a smooth material at the small test grid.
TEST(RglWriter, BetweenNodesErrorIsSmall) {
    const AnalyticBrdf brdf(copper(0.3f, 0.3f));
    const std::string path = write(brdf, "between", small_grid(Channels::rgb()));
    const auto reader = RglBrdf::load(path);
    const npf::ChannelQuery rq = reader->query(Channels::rgb()), sq = brdf.query(Channels::rgb());
    std::mt19937 rng(5);
    double sum_sq = 0.0, sum_ref = 0.0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 wi = direction_above(rng, 0.2f);
        const Vec3 wo = direction_above(rng, 0.2f);
        float a[3], b[3];
        reader->eval_cos(wi, wo, rq, a);
        brdf.eval_cos(wi, wo, sq, b);
        sum_sq += (a[1] - b[1]) * (a[1] - b[1]);
        sum_ref += b[1] * b[1];
    }
    const double relative_rms = std::sqrt(sum_sq / sum_ref);
    RecordProperty("relative_rms", std::to_string(relative_rms));
    EXPECT_LT(relative_rms, 0.05) << "relative RMS error between nodes (below 78 degrees)";
}

// Rotating the material's tangent frame by 90 degrees swaps the highlight axes in the file.
TEST(RglWriter, RotatingTheFrameSwapsTheHighlightAxes) {
    const AnalyticBrdf along_x(copper(0.08f, 0.35f, 0.f));
    const AnalyticBrdf along_y(copper(0.08f, 0.35f, 0.5f * npf::kPi));
    const auto a = RglBrdf::load(write(along_x, "frame0", small_grid(Channels::rgb())));
    const auto b = RglBrdf::load(write(along_y, "frame90", small_grid(Channels::rgb())));
    const npf::ChannelQuery q = a->query(Channels::rgb());
    auto value = [&](const RglBrdf& r, const Vec3& wi, const Vec3& wo) {
        float v[3];
        r.eval_cos(wi, wo, q, v);
        return v[1];
    };
    // Off-specular along x vs along y: the narrow axis (alpha 0.08) falls off fast.
    const Vec3 wi = npf::spherical_direction(0.5f, 0.f);
    const Vec3 mirror(-wi.x, -wi.y, wi.z);
    const Vec3 off_x = npf::normalize(mirror + Vec3(-0.15f, 0.f, 0.f));
    const Vec3 off_y = npf::normalize(mirror + Vec3(0.f, 0.15f, 0.f));
    EXPECT_LT(value(*a, wi, off_x), 0.5f * value(*a, wi, off_y)) << "alpha_x = 0.08: narrow along x";
    EXPECT_GT(value(*b, wi, off_x), 2.0f * value(*b, wi, off_y)) << "rotated by 90 degrees: narrow along y";
    // And the rotated file is the first one turned by 90 degrees, up to the interpolation
    // error between nodes (the warps' CDFs start at phi = -pi, so the data nodes of the two
    // files do not map onto each other).
    auto turn = [](const Vec3& w) { return Vec3(-w.y, w.x, w.z); };
    std::mt19937 rng(9);
    double diff = 0.0, ref = 0.0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 p = direction_above(rng, 0.3f);
        const Vec3 o = direction_above(rng, 0.3f);
        const double x = value(*a, p, o), y = value(*b, turn(p), turn(o));
        diff += (y - x) * (y - x);
        ref += x * x;
    }
    EXPECT_LT(std::sqrt(diff / ref), 0.05) << "relative RMS difference of the turned file";
}

TEST(RglWriter, IsotropyIsDetected) {
    EXPECT_TRUE(npf::looks_isotropic(AnalyticBrdf(copper(0.2f, 0.2f))));
    EXPECT_FALSE(npf::looks_isotropic(AnalyticBrdf(copper(0.1f, 0.3f))));
    RglWriterOptions o = small_grid(Channels::rgb());
    o.anisotropy = npf::AnisotropyMode::Auto;
    const npf::RglWriteReport r = npf::write_rgl(AnalyticBrdf(copper(0.2f, 0.2f)), folder() + "/auto_iso.bsdf", o);
    EXPECT_TRUE(r.isotropic);
    EXPECT_EQ(r.phi_i.size(), 1u);
}

TEST(RglWriter, WrittenFilesSample) {
    const AnalyticBrdf brdf(copper(0.12f, 0.3f, 0.2f));
    const auto reader = RglBrdf::load(write(brdf, "sampling", small_grid(Channels::spectral({450.f, 550.f, 650.f}))));
    for (const Vec3& wi : {npf::spherical_direction(0.f, 0.f), npf::spherical_direction(0.7f, 2.f),
                           npf::spherical_direction(1.3f, -1.f)}) {
        npf::testing::Chi2Options opt;
        opt.sample_count = 300000;
        opt.trials = 3;
        const npf::testing::Chi2Result r = npf::testing::run_chi2_test(*reader, wi, opt);
        EXPECT_TRUE(r.passed) << r.message;
    }
}

TEST(RglWriter, BadOptionsAndChannelsAreErrors) {
    const AnalyticBrdf brdf(copper(0.2f, 0.2f));
    RglWriterOptions o = small_grid(Channels::rgb());
    o.data_size = 1;
    EXPECT_THROW(npf::write_rgl(brdf, folder() + "/bad.bsdf", o), npf::Error);
    o = small_grid(Channels::spectral({500.f, 400.f}));
    EXPECT_THROW(npf::write_rgl(brdf, folder() + "/bad.bsdf", o), npf::Error);
    // An RGB source cannot be written as spectral.
    const std::string rgb_path = write(brdf, "rgb_source", small_grid(Channels::rgb()));
    const auto rgb = RglBrdf::load(rgb_path);
    EXPECT_THROW(npf::write_rgl(*rgb, folder() + "/bad.bsdf", small_grid(Channels::spectral({500.f}))), npf::Error);
    struct stat st;
    EXPECT_NE(::stat((folder() + "/bad.bsdf").c_str(), &st), 0) << "no output on failure";
}

TEST(RglWriter, ConvertsAMeasuredFileToo) {
    // Any source: a real measured file re-acquired at a smaller grid reads back close to it.
    const std::string real = npf::testing::shared_data_file("rgl/paper_white_rgb.bsdf");
    if (real.empty()) GTEST_SKIP() << "rgl/paper_white_rgb.bsdf not found in the shared data folder";
    const auto source = RglBrdf::load(real);
    RglWriterOptions o = small_grid(Channels::rgb());
    o.power_iterations = 8;
    const std::string path = folder() + "/paper_again.bsdf";
    npf::write_rgl(*source, path, o);
    expect_exact_at_nodes(*source, path, Channels::rgb());
}

}  // namespace

// Every shipped recipe, written at a reduced grid, samples as its pdf says (the failure case
// and the thin film included).
class RglWriterRecipes : public ::testing::TestWithParam<std::string> {};

TEST_P(RglWriterRecipes, WrittenFileSamples) {
    const std::string recipe_path = std::string(NPF_SOURCE_DIR) + "/configs/materials/" + GetParam() + ".yaml";
    npf::MaterialRecipe recipe = npf::load_material_recipe(recipe_path);
    const AnalyticBrdf brdf(recipe.material);
    RglWriterOptions o = recipe.writer;
    o.channels = Channels::rgb();
    o.phi_count = 9;
    o.theta_count = 6;
    o.ndf_rows = 24;
    o.vndf_size = 48;
    o.data_size = 16;
    const auto reader = RglBrdf::load(write(brdf, "recipe_" + GetParam(), o));
    for (const Vec3& wi : {npf::spherical_direction(0.3f, 0.4f), npf::spherical_direction(1.1f, 2.5f)}) {
        npf::testing::Chi2Options opt;
        opt.sample_count = 200000;
        opt.trials = 2;
        const npf::testing::Chi2Result r = npf::testing::run_chi2_test(*reader, wi, opt);
        EXPECT_TRUE(r.passed) << GetParam() << ": " << r.message;
    }
}

INSTANTIATE_TEST_SUITE_P(Shipped, RglWriterRecipes,
                         ::testing::Values("brushed_copper", "satin_fabric", "red_plastic", "thin_film_aluminium",
                                           "crossed_lobes_failure"));
