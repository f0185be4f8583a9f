// Analytic materials behind the common BRDF interface, evaluated at any wavelengths or as
// RGB: sums of anisotropic microfacet specular lobes (each with its own NDF, frame rotation,
// Fresnel and spectral weight), a Lambertian diffuse term, and two non-microfacet lobes
// (retro-reflection, sheen) for materials the NPF model cannot represent.
//
// f_r(wi, wo, lambda) = rho_d(lambda) / pi
//                     + sum_lobes w(lambda) D(h) F(wi.h, lambda) G1(wi, h) G1(wo, h) / (4 cos_i cos_o)
//                     + retro(lambda) (n + 1) / (2 pi) max(0, wi.wo)^n
//                     + sheen(lambda) (1 - |wi.h|)^5 ... (see analytic_brdf.cpp)
// The diffuse term is added without a (1 - F) factor on purpose: the material then lies
// exactly in the NPF model's family (rho_d + rho_s D F G G / cos cos) when it has one lobe,
// which is what the fitter's exactness tests need.
#pragma once

#include <npf/color/spectrum.h>
#include <npf/converter/analytic/fresnel.h>
#include <npf/converter/analytic/microfacet.h>
#include <npf/core/brdf.h>

#include <array>
#include <string>
#include <vector>

namespace npf {

struct SpecularLobe {
    MicrofacetNdf ndf;
    Fresnel fresnel = Fresnel::one();
    color::SampledSpectrum weight = color::SampledSpectrum::constant(1.0);
};

struct AnalyticMaterial {
    std::string name = "analytic";
    std::vector<SpecularLobe> specular;
    color::SampledSpectrum diffuse;           // rho_d (albedo of the Lambertian term); empty: none
    color::SampledSpectrum retroreflection;   // weight of the retro-reflective lobe; empty: none
    float retro_exponent = 20.f;
    color::SampledSpectrum sheen;             // weight of the sheen lobe; empty: none
    // The wavelengths this material reports as its own (info().channels), e.g. for writers
    // that keep "all" of them: 195 samples over 360..1000 nm by default, like the database.
    std::vector<float> wavelengths;
};

class AnalyticBrdf final : public Brdf {
public:
    explicit AnalyticBrdf(AnalyticMaterial material);

    const BrdfInfo& info() const override { return m_info; }
    // Accepts RGB (linear sRGB, convention of npf/color/spectrum.h) and any wavelengths.
    ChannelQuery query(const Channels& requested) const override;
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const override;
    float pdf(const Vec3& wi, const Vec3& wo) const override;
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override;

    const AnalyticMaterial& material() const { return m_material; }
    // The NDF of a material with exactly one specular lobe (for writers that tabulate it), or
    // nullptr.
    const MicrofacetNdf* single_ndf() const;

private:
    AnalyticMaterial m_material;
    BrdfInfo m_info;
    std::vector<float> m_rgb_wavelengths;          // spectral grid for RGB evaluation
    std::array<std::vector<double>, 3> m_rgb_weights;
    std::vector<float> m_lobe_probability;         // sampling mixture: specular lobes..., diffuse, retro, sheen
};

}  // namespace npf
