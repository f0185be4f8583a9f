#include <npf/materials/isotropic_rgb_brdf.h>

#include <npf/core/cosine_sampling.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace npf {

float IsotropicRgbBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
    if (!(wi.z > 0.f) || !(wo.z > 0.f)) return 0.f;
    return wo.z * (1.f / kPi);
}

bool IsotropicRgbBrdf::sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                              float* weight) const {
    return sample_cosine_hemisphere(*this, wi, u, query, s, weight);
}

bool IsotropicRgbBrdf::evaluable(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) {
    const auto finite = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    if (wi.z > 0.f && wo.z > 0.f && finite(wi) && finite(wo)) return true;
    std::fill(out, out + query.size(), 0.f);
    return false;
}

void IsotropicRgbBrdf::describe_rgb_file(const std::string& format, const std::string& path, std::uint64_t file_bytes) {
    m_info.format = format;
    m_info.path = path;
    m_info.description = std::filesystem::path(path).stem().string();
    m_info.isotropic = true;
    m_info.channels = Channels::rgb();
    m_info.file_bytes = file_bytes;
}

}  // namespace npf
