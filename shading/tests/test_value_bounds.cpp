// What a material can produce, not only what it stores (issue 33, classes 5 and 6): every reader
// bounds f_r cos(theta_i) cos(theta_o) from its tables' products and refuses a material above
// kMaxMaterialValue; the bound holds at any pair; no output of an accepted material is Inf, NaN
// or silently 0; a conversion that would drop values fails.
#include "error_of.h"
#include "npf_test_factors.h"
#include "raw_exr.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/converter/convert.h>
#include <npf/fit/spectral_compression.h>
#include <npf/materials/open_material.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/core/brdf.h>
#include <npf/core/error.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/shading/npf_texture_layout.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using npf::testing::contains, npf::testing::error_of, npf::testing::describe, npf::testing::RawPart,
      npf::testing::run_tool, npf::testing::ToolRun;

const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("value-bounds");
    return dir;
}

std::string file(const std::string& name) { return folder() + "/" + name; }

npf::NpfModel small_model(bool spectral) {
    npf::testing::TestFactorSpec kind;
    kind.anisotropic = true;
    kind.spectral = spectral;
    kind.channels = spectral ? 12 : 3;
    npf::NpfModel m = npf::compress_factors(npf::testing::make_test_factors(kind), {});
    m.metadata = {{"description", "value bound test"}};
    return m;
}


// Every table value set to 9e11 (each under the 1e12 cap) and no checksum to give it away:
// the review's texture, whose products reach 6e59.
std::string every_table_at(float value) {
    const std::string valid = file("valid.exr");
    npf::write_npf_texture(small_model(false), valid);
    std::vector<RawPart> parts = npf::testing::read_raw(valid);
    for (RawPart& p : parts) {
        p.spec.erase_attribute(npf::npf_exr::kAttrTablesChecksum);
        const std::string name = p.spec.get_string_attribute("oiio:subimagename");
        const int keep = name == npf::npf_exr::kPartSpectral ? p.spec.channelindex("wavelength") : -1;
        const std::size_t nc = std::size_t(p.spec.nchannels);
        for (std::size_t i = 0; i < p.pixels.size(); ++i)
            if (int(i % nc) != keep) p.pixels[i] = value;
    }
    const std::string path = file("every_table_9e11.exr");
    npf::testing::write_raw(path, parts);
    return path;
}

TEST(ValueBounds, ATextureOfTablesEachUnderTheCapIsRefusedByTheirProduct) {
    const std::string path = every_table_at(9e11f);
    const std::string e = error_of([&] { npf::read_npf_texture(path); });
    EXPECT_TRUE(contains(e, path + ": its tables can give f_r cos(theta_i) cos(theta_o) up to")) << e;
    EXPECT_TRUE(contains(e, "above the 1e12 a material may reach")) << e;
    // Every command that opens it says so and exits 1: nothing is written, printed or shaded.
    const std::string probe = std::string(NPF_SOURCE_DIR) + "/data/materials/probe_dirs.txt";
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"info", "--check", path}, {"eval", path, "--dirs", probe}, {"eval", path, "--path", "texture", "--dirs", probe},
          {"render", path, "-o", file("r.exr"), "--size", "8", "--spp", "1"}, {"albedo", path},
          {"convert", path, "-o", file("c.exr"), "--preset", "preview"}, {"edit", path, "-o", file("e.exr"), "--limit-albedo", "1"}}) {
        const ToolRun run = run_tool(args);
        EXPECT_EQ(run.status, 1) << describe(run);
        EXPECT_TRUE(contains(run.err + run.out, "its tables can give")) << describe(run);
    }
    EXPECT_FALSE(std::filesystem::exists(file("r.exr")) || std::filesystem::exists(file("c.exr")) ||
                 std::filesystem::exists(file("e.exr")));
}

// The bound is an upper bound: f_r cos_i cos_o at many random pairs never exceeds it.
void expect_bounded(const npf::Brdf& b, const std::string& what) {
    const double bound = b.info().value_bound;
    ASSERT_GT(bound, 0.0) << what;
    const npf::ChannelQuery q = b.native_query();
    std::vector<float> out(q.size());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const auto direction = [&] {
        const float z = u(rng), phi = 6.2831853f * u(rng), r = std::sqrt(std::max(0.f, 1.f - z * z));
        return npf::Vec3(r * std::cos(phi), r * std::sin(phi), z);
    };
    double largest = 0.0;
    for (int i = 0; i < 20000; ++i) {
        npf::Vec3 wi = direction(), wo = direction();
        if (i % 4 == 0) wo = npf::Vec3(-wi.x, -wi.y, wi.z);  // the mirror pair: where peaks are
        b.eval_cos(wi, wo, q, out.data());
        for (float v : out) {
            ASSERT_TRUE(std::isfinite(v)) << what;
            largest = std::max(largest, double(v) * double(wi.z));
        }
    }
    EXPECT_LE(largest, bound * (1.0 + 1e-6)) << what;
    EXPECT_GT(largest, 0.0) << what;
}

