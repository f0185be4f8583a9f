#include <npf/shading/npf_closure.h>

#include "batch_values.h"

#include "finite_float.h"

#include "luminance.h"
#include "texture_tables.h"

#include <npf/core/cosine_sampling.h>
#include <npf/core/error.h>
#include <npf/core/float_environment.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/shading/table_interpolation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace npf {

namespace {

constexpr double kInvPi = 1.0 / kPiD;

Vec3 reflect(const Vec3& w, const Vec3& h) {
    const float d = 2.f * dot(w, h);
    return {d * h.x - w.x, d * h.y - w.y, d * h.z - w.z};
}

// The detail layer's value of channel c at a prepared pair (0 without one).
double detail_value(const NpfModel& m, const NpfModel::Lookup& at, std::size_t c) {
    if (m.detail.rank == 0) return 0.0;
    const float* w = m.detail.weights.data() + c * std::size_t(m.detail.rank);
    double r = 0.0;
    for (int k = 0; k < m.detail.rank; ++k) r += w[k] * at.r_basis[k];
    return r;
}

// The mean of term(u, v) over the centres of kStrata x kStrata strata of the unit square, for the
// quadratures at normal incidence below (a stratum that contributes nothing gives 0).
template <class Term>
double strata_mean(const Term& term) {
    constexpr int kStrata = 32;
    double sum = 0.0;
    for (int a = 0; a < kStrata; ++a)
        for (int b = 0; b < kStrata; ++b) sum += term((a + 0.5f) / kStrata, (b + 0.5f) / kStrata);
    return sum / (kStrata * kStrata);
}

// Directional albedo of the specular term at normal incidence, luminance weighted: a quadrature
// over the half-vector sampler's own strata, used only to balance the two sampling strategies.
double specular_albedo_at_normal(const NpfModel& m, const HalfVectorSampler& sampler, const std::vector<double>& y) {
    const Vec3 normal(0.f, 0.f, 1.f);
    NpfModel::Lookup at;
    return std::max(0.0, strata_mean([&](float u, float v) {
        const Vec3 h = sampler.sample(u, v);
        const Vec3 light = reflect(normal, h);
        const double pdf = sampler.pdf(h) / (4.0 * std::max(double(h.z), 1e-12));
        if (!(light.z > 0.f) || !(pdf > 0.0) || !m.prepare(normal, light, at)) return 0.0;
        double f = 0.0;
        for (std::size_t c = 0; c < y.size(); ++c) f += y[c] * (m.value(at, c) - m.rho_d[c] - detail_value(m, at, c));
        return f * light.z / pdf;
    }));
}

// The same for the detail layer's positive part, by cosine-weighted strata: a residual that adds
// light away from the peak (a body colour the diffuse term missed, say) is better drawn by the
// cosine strategy, so it counts on the diffuse side of the balance.
double detail_albedo_at_normal(const NpfModel& m, const std::vector<double>& y) {
    if (!m.has_detail()) return 0.0;
    const Vec3 normal(0.f, 0.f, 1.f);
    NpfModel::Lookup at;
    return strata_mean([&](float u, float v) {
        const Vec3 light = cosine_hemisphere_direction(Vec2{u, v});
        if (!m.prepare(normal, light, at)) return 0.0;
        double r = 0.0;
        for (std::size_t c = 0; c < y.size(); ++c) r += y[c] * detail_value(m, at, c);
        return std::max(0.0, r) * kPiD;  // f cos / (cos / pi)
    });
}

}  // namespace

NpfClosure::NpfClosure(NpfModel model) : m_path(Path::Memory), m_model(std::move(model)) {
    m_model.validate("NPF model");
    finish_construction();
}

NpfClosure::NpfClosure(const std::string& path, Path path_kind, OIIO::TextureSystem* ts) : m_path(path_kind) {
    // (read_npf_texture reads the texels with denormals kept, whatever the caller's setting.)
    if (path_kind == Path::Memory) {
        m_model = read_npf_texture(path);
    } else {
        m_texture = std::make_unique<TextureTables>(path, ts);
        m_model = m_texture->read_model();
    }
    finish_construction();
    if (m_texture) {
        // The bases now live in the TextureSystem's cache only.
        m_model.D.basis = std::vector<float>();
        m_model.G.basis = std::vector<float>();
        m_model.detail.basis = std::vector<float>();
    }
}

NpfClosure::~NpfClosure() = default;

