// A fitted NPF material behind the common npf::Brdf interface, from an NpfModel in memory or an
// NPF factor texture (docs/format.md): an NpfClosure (either path) seen through npf::Brdf's
// conventions (wi conditioned, values f_r cos theta_o). Spectral models answer any wavelengths
// (linear between the stored ones, constant outside), RGB models answer RGB, as the measured
// readers do.
#pragma once

#include <npf/core/brdf.h>
#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_model.h>

#include <memory>
#include <string>

namespace npf {

class NpfBrdf final : public Brdf {
public:
    // Throws npf::Error when the model is inconsistent (NpfModel::validate).
    explicit NpfBrdf(NpfModel model);
    // Reads an NPF factor texture; throws npf::Error naming the file (read_npf_texture). The
    // texture path shades through `ts` (a private TextureSystem when null).
    explicit NpfBrdf(const std::string& path, NpfClosure::Path path_kind = NpfClosure::Path::Memory,
                     OIIO::TextureSystem* ts = nullptr);

    const BrdfInfo& info() const override { return m_info; }
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const override;
    // The closure's sampler: the half vector from the luminance-averaged D (alias table) mixed
    // with cosine sampling for the diffuse term.
    float pdf(const Vec3& wi, const Vec3& wo) const override;
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override;
    // On the memory path: npf_directional_albedo on the model's tables.
    bool albedo_by_quadrature(const Vec3& wi, const ChannelQuery& query, std::vector<double>& albedo) const override;

    // Complete on the memory path; without D and G tables on the texture path.
    const NpfModel& model() const { return m_closure->model(); }
    const NpfClosure& closure() const { return *m_closure; }

private:
    NpfBrdf(std::unique_ptr<NpfClosure> closure, const std::string& path, std::uint64_t file_bytes);

    std::unique_ptr<NpfClosure> m_closure;
    BrdfInfo m_info;
};

}  // namespace npf
