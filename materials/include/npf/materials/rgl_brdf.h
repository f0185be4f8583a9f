// Measured materials of the RGL database (`*.bsdf`, Dupuy & Jakob 2018): isotropic and
// anisotropic (phi_i reductions 1, 2 and 4), RGB and spectral, with or without the Jacobian
// factor, evaluated, sampled and pdf'd exactly as the reference readers do
// (docs/rgl-format.md, secs. 5 to 8). The direction work (VNDF inversion, parameter blends)
// is done once per direction pair and shared by every requested channel.
#pragma once

#include <npf/materials/piecewise_linear_2d.h>
#include <npf/materials/tensor_file.h>
#include <npf/core/brdf.h>

#include <memory>
#include <string>
#include <vector>

namespace npf {

class RglBrdf final : public Brdf {
public:
    // Throws npf::Error naming the file and the problem.
    static std::unique_ptr<RglBrdf> load(const std::string& path);
    static std::unique_ptr<RglBrdf> from_tensor_file(const TensorFile& file);

    const BrdfInfo& info() const override { return m_info; }
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query,
                  float* out) const override;
    float pdf(const Vec3& wi, const Vec3& wo) const override;
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override;

    // 1 for full-circle anisotropic and for isotropic files, 2 or 4 for folded ones.
    int reduction() const { return m_reduction; }
    bool jacobian() const { return m_jacobian; }
    const std::vector<float>& phi_i() const { return m_phi_i; }
    const std::vector<float>& theta_i() const { return m_theta_i; }

private:
    RglBrdf() = default;

    // Everything about (wi, wh) that does not depend on the channel.
    struct DirectionState;
    bool prepare(Vec3 wi, Vec3 wo, DirectionState& st) const;
    void eval_data(const DirectionState& st, const ChannelQuery& query, float* out) const;

    BrdfInfo m_info;
    bool m_isotropic = true;
    bool m_jacobian = true;
    int m_reduction = 1;
    std::vector<float> m_phi_i, m_theta_i;
    std::size_t m_channel_count = 0;          // 3 for RGB, nL for spectral
    std::size_t m_data_width = 0, m_data_height = 0;
    std::vector<float> m_data;                // [nP][nT][H][W][channels], the ratio R
    PiecewiseLinear2D m_ndf, m_sigma, m_vndf, m_luminance;
};

}  // namespace npf
