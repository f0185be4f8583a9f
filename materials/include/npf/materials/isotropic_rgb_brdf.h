// The base of the isotropic RGB materials read from files without a description or sampling data
// of their own (MERL tables, Neural BRDF networks). Their table or network does not invert
// cheaply, so wo is drawn cosine-weighted over the hemisphere (cosine_sampling.h): exact for the
// diffuse part, never zero where the BRDF is not, and pdf and sample stay trivially consistent.
// A reader fills m_info (describe_rgb_file) and implements eval_cos (write_rgb_query).
#pragma once

#include <npf/core/brdf.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

namespace npf {

class IsotropicRgbBrdf : public Brdf {
public:
    const BrdfInfo& info() const override { return m_info; }
    // cos(theta_o) / pi, 0 with either direction at or below the horizon.
    float pdf(const Vec3& wi, const Vec3& wo) const override;
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                float* weight) const override;

protected:
    IsotropicRgbBrdf() = default;

    // m_info's format, path, file size, isotropy and RGB channels; the description is the file's
    // name, the material's only name.
    void describe_rgb_file(const std::string& format, const std::string& path, std::uint64_t file_bytes);

    // Whether eval_cos has a value for the pair: both directions finite and above the horizon (a
    // one-sided material). When not, writes the query's zeros to `out`.
    static bool evaluable(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out);

    // out[k], k < query.size(): the query's channel k of `rgb` (R, G, B; 0 beyond) times cos_o, in
    // T's precision; 0 where not finite (arguments that are not unit vectors), and 0 for a
    // negative value when the query clamps.
    template <class T>
    static void write_rgb_query(const T (&rgb)[3], T cos_o, const ChannelQuery& query, float* out) {
        for (std::size_t k = 0; k < query.size(); ++k) {
            const std::uint32_t i0 = query.index0[k], i1 = query.index1[k];
            const T w1 = query.weight1[k];
            const T a = i0 < 3 ? rgb[i0] : T(0);
            const T b = i1 < 3 ? rgb[i1] : T(0);
            T v = (w1 == T(0) ? a : (T(1) - w1) * a + w1 * b) * cos_o;
            if (!std::isfinite(v)) v = T(0);
            if (query.clamp_negative && v < T(0)) v = T(0);
            out[k] = static_cast<float>(v);
        }
    }

    BrdfInfo m_info;
};

}  // namespace npf
