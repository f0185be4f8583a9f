#include <npf/shading/npf_brdf.h>

#include <npf/core/cosine_sampling.h>
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
    char kept[64];
    std::snprintf(kept, sizeof kept, "%.6g", 100.0 * s.kept_ratio);
    return std::to_string(s.rank) + " of " + std::to_string(std::min(s.cells, channels)) + " (keeps " + kept +
           " % of the squared singular values)";
}

BrdfInfo describe(const NpfModel& m, const std::string& path, std::uint64_t file_bytes) {
    BrdfInfo info;
    info.format = "npf-exr";
    info.path = path;
    info.isotropic = m.isotropic();
    info.channels = m.channels;
    info.file_bytes = file_bytes;
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
    for (const auto& [key, value] : m.metadata) {
        if (key != "description") info.details.emplace_back(key, value);
    }
    return info;
}

}  // namespace

NpfBrdf::NpfBrdf(NpfModel model) : NpfBrdf(std::move(model), std::string(), 0) {}

NpfBrdf::NpfBrdf(const std::string& path)
    : NpfBrdf(read_npf_texture(path), path, require_regular_file(path, "an NPF texture (.exr)")) {}

NpfBrdf::NpfBrdf(NpfModel model, const std::string& path, std::uint64_t file_bytes) : m_model(std::move(model)) {
    m_model.validate(path.empty() ? std::string("NPF model") : path);
    m_info = describe(m_model, path, file_bytes);
}

void NpfBrdf::eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const {
    const std::size_t n = query.size();
    NpfModel::Lookup at;
    if (!m_model.prepare(wi, wo, at)) {
        std::fill(out, out + n, 0.f);
        return;
    }
    const std::size_t C = m_model.channel_count();
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t i0 = query.index0[k], i1 = query.index1[k];
        const double w1 = query.weight1[k];
        const double a = i0 < C ? m_model.value(at, i0) : 0.0;
        const double b = w1 == 0.0 ? 0.0 : (i1 < C ? m_model.value(at, i1) : 0.0);
        double v = ((1.0 - w1) * a + w1 * b) * at.cos_o;
        if (!std::isfinite(v)) v = 0.0;  // f_r cos can overflow only for directions grazing to 1e-38
        if (query.clamp_negative && v < 0.0) v = 0.0;
        out[k] = float(v);
    }
}

// ---- Sampling ----------------------------------------------------------------------------
// Cosine-weighted: exact for the diffuse term, never zero where the BRDF is not.

float NpfBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
    if (!(wi.z > 0.f) || !(wo.z > 0.f)) return 0.f;
    return wo.z * (1.f / kPi);
}

bool NpfBrdf::sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s, float* weight) const {
    return sample_cosine_hemisphere(*this, wi, u, query, s, weight);
}

}  // namespace npf
