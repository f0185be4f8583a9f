// The NPF material as a renderer shades with it: an OSL-closure-shaped BSDF (eval / sample /
// pdf) over a converted factor texture (docs/format.md), read either
//  - through OpenImageIO's TextureSystem (Path::Texture): D and G are bilinear texture lookups in
//    the host's TextureSystem (or a private one), so the host's cache owns their memory; or
//  - from the same tables baked into arrays (Path::Memory): the fast path, the evaluation the
//    converter itself uses (NpfModel), same results to float rounding.
//
// Conventions (docs/conventions.md): the directions are named by their roles, not wi/wo, whose
// meaning differs between OSL and pbrt (wo towards the viewer) and npf::Brdf, Mitsuba and the RGL
// files (wi towards the viewer):
//  - Local shading frame: z = normal, x = tangent (phi = 0), y = bitangent.
//  - `view` points towards the viewer (the direction a query is conditioned on: npf::Brdf's wi),
//    `light` towards the light (the one `sample` draws: npf::Brdf's wo). Both point away from
//    the surface. The NPF model is reciprocal, so only the cosine factor depends on which is which.
//  - Values are f_r(view, light) cos(theta_light); weights are value / pdf; pdf is per solid angle
//    of `light`.
//  - Either direction at or below the horizon gives value 0 and pdf 0 (one-sided).
//
// Wavelengths: a spectral material answers any wavelengths (hero-wavelength rendering: 4 at a
// time, any values) or its whole stored spectrum. At a requested wavelength the BRDF is linear
// between the two neighbouring stored wavelengths and constant outside them (the rule of every
// npf source); D and G are rebuilt from their SVD bases at those stored wavelengths (Eq. 11).
// An RGB material shades in RGB: it always answers R, G, B, whatever the request.
//
// Sampling (paper sec. 3.5): the half vector is drawn from the luminance-averaged NDF through an
// alias table (HalfVectorSampler), mixed with cosine sampling for the diffuse term in proportion
// to the two terms' albedos; pdf() is the density of exactly that mixture.
//
// An NpfClosure is immutable after construction: any number of threads may shade with one at
// once. eval, pdf and sample never throw and never allocate.
#pragma once

#include <npf/core/channels.h>
#include <npf/core/vec.h>
#include <npf/shading/half_vector_sampler.h>
#include <npf/shading/npf_batch.h>
#include <npf/shading/npf_model.h>
#include <npf/shading/oiio_fwd.h>

#include <cstddef>
#include <memory>
#include <string>

namespace npf {

// Which values an evaluation writes.
struct WavelengthRequest {
    const float* nm = nullptr;  // null: every stored channel, in stored order
    int count = 0;

    static WavelengthRequest stored() { return {}; }
    static WavelengthRequest at(const float* nm, int count) { return {nm, count}; }
};

struct ClosureSample {
    Vec3 light;       // the drawn direction, towards the light
    float pdf = 0.f;  // solid-angle density of `light`
};

class NpfClosure {
public:
    enum class Path { Memory, Texture };

    // The fast path over a model in memory. Throws npf::Error when the model is inconsistent.
    explicit NpfClosure(NpfModel model);
    // Opens an NPF factor texture. Path::Texture shades through `ts` (the host's TextureSystem,
    // which must outlive the closure; a private one when null) and keeps only the per-channel
    // values and F in memory; Path::Memory reads the whole file into arrays (`ts` unused).
    // Throws npf::Error naming the file for anything read_npf_texture rejects, and for a rank
    // above NpfModel::kInlineRank on the texture path.
    explicit NpfClosure(const std::string& path, Path path_kind = Path::Memory, OIIO::TextureSystem* ts = nullptr);
    ~NpfClosure();
    NpfClosure(const NpfClosure&) = delete;
    NpfClosure& operator=(const NpfClosure&) = delete;

    Path path() const { return m_path; }
    const Channels& channels() const { return m_model.channels; }
    std::size_t channel_count() const { return m_model.channel_count(); }
    // How many values eval/sample write for `request` (3 for RGB materials).
    std::size_t value_count(WavelengthRequest request) const;
    // The same for a batch's wavelengths (per pair).
    std::size_t value_count(BatchWavelengths w) const { return value_count(WavelengthRequest::at(w.nm, w.count)); }
    // The model: complete on the memory path; on the texture path its D and G basis tables are
    // empty (they live in the TextureSystem), everything else is there.
    const NpfModel& model() const { return m_model; }
    // NpfModel::value_bound of the model as read (the texture path's bases are gone after loading).
    double value_bound() const { return m_value_bound; }

