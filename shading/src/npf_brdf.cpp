#include <npf/shading/npf_brdf.h>

#include <npf/core/number_text.h>
#include <npf/core/text.h>

#include <npf/shading/npf_albedo.h>
#include <npf/shading/npf_texture_file.h>

#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <utility>

namespace npf {

namespace {

std::string grid_text(int a, int b, const char* axes) {
    return std::to_string(a) + " x " + std::to_string(b) + " (" + axes + ")";
}

std::string rank_text(const SpectralBasis& s, std::size_t channels) {
    return std::to_string(s.rank) + " of " + std::to_string(std::min(s.cells, channels)) + " (keeps " +
           number_text(100.0 * s.kept_ratio) +
           " % of the squared singular values)";
}

BrdfInfo describe(const NpfModel& m, double value_bound, const std::string& path, std::uint64_t file_bytes) {
    BrdfInfo info;
    info.format = "npf-exr";
    info.path = path;
    info.isotropic = m.isotropic();
    info.channels = m.channels;
    info.file_bytes = file_bytes;
    info.value_bound = value_bound;
    for (const auto& [key, value] : m.metadata) {
        if (key == "description") info.description = value;
    }
    if (info.description.empty() && !path.empty()) info.description = std::filesystem::path(path).stem().string();
    const std::size_t C = m.channel_count();
    info.details = {
        {"D grid", grid_text(m.d_theta, m.d_phi, "theta_h square-root mapped x phi_h")},
        {"F grid", std::to_string(m.f_theta) + " (theta_d)"},
        {"G grid", grid_text(m.g_theta, m.g_phi, "theta x phi")},
        {"D rank", rank_text(m.D, C)},
        {"G rank", rank_text(m.G, C)},
    };
    if (m.has_detail()) {
        const DetailGrid& g = m.detail_grid;
        info.details.emplace_back("detail grid", std::to_string(g.theta_h) + " x " + std::to_string(g.theta_d) + " x " +
                                                     std::to_string(g.phi_d) + " (u_h x theta_d x phi_d)");
        info.details.emplace_back("detail rank", rank_text(m.detail, C));
    }
    for (const auto& [key, value] : m.metadata) {
        if (key != "description") info.details.emplace_back(key, value);
    }
    return info;
}

}  // namespace

NpfBrdf::NpfBrdf(NpfModel model) : NpfBrdf(std::make_unique<NpfClosure>(std::move(model)), std::string(), 0) {}

NpfBrdf::NpfBrdf(const std::string& path, NpfClosure::Path path_kind, OIIO::TextureSystem* ts)
    : NpfBrdf(std::make_unique<NpfClosure>(path, path_kind, ts), path,
              require_regular_file(path, "an NPF texture (.exr)")) {}

NpfBrdf::NpfBrdf(std::unique_ptr<NpfClosure> closure, const std::string& path, std::uint64_t file_bytes)
    : m_closure(std::move(closure)) {
    m_info = describe(m_closure->model(), m_closure->value_bound(), path, file_bytes);
    if (m_closure->path() == NpfClosure::Path::Texture) {
        m_info.details.emplace_back("shading path", "texture (OpenImageIO TextureSystem)");
    }
}

namespace {
WavelengthRequest request_of(const ChannelQuery& query) {
    const Channels& r = query.requested;
    return r.is_rgb() ? WavelengthRequest::stored() : WavelengthRequest::at(r.wavelengths().data(), int(r.size()));
}
}  // namespace

// npf::Brdf's wi is the closure's view, its wo the closure's light (docs/conventions.md).
void NpfBrdf::eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const {
    m_closure->eval(/*view=*/wi, /*light=*/wo, request_of(query), out);
}

float NpfBrdf::pdf(const Vec3& wi, const Vec3& wo) const { return m_closure->pdf(/*view=*/wi, /*light=*/wo); }

bool NpfBrdf::sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s, float* weight) const {
    ClosureSample c;
    const bool ok = m_closure->sample(/*view=*/wi, u.x, u.y, request_of(query), c, weight);
    s.wo = c.light;
    s.pdf = ok ? c.pdf : 0.f;
    return ok;
}

// In memory the model's tables are at hand: the quadrature on them (npf_albedo.h). Channels
// between stored wavelengths blend the stored channels' albedos with eval's own weights (eval
// blends values, and the integral is linear). The texture path has no D or G tables here.
bool NpfBrdf::albedo_by_quadrature(const Vec3& wi, const ChannelQuery& query, std::vector<double>& albedo) const {
    if (m_closure->path() != NpfClosure::Path::Memory) return false;
    const std::vector<double> stored = npf_directional_albedo(m_closure->model(), wi);
    albedo.assign(query.size(), 0.0);
    for (std::size_t k = 0; k < query.size(); ++k) {
        const double t = query.weight1[k], a = stored[query.index0[k]];
        albedo[k] = t == 0.f ? a : (1.0 - t) * a + t * stored[query.index1[k]];
    }
    return true;
}

}  // namespace npf
