// The RGL reader on valid synthetic files of every kind: they load and describe themselves
// correctly, with optional and unknown fields accepted.

#include "rgl_bad_input.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/core/error.h>
#include <npf/materials/open_material.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/materials/tensor_file.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <sys/stat.h>

namespace {

using namespace npf::testing::rgl_bad_input;
using npf::DType, npf::RglBrdf, npf::testing::contains, npf::testing::remove_field,
      npf::testing::synthetic_rgl_fields, npf::testing::SyntheticField, npf::testing::SyntheticRglSpec;

// ---- Valid files of every kind ------------------------------------------------------------

struct ValidKind {
    const char* name;
    int phi_count;
    int reduction;
    bool spectral;
    bool jacobian;
};

const ValidKind kValidKinds[] = {
    {"iso_rgb", 1, 1, false, true},          {"iso2_rgb", 2, 1, false, true},
    {"iso_spectral", 1, 1, true, true},      {"aniso1_rgb", 5, 1, false, true},
    {"aniso2_rgb", 5, 2, false, true},       {"aniso4_rgb", 4, 4, false, true},
    {"aniso1_spectral", 5, 1, true, true},   {"aniso2_spectral", 3, 2, true, true},
    {"aniso4_spectral", 5, 4, true, true},   {"iso_rgb_jacobian0", 1, 1, false, false},
    {"aniso2_spectral_jacobian0", 5, 2, true, false},
};

TEST(RglBadInputValidFiles, EveryKindLoadsAndDescribesItself) {
    for (const ValidKind& k : kValidKinds) {
        SCOPED_TRACE(k.name);
        SyntheticRglSpec s = small_spec(k.spectral);
        s.phi_count = k.phi_count;
        s.reduction = k.reduction;
        s.jacobian = k.jacobian;
        s.alpha_x = 0.2f;
        s.alpha_y = 0.45f;
        s.wavelengths = {380.f, 455.5f, 600.f, 780.f, 830.f};
        s.description = std::string("valid ") + k.name;
        const std::string path = npf::testing::write_synthetic_rgl(s, folder() + "/valid_" + k.name + ".bsdf");
        const bool isotropic = k.phi_count <= 2;

        std::unique_ptr<RglBrdf> rgl;
        ASSERT_NO_THROW(rgl = RglBrdf::load(path));
        std::unique_ptr<npf::Brdf> any;
        ASSERT_NO_THROW(any = npf::open_material(path));
        EXPECT_EQ(rgl->reduction(), isotropic ? 1 : k.reduction);
        EXPECT_EQ(rgl->jacobian(), k.jacobian);
        EXPECT_EQ(rgl->phi_i().size(), std::size_t(k.phi_count));
        EXPECT_EQ(rgl->theta_i().size(), std::size_t(s.theta_count));
        for (const npf::BrdfInfo* info : {&rgl->info(), &any->info()}) {
            EXPECT_EQ(info->format, "rgl");
            EXPECT_EQ(info->path, path);
            EXPECT_EQ(info->description, s.description);
            EXPECT_EQ(info->isotropic, isotropic);
            EXPECT_EQ(info->file_bytes, file_size(path));
            EXPECT_EQ(info->channels.is_rgb(), !k.spectral);
            if (k.spectral) {
                EXPECT_EQ(info->channels.wavelengths(), s.wavelengths);
            } else {
                EXPECT_EQ(info->channels.size(), 3u);
            }
            bool found = false;
            for (const auto& [key, value] : info->details) {
                if (key != "phi_i reduction") continue;
                found = true;
                EXPECT_EQ(value, std::to_string(k.reduction) + " (phi_i covers 2 pi / " + std::to_string(k.reduction) + ")");
            }
            EXPECT_EQ(found, !isotropic) << "'phi_i reduction' detail is for anisotropic files only";
        }

        // Evaluation, pdf and sampling give finite, non-negative results over the hemisphere.
        const npf::ChannelQuery q = rgl->native_query();
        std::vector<float> out(q.size()), weight(q.size());
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> uni(0.f, 1.f);
        int positive = 0;
        for (int i = 0; i < 200; ++i) {
            const npf::Vec3 wi = npf::spherical_direction(0.5f * npf::kPi * uni(rng), 2.f * npf::kPi * uni(rng));
            const npf::Vec3 wo = npf::spherical_direction(0.5f * npf::kPi * uni(rng), 2.f * npf::kPi * uni(rng));
            rgl->eval_cos(wi, wo, q, out.data());
            for (float v : out) {
                ASSERT_TRUE(std::isfinite(v) && v >= 0.f) << v;
                positive += v > 0.f;
            }
            const float p = rgl->pdf(wi, wo);
            ASSERT_TRUE(std::isfinite(p) && p >= 0.f) << p;
            npf::BrdfSample smp;
            if (rgl->sample(wi, {uni(rng), uni(rng)}, q, smp, weight.data())) {
                ASSERT_GT(smp.wo.z, 0.f);
                ASSERT_TRUE(std::isfinite(smp.pdf) && smp.pdf > 0.f);
                for (float w : weight) ASSERT_TRUE(std::isfinite(w) && w >= 0.f);
            }
        }
        EXPECT_GT(positive, 100);
    }
}

TEST(RglBadInputValidFiles, OptionalFieldsAndUnknownFields) {
    Fields f = synthetic_rgl_fields(small_spec());
    ASSERT_TRUE(remove_field(f, "jacobian"));
    ASSERT_TRUE(remove_field(f, "description"));
    SyntheticField valid;
    valid.name = "valid";
    valid.dtype = DType::U8;
    valid.shape = {6};  // 1 * 3 * 4 * 4 nodes = 48 bits
    valid.bytes = {0xff, 0xff, 0x0f, 0xff, 0x00, 0x01};
    f.push_back(valid);
    SyntheticField unknown;
    unknown.name = "some_future_field";
    unknown.dtype = DType::I64;
    unknown.shape = {2, 1};
    unknown.bytes.assign(16, 0xab);
    f.insert(f.begin(), unknown);
    const std::string path = write_fields("optional.bsdf", f);
    std::unique_ptr<RglBrdf> b;
    ASSERT_NO_THROW(b = RglBrdf::load(path));
    EXPECT_TRUE(b->jacobian());
    EXPECT_EQ(b->info().description, "");
    bool saw_valid = false, saw_jacobian = false;
    for (const auto& [key, value] : b->info().details) {
        if (key == "valid mask") {
            saw_valid = true;
            EXPECT_EQ(value, "29 of 48 bits set (not used by evaluation)");
        }
        if (key == "jacobian") {
            saw_jacobian = true;
            EXPECT_TRUE(contains(value, "absent")) << value;
        }
    }
    EXPECT_TRUE(saw_valid);
    EXPECT_TRUE(saw_jacobian);
    EXPECT_NO_THROW(npf::open_material(path));
}

}  // namespace