void NpfClosure::finish_construction() {
    const ExactFloatScope exact;  // the sampler's tables the same in any caller's environment
    m_value_bound = m_model.value_bound();
    if (!m_model.channels.is_rgb()) m_wavelengths = WavelengthLocator(m_model.channels.wavelengths());
    if (!m_texture) {
        m_cell_major_d = batch_detail::paired_cells_of(m_model.D, m_model.d_theta, m_model.d_phi, m_model.d_phi == 1);
        m_cell_major_g = batch_detail::paired_cells_of(m_model.G, m_model.g_theta, m_model.g_phi, m_model.g_phi == 1);
        const DetailGrid& grid = m_model.detail_grid;
        m_cell_major_detail = batch_detail::padded_detail_cells_of(m_model.detail, grid);
        m_cell_major_f = batch_detail::paired_cells_of(m_model.F.data(), int(m_model.channel_count()), m_model.f_theta, 1, true);
        m_channel_records = batch_detail::channel_records_of(m_model);
        const std::size_t channels = m_model.channel_count();
        m_channel_d = batch_detail::paired_cells_of(batch_detail::channel_tables_of(m_model.D, channels), m_model.d_theta,
                                                    m_model.d_phi, m_model.d_phi == 1);
        m_channel_g = batch_detail::paired_cells_of(batch_detail::channel_tables_of(m_model.G, channels), m_model.g_theta,
                                                    m_model.g_phi, m_model.g_phi == 1);
        m_channel_detail = batch_detail::padded_detail_cells_of(batch_detail::channel_tables_of(m_model.detail, channels), grid);
    }
    try {
        m_sampler = HalfVectorSampler(HalfVectorSampler::luminance_averaged_ndf(m_model), m_model.d_theta,
                                      m_model.d_phi);
    } catch (const Error&) {
        // No cell of D has weight (a purely diffuse material): only cosine sampling remains.
        m_sampler = HalfVectorSampler();
    }
    const std::vector<double> y = luminance_weights_of(m_model.channels);
    double diffuse = 0.0;
    for (std::size_t c = 0; c < y.size(); ++c) diffuse += y[c] * m_model.rho_d[c] * kPiD;
    diffuse += detail_albedo_at_normal(m_model, y);
    const double specular = m_sampler.empty() ? 0.0 : specular_albedo_at_normal(m_model, m_sampler, y);
    if (specular <= 0.0 || m_sampler.empty()) {
        m_diffuse_probability = 1.0;
    } else if (diffuse <= 0.0) {
        m_diffuse_probability = 0.0;
    } else {
        // Neither strategy may starve: each keeps at least 5 % of the samples.
        m_diffuse_probability = std::clamp(diffuse / (diffuse + specular), 0.05, 0.95);
    }
}

std::size_t NpfClosure::value_count(WavelengthRequest request) const {
    if (m_model.channels.is_rgb() || !request.nm) return m_model.channel_count();
    return std::size_t(std::max(request.count, 0));
}

bool NpfClosure::lookup(const Vec3& view, const Vec3& light, NpfModel::Lookup& at) const {
    if (!m_texture) return m_model.prepare(view, light, at);
    if (!m_model.prepare(view, light, at, /*project_bases=*/false)) return false;
    const ExactFloatScope exact;  // the TextureSystem converts half texels as it reads them
    return m_texture->fill(at);
}

void NpfClosure::write_values(const NpfModel::Lookup& at, double cos_light, WavelengthRequest request, float* value,
                              std::size_t stride) const {
    const std::size_t C = m_model.channel_count();
    if (m_model.channels.is_rgb() || !request.nm) {
        for (std::size_t c = 0; c < C; ++c) value[c * stride] = finite_float(std::max(0.0, m_model.value(at, c)) * cos_light);
        return;
    }
    for (int k = 0; k < request.count; ++k) {
        std::uint32_t i0, i1;
        float t;
        m_wavelengths.locate(request.nm[k], i0, i1, t);
        const double a = m_model.value(at, i0);
        const double v = t == 0.f ? a : (1.0 - t) * a + t * m_model.value(at, i1);
        value[std::size_t(k) * stride] = finite_float(std::max(0.0, v) * cos_light);
    }
}

float NpfClosure::pdf_at(double theta_h, double u_h, double phi_h, double cos_d, double cos_light) const {
    double p = m_diffuse_probability * cos_light * kInvPi;
    if (m_diffuse_probability < 1.0 && cos_d > 0.0) {
        p += (1.0 - m_diffuse_probability) * m_sampler.pdf(theta_h, u_h, phi_h) / (4.0 * cos_d);
    }
    return finite_float(p);
}

float NpfClosure::eval(const Vec3& view, const Vec3& light, WavelengthRequest request, float* value) const {
    NpfModel::Lookup at;
    if (!lookup(view, light, at)) {
        std::fill(value, value + value_count(request), 0.f);
        return 0.f;
    }
    write_values(at, at.cos_o, request, value);
    return pdf_at(at.theta_h, at.u_h, at.phi_h, at.cos_d, at.cos_o);
}

float NpfClosure::pdf(const Vec3& view, const Vec3& light) const {
    // Only the half vector is needed, computed by the same code as in eval, so that eval's pdf
    // and this one agree to the bit.
    NpfModel::HalfVector h;
    if (!m_model.half_vector(view, light, h)) return 0.f;
    return pdf_at(h.theta_h, h.u_h, h.phi_h, h.cos_d, h.cos_o);
}

bool NpfClosure::draw_light(const Vec3& view, float u1, float u2, Vec3& light) const {
    if (!(view.z > 0.f)) return false;
    const double pd = m_diffuse_probability;
    if (u2 < pd) {
        // Stretch u2 back to [0, 1) for the strategy's own use.
        const float v = std::min(float(u2 / pd), 0x1.fffffep-1f);
        light = cosine_hemisphere_direction(Vec2{u1, v});
    } else {
        const float v = std::min(float((u2 - pd) / (1.0 - pd)), 0x1.fffffep-1f);
        light = reflect(view, m_sampler.sample(u1, v));
    }
    return light.z > 0.f;
}

bool NpfClosure::sample_direction(const Vec3& view, float u1, float u2, ClosureSample& s) const {
    if (!draw_light(view, u1, u2, s.light)) return false;
    s.pdf = pdf(view, s.light);
    return s.pdf > 0.f;
}

bool NpfClosure::sample(const Vec3& view, float u1, float u2, WavelengthRequest request, ClosureSample& s,
                        float* weight) const {
    const std::size_t n = value_count(request);
    if (weight) std::fill(weight, weight + n, 0.f);
    if (!sample_direction(view, u1, u2, s)) return false;
    if (!weight) return true;
    NpfModel::Lookup at;
    if (!lookup(view, s.light, at)) return false;
    write_values(at, at.cos_o, request, weight);
    const double inv_pdf = 1.0 / double(s.pdf);
    for (std::size_t k = 0; k < n; ++k) weight[k] = finite_float(weight[k] * inv_pdf);
    return true;
}

}  // namespace npf