    // f_r cos(theta_light) into value[value_count(request)]; returns pdf(view, light).
    float eval(const Vec3& view, const Vec3& light, WavelengthRequest request, float* value) const;
    float pdf(const Vec3& view, const Vec3& light) const;
    // Draws `light` from two uniform numbers in [0, 1); writes value / pdf into weight (when not
    // null).
    // false (weights 0) when the draw falls below the horizon.
    bool sample(const Vec3& view, float u1, float u2, WavelengthRequest request, ClosureSample& s,
                float* weight) const;
    // The direction and its pdf alone, without evaluating the BRDF.
    bool sample_direction(const Vec3& view, float u1, float u2, ClosureSample& s) const;

    // Batched (npf_batch.h): n pairs at once, the results of eval and pdf above for each. values:
    // channel-major, pair i's value k at values[k * n + i] (k < value_count of the request);
    // pdf[i] when pdf is not null. No allocation. The texture path evaluates pair by pair.
    void eval_batch(std::size_t n, const DirectionArrays& view, const DirectionArrays& light, BatchWavelengths wavelengths,
                    float* values, float* pdf) const;
    void pdf_batch(std::size_t n, const DirectionArrays& view, const DirectionArrays& light, float* pdf) const;
    // sample() for each pair from u1[i], u2[i]: the drawn direction into light_out (x, y, z arrays
    // of n; (0, 0, 0) where the draw fails), its pdf (0 where it fails) and, when weights is not
    // null, value / pdf channel-major as eval_batch's values (0 where it fails).
    void sample_batch(std::size_t n, const DirectionArrays& view, const float* u1, const float* u2,
                      BatchWavelengths wavelengths, float* const light_out[3], float* pdf, float* weights) const;

    // The batched eval's arithmetic (npf_batch.h's BatchPrecision); set before shading (not
    // synchronised with batched calls on other threads). The scalar calls are double always.
    void set_batch_precision(BatchPrecision p) { m_batch_precision = p; }
    BatchPrecision batch_precision() const { return m_batch_precision; }

    // Probability of choosing the diffuse (cosine) strategy rather than the half-vector one.
    double diffuse_probability() const { return m_diffuse_probability; }

private:
    class TextureTables;

    void finish_construction();
    // The sampling strategies' draw of `light` alone (sample_direction without its pdf); false
    // when it falls at or below the horizon.
    bool draw_light(const Vec3& view, float u1, float u2, Vec3& light) const;
    // Fills `at` (NpfModel takes the conditioned direction, `view`, first); false below the horizon.
    bool lookup(const Vec3& view, const Vec3& light, NpfModel::Lookup& at) const;
    // value[k * stride] for each value k (stride 1: contiguous; the batch writes channel-major).
    void write_values(const NpfModel::Lookup& at, double cos_light, WavelengthRequest request, float* value,
                      std::size_t stride = 1) const;
    float pdf_at(double theta_h, double u_h, double phi_h, double cos_d, double cos_light) const;

    Path m_path = Path::Memory;
    NpfModel m_model;
    double m_value_bound = 0.0;
    std::unique_ptr<TextureTables> m_texture;
    HalfVectorSampler m_sampler;
    WavelengthLocator m_wavelengths;  // the stored grid (spectral materials)
    double m_diffuse_probability = 0.0;
    // D's, G's and the detail layer's bases again, cell by cell (four floats per cell: ranks up to
    // 4) with neighbours side by side (batch_values.h's paired_cells_of), so that the batched
    // eval's vector lookups load two corners' ranks at once; empty where a rank is above 4 and on
    // the texture path.
    std::vector<float> m_cell_major_d, m_cell_major_g, m_cell_major_detail;
    std::vector<float> m_cell_major_f;  // F cell by cell (up to 4 channels): the stored channels' at once
    // Each channel's coefficients in eight floats (batch_values.h), for per-lane channels.
    std::vector<float> m_channel_records;
    // D, G and the detail layer recombined channel by channel, paired like the above
    // (batch_values.h's channel_tables_of): the float lanes' stored channels; empty past 4 channels.
    std::vector<float> m_channel_d, m_channel_g, m_channel_detail;
    BatchPrecision m_batch_precision = BatchPrecision::Double;
};

}  // namespace npf