TEST(ValueBounds, TheBoundHoldsAtRandomPairsOfEveryKindOfSource) {
    for (const char* recipe : {"brushed_copper", "red_plastic", "satin_fabric", "thin_film_aluminium", "crossed_lobes_failure"}) {
        const std::string path = std::string(NPF_SOURCE_DIR) + "/configs/materials/" + recipe + ".yaml";
        expect_bounded(*npf::open_material(path), path);
    }
    for (bool jacobian : {true, false}) {
        npf::testing::SyntheticRglSpec s;
        s.jacobian = jacobian;
        s.phi_count = 5;
        const std::string path = npf::testing::write_synthetic_rgl(s, file(jacobian ? "j1.bsdf" : "j0.bsdf"));
        expect_bounded(*npf::open_material(path), path);
    }
    for (bool spectral : {false, true}) {
        const std::string path = file(spectral ? "spectral.exr" : "rgb.exr");
        npf::write_npf_texture(small_model(spectral), path);
        expect_bounded(*npf::open_material(path), path);
        expect_bounded(npf::NpfBrdf(path, npf::NpfClosure::Path::Texture), path + " (texture path)");
    }
    const std::string ilm = npf::testing::shared_data_file("rgl/ilm_l3_37_metallic_rgb.bsdf");
    if (!ilm.empty()) expect_bounded(*npf::open_material(ilm), ilm);
}

// RGL: f_r cos_o = data x ndf / (4 sigma), so a tiny projected area is as absurd as a huge value.
TEST(ValueBounds, AnRglFileWhoseProjectedAreaIsTinyIsRefused) {
    std::vector<npf::testing::SyntheticField> fields = npf::testing::synthetic_rgl_fields({});
    npf::testing::SyntheticField* sigma = npf::testing::find_field(fields, "sigma");
    std::vector<float> v = sigma->floats();
    v[3] = 1e-40f;
    sigma->set_floats(v);
    const std::string path = file("sigma.bsdf");
    npf::testing::to_writer(fields).write(path);
    const std::string e = error_of([&] { npf::RglBrdf::load(path); });
    EXPECT_TRUE(contains(e, path + ": its tables can give")) << e;
    EXPECT_TRUE(contains(e, "sigma down to")) << e;
}

TEST(ValueBounds, AnalyticRecipesAreBoundedByTheirLobesPeaks) {
    npf::AnalyticMaterial m;
    m.name = "needle.yaml";
    m.specular.push_back({});
    m.specular[0].ndf.alpha_x = m.specular[0].ndf.alpha_y = 1e-4f;
    m.specular[0].weight = npf::color::SampledSpectrum::constant(1e6);  // peak 8e12
    const std::string e = error_of([&] { npf::AnalyticBrdf b(m); });
    EXPECT_TRUE(contains(e, "needle.yaml: its tables can give")) << e;
    m.specular[0].weight = npf::color::SampledSpectrum::constant(1.0);  // peak 8e6: a near-mirror
    EXPECT_NEAR(npf::AnalyticBrdf(m).info().value_bound, 1.0 / (4.0 * 3.14159265358979 * 1e-8), 1e3);
}

// A source that gives NaN at some pairs: the fit would give them no weight; the conversion fails
// naming the material instead of writing a file that silently lacks them.
class PartlyNan final : public npf::Brdf {
public:
    explicit PartlyNan(std::unique_ptr<npf::Brdf> inner) : m_inner(std::move(inner)) {
        m_info = m_inner->info();
        m_info.path = "partly_nan.bsdf";
    }
    const npf::BrdfInfo& info() const override { return m_info; }
    void eval_cos(const npf::Vec3& wi, const npf::Vec3& wo, const npf::ChannelQuery& q, float* out) const override {
        m_inner->eval_cos(wi, wo, q, out);
        if (wi.z < 0.3f) out[0] = std::numeric_limits<float>::quiet_NaN();
    }
    float pdf(const npf::Vec3& wi, const npf::Vec3& wo) const override { return m_inner->pdf(wi, wo); }
    bool sample(const npf::Vec3& wi, const npf::Vec2& u, const npf::ChannelQuery& q, npf::BrdfSample& s, float* w) const override {
        return m_inner->sample(wi, u, q, s, w);
    }
    npf::ChannelQuery query(const npf::Channels& c) const override { return m_inner->query(c); }

private:
    std::unique_ptr<npf::Brdf> m_inner;
    npf::BrdfInfo m_info;
};

TEST(ValueBounds, AConversionThatWouldDropValuesFails) {
    const PartlyNan source(npf::open_material(std::string(NPF_SOURCE_DIR) + "/configs/materials/red_plastic.yaml"));
    npf::ConvertSettings s = npf::preset_settings(npf::ConvertPreset::Preview, true);
    s.predict_psnr = false;
    const std::string out = file("dropped.exr");
    const std::string e = error_of([&] { npf::convert_material(source, out, s); });
    EXPECT_TRUE(contains(e, "partly_nan.bsdf: ")) << e;
    EXPECT_TRUE(contains(e, "source values at the fit's samples are not finite (NaN or infinite): the conversion would drop them")) << e;
    EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
