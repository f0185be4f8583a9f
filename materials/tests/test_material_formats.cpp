// Material formats as a registry (issue 36): a new format is one MaterialFormat and one
// registration; open_material finds it by its content and its description joins the message
// for files no format claims.
#include "synthetic_rgl.h"

#include <npf/materials/material_formats.h>
#include <npf/materials/open_material.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>

namespace {

// A toy format: a text file starting with "GREY " and a reflectance, a Lambertian material.
class GreyBrdf : public npf::Brdf {
public:
    GreyBrdf(const std::string& path, float albedo) : m_albedo(albedo) {
        m_info.path = path;
        m_info.format = "grey text";
        m_info.channels = npf::Channels::rgb();
        m_info.value_bound = albedo;
    }
    const npf::BrdfInfo& info() const override { return m_info; }
    void eval_cos(const npf::Vec3& wi, const npf::Vec3& wo, const npf::ChannelQuery& query, float* out) const override {
        for (std::size_t c = 0; c < query.size(); ++c) out[c] = wi.z > 0 && wo.z > 0 ? m_albedo * wo.z / kPi : 0.f;
    }
    float pdf(const npf::Vec3&, const npf::Vec3& wo) const override { return wo.z > 0 ? wo.z / kPi : 0.f; }
    bool sample(const npf::Vec3&, const npf::Vec2&, const npf::ChannelQuery&, npf::BrdfSample&, float*) const override {
        return false;
    }

private:
    static constexpr float kPi = 3.14159265f;
    npf::BrdfInfo m_info;
    float m_albedo;
};

TEST(MaterialFormats, ANewFormatIsOneDefinitionAndOneRegistration) {
    const std::string dir = npf::testing::temporary_folder("material-formats");
    std::ofstream(dir + "/wall.grey") << "GREY 0.5\n";
    std::ofstream(dir + "/noise.bin") << "nothing anyone reads";
    // Before: nobody claims it, and the message lists the shipped formats.
    try {
        npf::open_material(dir + "/wall.grey");
        ADD_FAILURE() << "opened a format nobody registered";
    } catch (const npf::Error& e) {
        EXPECT_EQ(e.problem(), "unknown material format (not an RGL tensor_file, a MERL .binary, an NPF texture .exr or a "
                               "Neural BRDF .h5)");
    }

    npf::MaterialFormat grey;
    grey.described_as = "a grey text file";
    grey.claims_file = [](const npf::MaterialFileHead& h) { return h.count >= 5 && std::memcmp(h.bytes, "GREY ", 5) == 0; };
    grey.open = [](const std::string& path) -> std::unique_ptr<npf::Brdf> {
        std::ifstream in(path);
        std::string tag;
        float albedo = 0.f;
        in >> tag >> albedo;
        return std::make_unique<GreyBrdf>(path, albedo);
    };
    npf::register_material_format(grey);

    const std::unique_ptr<npf::Brdf> wall = npf::open_material(dir + "/wall.grey");
    EXPECT_EQ(wall->info().format, "grey text");
    float f[3] = {};
    wall->eval_cos(npf::Vec3(0, 0, 1), npf::Vec3(0, 0, 1), wall->native_query(), f);
    EXPECT_NEAR(f[1], 0.5f / 3.14159265f, 1e-7f);
    try {
        npf::open_material(dir + "/noise.bin");
        ADD_FAILURE() << "opened noise";
    } catch (const npf::Error& e) {
        EXPECT_NE(e.problem().find(", a Neural BRDF .h5 or a grey text file)"), std::string::npos) << e.problem();
    }
}

}  // namespace
