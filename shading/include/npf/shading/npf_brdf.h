// A fitted NPF material behind the common npf::Brdf interface, from an NpfModel in memory or an
// NPF factor texture (docs/format.md). Spectral models answer any wavelengths (linear between
// the stored ones, constant outside), RGB models answer RGB, as the measured readers do.
#pragma once

#include <npf/core/brdf.h>
#include <npf/shading/npf_model.h>

#include <string>

namespace npf {

class NpfBrdf final : public Brdf {
public:
    // Throws npf::Error when the model is inconsistent (NpfModel::validate).
    explicit NpfBrdf(NpfModel model);
    // Reads an NPF factor texture; throws npf::Error naming the file (read_npf_texture).
    explicit NpfBrdf(const std::string& path);

    const BrdfInfo& info() const override { return m_info; }
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const override;
    // Cosine-weighted hemisphere sampling of wo for now. The paper's sampler (sec. 3.5: the half
    // vector drawn from the luminance-averaged D through an alias table) comes with the shading
    // work of issue 5; pdf and sample stay consistent with each other either way.
    float pdf(const Vec3& wi, const Vec3& wo) const override;
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override;

    const NpfModel& model() const { return m_model; }

private:
    NpfBrdf(NpfModel model, const std::string& path, std::uint64_t file_bytes);

    NpfModel m_model;
    BrdfInfo m_info;
};

}  // namespace npf
