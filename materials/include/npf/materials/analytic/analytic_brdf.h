// Analytic materials behind the common BRDF interface, evaluated at any wavelengths or as
// RGB: sums of anisotropic microfacet specular lobes (each with its own NDF, frame rotation,
// Fresnel and spectral weight), a Lambertian diffuse term, and two non-microfacet lobes
// (retro-reflection, sheen) for materials the NPF model cannot represent.
//
// f_r(wi, wo, lambda) = rho_d(lambda) / pi
//                     + sum_lobes w(lambda) D(h) F(wi.h, lambda) G1(wi, h) G1(wo, h) / (4 cos_i cos_o)
//                     + retro(lambda) (n + 1) / (2 pi) max(0, wi.wo)^n
//                     + sheen(lambda) D_s(h) / (4 (cos_i + cos_o - cos_i cos_o))
// with h = normalize(wi + wo), G1 Smith's separable masking of each lobe's NDF, n =
// retro_exponent, and the sheen lobe the "Charlie" fibre distribution (Estevez & Kulla 2017)
//     D_s(h) = (2 + 1/a) sin(theta_h)^(1/a) / (2 pi),   a = sheen_roughness in (0, 1],
// (normalised like an NDF: integral D_s cos = 1) with Neubelt & Pettineo's (2013) smooth
// visibility term instead of a masking function. It peaks where h lies in the tangent plane,
// i.e. at grazing, opposite wi and wo (the rim highlight of velvet and other fibre-covered
// surfaces), is reciprocal, and stays finite at the horizon. Every term is >= 0 and reciprocal.
// The diffuse term is added without a (1 - F) factor on purpose: the material then lies
// exactly in the NPF model's family (rho_d + rho_s D F G G / cos cos) when it has one lobe,
// which is what the fitter's exactness tests need.
//
// Sampling is a mixture: specular lobes draw m ~ D(m) cos(theta_m) and reflect wi (draws with
// wi.m <= 0 or wo below the horizon fail), the diffuse and sheen lobes draw cosine-weighted
// directions, the retro lobe draws (n + 1) / (2 pi) (wi.wo)^n around wi (draws below the
// horizon fail). Lobes are chosen with probabilities proportional to the luminance (over the
// material's wavelengths) of their weight spectra, each specular weight times the
// cosine-weighted hemispherical average of its Fresnel term; pdf() is the exact density of
// that procedure, so pdf integrates to 1 minus the failure probability.
#pragma once

#include <npf/color/spectrum.h>
#include <npf/materials/analytic/fresnel.h>
#include <npf/materials/analytic/microfacet.h>
#include <npf/core/brdf.h>

#include <array>
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
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
    // that keep "all" of them: 195 samples over 360..1000 nm by default, like the database
    // (AnalyticBrdf fills that list in when this is empty). Must be strictly ascending.
    std::vector<float> wavelengths;
    // Width of the sheen lobe (a of D_s above): 1 broad, -> 0 concentrated at the horizon.
    float sheen_roughness = 0.5f;
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
    // The same as a callable for RglWriterOptions::ndf (a copy, independent of this object), or
    // an empty function when there is no single NDF.
    std::function<float(const Vec3&)> ndf_function() const;

private:
    // The material's spectra looked up once at a fixed list of wavelengths (empty vectors
    // where a lobe is absent): the internal RGB grid, and the material's own wavelengths (the
    // list writers ask for), so that those evaluations search no tables.
    struct SpectralTable {
        std::vector<float> wavelengths;
        std::vector<std::vector<double>> lobe_weight;                // per specular lobe
        std::vector<std::vector<Fresnel::Coefficients>> fresnel;    // per specular lobe
        std::vector<double> diffuse, retro, sheen;
    };
    SpectralTable make_table(const std::vector<float>& wavelengths) const;

    // Tables for other wavelength lists, made when query() sees one (a fit at a subset of the
    // material's wavelengths asks millions of times for the same list: looking each spectrum
    // up per evaluation was most of a preview conversion). Append-only, read without a lock;
    // shared by copies, which hold the same material.
    struct QueryTables {
        static constexpr std::size_t kSlots = 8;
        std::array<std::atomic<const SpectralTable*>, kSlots> slots{};
        std::mutex adding;
        std::vector<std::unique_ptr<const SpectralTable>> owned;
    };
    const SpectralTable* table_for(const std::vector<float>& wavelengths) const;

    // Adds f_r cos(theta_o) at `n` wavelengths to acc[]: entries [first, first + n) of
    // `table`, or, when table is null, lambda[0..n) looked up in the spectra. Both directions
    // must be above the horizon.
    template <typename Acc>
    void accumulate(const Vec3& wi, const Vec3& wo, const SpectralTable* table, std::size_t first,
                    const float* lambda, std::size_t n, Acc* acc) const;
    double specular_pdf(const SpecularLobe& lobe, const Vec3& wi, const Vec3& wo) const;

    AnalyticMaterial m_material;
    BrdfInfo m_info;
    std::vector<float> m_rgb_wavelengths;          // spectral grid for RGB evaluation
    std::array<std::vector<double>, 3> m_rgb_weights;
    std::vector<float> m_lobe_probability;         // sampling mixture: specular lobes..., diffuse, retro, sheen
    std::vector<float> m_lobe_cdf;                 // its running sum (size + 1 entries, last = 1)
    SpectralTable m_grid_table, m_native_table;
    std::shared_ptr<QueryTables> m_query_tables = std::make_shared<QueryTables>();
};

}  // namespace npf
