// A Lambertian reflector of constant albedo for the renderer's tests (f_r = albedo / pi): it
// reports RGB or any wavelength list as its stored channels, answers any channels asked for with
// the same value, and samples by the cosine.
#pragma once

#include <npf/core/brdf.h>
#include <npf/core/cosine_sampling.h>

#include <cstddef>
#include <utility>

namespace npf::testing {

class Lambertian final : public Brdf {
public:
    static constexpr double kPi = 3.14159265358979323846;

    explicit Lambertian(float albedo, Channels stored = Channels::rgb()) : m_albedo(albedo) {
        m_info.format = "test lambertian";
        m_info.channels = std::move(stored);
    }
    const BrdfInfo& info() const override { return m_info; }
    ChannelQuery query(const Channels& requested) const override {
        ChannelQuery q;
        q.requested = requested;
        q.index0.assign(requested.size(), 0);
        q.index1.assign(requested.size(), 0);
        q.weight1.assign(requested.size(), 0.f);
        return q;
    }
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& q, float* out) const override {
        const float v = wi.z > 0.f && wo.z > 0.f ? m_albedo * wo.z / float(kPi) : 0.f;
        for (std::size_t k = 0; k < q.size(); ++k) out[k] = v;
    }
    float pdf(const Vec3& wi, const Vec3& wo) const override { return wi.z > 0.f && wo.z > 0.f ? wo.z / float(kPi) : 0.f; }
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& q, BrdfSample& s, float* weight) const override {
        return sample_cosine_hemisphere(*this, wi, u, q, s, weight);
    }

private:
    float m_albedo;
    BrdfInfo m_info;
};

}  // namespace npf::testing
