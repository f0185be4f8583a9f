// An npf::Brdf whose eval_cos is the batched closure's (NpfClosure::eval_batch with the pair in
// all eight lanes of a batch), so that a render (npf/render) can shade through either of the
// batch's precisions: the paired render of the float budget (docs/shading.md) compares the two.
// Header-only: shading/tests/test_batch_float.cpp and bench/batch_floor.cpp.
#pragma once

#include <npf/shading/npf_batch.h>
#include <npf/shading/npf_brdf.h>
#include <npf/shading/npf_closure.h>

#include <algorithm>
#include <string>
#include <vector>

namespace npf::testing {

class BatchedBrdf final : public Brdf {
public:
    BatchedBrdf(const std::string& path, BatchPrecision precision) : m_scalar(path), m_closure(path) {
        m_closure.set_batch_precision(precision);
    }
    const BrdfInfo& info() const override { return m_scalar.info(); }
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const override {
        constexpr std::size_t kLanes = 8;  // one whole group of the float lanes
        const Channels& r = query.requested;
        const BatchWavelengths wl =
            r.is_rgb() ? BatchWavelengths::stored() : BatchWavelengths::shared(r.wavelengths().data(), int(r.size()));
        const std::size_t count = m_closure.value_count(wl);
        float v[6][kLanes];
        const float c[6] = {wi.x, wi.y, wi.z, wo.x, wo.y, wo.z};
        for (int k = 0; k < 6; ++k) std::fill(v[k], v[k] + kLanes, c[k]);
        std::vector<float> values(count * kLanes);
        m_closure.eval_batch(kLanes, {v[0], v[1], v[2]}, {v[3], v[4], v[5]}, wl, values.data(), nullptr);
        for (std::size_t k = 0; k < count; ++k) out[k] = values[k * kLanes];
    }
    // Sampling and pdf as the scalar closure (a render with delta lights uses neither).
    float pdf(const Vec3& wi, const Vec3& wo) const override { return m_scalar.pdf(wi, wo); }
    bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s, float* weight) const override {
        return m_scalar.sample(wi, u, query, s, weight);
    }

private:
    NpfBrdf m_scalar;
    NpfClosure m_closure;
};

}  // namespace npf::testing
