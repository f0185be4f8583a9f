// RGL files evaluated, sampled and pdf'd (loading: rgl_brdf_load.cpp).
#include <npf/core/clamp.h>
#include <npf/materials/rgl_brdf.h>
#include "rgl_u_space.h"
#include <npf/core/brdf.h>

#include <algorithm>
#include <cmath>

namespace npf {

namespace {

// The sign flips that fold an anisotropic query into the stored azimuth range (Mitsuba 3's
// rule for files whose phi_i grid covers 1/2 or 1/4 of the circle).
struct Fold {
    bool flip_x = false, flip_y = false;
    Vec3 apply(Vec3 w) const {
        if (flip_x) w.x = -w.x;
        if (flip_y) w.y = -w.y;
        return w;
    }
};

Fold fold_for(int reduction, const Vec3& wi) {
    Fold f;
    if (reduction == 2) {
        f.flip_x = f.flip_y = !std::signbit(wi.y);
    } else if (reduction == 4) {
        f.flip_y = !std::signbit(wi.y);
        f.flip_x = !std::signbit(wi.x);
    }
    return f;
}

}  // namespace

struct RglBrdf::DirectionState {
    Vec3 wi, wh;          // folded
    float theta_i = 0.f, phi_i = 0.f;
    Vec2 u_h;             // half vector in u-space (relative azimuth if isotropic)
    Vec2 u_i;             // wi in u-space
    SliceBlend params;    // (phi_i, theta_i) blend of the conditional tables
    Vec2 xi;              // data-square position
    float vndf_density = 0.f;
};

bool RglBrdf::prepare(Vec3 wi, Vec3 wo, DirectionState& st) const {
    if (!(wi.z > 0.f) || !(wo.z > 0.f)) return false;
    const Fold fold = fold_for(m_reduction, wi);
    st.wi = wi = fold.apply(wi);
    wo = fold.apply(wo);
    st.wh = normalize(wi + wo);  // wi.z + wo.z > 0, so never the zero vector

    st.theta_i = elevation(wi);
    st.phi_i = azimuth(wi);
    const float theta_h = elevation(st.wh);
    float phi_h = azimuth(st.wh);
    if (m_isotropic) phi_h -= st.phi_i;
    float u_phi_h = phi_to_u(phi_h);
    u_phi_h -= std::floor(u_phi_h);
    st.u_h = {theta_to_u(theta_h), u_phi_h};
    st.u_i = {theta_to_u(st.theta_i), phi_to_u(st.phi_i)};
    st.params = blend_two_parameters(m_phi_i.size(), locate_on_grid(m_phi_i, st.phi_i), m_theta_i.size(),
                                     locate_on_grid(m_theta_i, st.theta_i));
    st.xi = m_vndf.invert(st.u_h, st.params, &st.vndf_density);
    return true;
}

void RglBrdf::eval_data(const DirectionState& st, const ChannelQuery& query, float* out) const {
    // The bilinear corner weights of xi times the parameter-slice weights: up to 16 terms that
    // every channel shares; each channel then only adds its own index.
    const std::size_t W = m_data_width, H = m_data_height, C = m_channel_count;
    const float gx = clamp_range(st.xi.x, 0.f, 1.f) * float(W - 1);
    const float gy = clamp_range(st.xi.y, 0.f, 1.f) * float(H - 1);
    const std::size_t c = std::min(std::size_t(gx), W - 2), r = std::min(std::size_t(gy), H - 2);
    const float s = gx - float(c), t = gy - float(r);
    const float corner_w[4] = {(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t};
    const std::size_t corner_k[4] = {r * W + c, r * W + c + 1, (r + 1) * W + c, (r + 1) * W + c + 1};
    const float* base[16];
    float weight[16];
    int terms = 0;
    for (int j = 0; j < st.params.count; ++j) {
        const float* slice = m_data.data() + std::size_t(st.params.slice[j]) * H * W * C;
        for (int q = 0; q < 4; ++q) {
            base[terms] = slice + corner_k[q] * C;
            weight[terms] = st.params.weight[j] * corner_w[q];
            ++terms;
        }
    }

    auto finish = [&](float v) { return query.clamp_negative ? clamp_low(v, 0.f) : v; };
    const std::size_t n = query.size();
    constexpr std::size_t kMaxAccumulated = 512;
    if (n > 8 && C <= kMaxAccumulated) {
        // Many channels: accumulate the stored channels they read, a contiguous range, in one
        // vectorisable pass, then read the requested ones from the sums. (The range, not every
        // stored channel: the fitter asks a 195-wavelength file for a third of them per pass.)
        std::uint32_t lo = query.index0[0], hi = query.index1[0];
        for (std::size_t k = 1; k < n; ++k) lo = std::min(lo, query.index0[k]), hi = std::max(hi, query.index1[k]);
        float sum[kMaxAccumulated];
        for (std::size_t ch = lo; ch <= hi; ++ch) sum[ch] = weight[0] * base[0][ch];
        for (int k = 1; k < terms; ++k) {
            const float w = weight[k];
            const float* b = base[k];
            for (std::size_t ch = lo; ch <= hi; ++ch) sum[ch] += w * b[ch];
        }
        for (std::size_t k = 0; k < n; ++k) {
            const float v0 = sum[query.index0[k]];
            out[k] = finish(v0 + query.weight1[k] * (sum[query.index1[k]] - v0));
        }
        return;
    }
    // Few channels (RGB, hero wavelengths): gather just those, eight at a time and term by
    // term, so that each corner's cache line is visited once for all of them.
    for (std::size_t first = 0; first < n; first += 8) {
        const std::size_t count = std::min<std::size_t>(8, n - first);
        const std::uint32_t* i0 = query.index0.data() + first;
        const std::uint32_t* i1 = query.index1.data() + first;
        float lower[8] = {}, upper[8] = {};
        for (int term = 0; term < terms; ++term) {
            const float w = weight[term];
            const float* b = base[term];
            for (std::size_t k = 0; k < count; ++k) {
                lower[k] += w * b[i0[k]];
                upper[k] += w * b[i1[k]];
            }
        }
        for (std::size_t k = 0; k < count; ++k) {
            out[first + k] = finish(lower[k] + query.weight1[first + k] * (upper[k] - lower[k]));
        }
    }
}

void RglBrdf::eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const {
    DirectionState st;
    if (!prepare(wi, wo, st)) {
        std::fill(out, out + query.size(), 0.f);
        return;
    }
    eval_data(st, query, out);
    if (m_jacobian) {
        const float sigma = m_sigma.eval(st.u_i, SliceBlend());
        const float factor = sigma > 0.f ? m_ndf.eval(st.u_h, SliceBlend()) / (4.f * sigma) : 0.f;
        for (std::size_t k = 0; k < query.size(); ++k) out[k] *= factor;
    }
}

float RglBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
    DirectionState st;
    if (!prepare(wi, wo, st)) return 0.f;
    const float lum_density = m_luminance.eval(st.xi, st.params);
    const float sin_theta_h = std::sqrt(st.wh.x * st.wh.x + st.wh.y * st.wh.y);
    // u-space to solid angle (2 pi^2 u sin theta) and half vector to wo (4 wi.wh); the 1e-6
    // floor at the pole is the reference readers' own.
    const float jacobian = clamp_low(2.f * kPi * kPi * st.u_h.x * sin_theta_h, 1e-6f) * 4.f * dot(st.wi, st.wh);
    return jacobian > 0.f ? st.vndf_density * lum_density / jacobian : 0.f;
}

bool RglBrdf::sample(const Vec3& wi_in, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                     float* weight) const {
    if (weight) std::fill(weight, weight + query.size(), 0.f);
    s = BrdfSample();
    if (!(wi_in.z > 0.f)) return false;
    const Fold fold = fold_for(m_reduction, wi_in);
    DirectionState st;
    st.wi = fold.apply(wi_in);
    st.theta_i = elevation(st.wi);
    st.phi_i = azimuth(st.wi);
    st.u_i = {theta_to_u(st.theta_i), phi_to_u(st.phi_i)};
    st.params = blend_two_parameters(m_phi_i.size(), locate_on_grid(m_phi_i, st.phi_i), m_theta_i.size(),
                                     locate_on_grid(m_theta_i, st.theta_i));

    // Uniform -> luminance warp -> data square -> VNDF warp -> half vector (readers swap u).
    float lum_density = 0.f, vndf_density = 0.f;
    st.xi = m_luminance.sample({u.y, u.x}, st.params, &lum_density);
    st.u_h = m_vndf.sample(st.xi, st.params, &vndf_density);
    const float theta_h = u_to_theta(st.u_h.x);
    float phi_h = u_to_phi(st.u_h.y);
    if (m_isotropic) phi_h += st.phi_i;
    st.wh = spherical_direction(theta_h, phi_h);
    const float cos_d = dot(st.wi, st.wh);
    const Vec3 wo = st.wh * (2.f * cos_d) - st.wi;
    if (!(wo.z > 0.f) || !(cos_d > 0.f)) return false;

    const float jacobian = clamp_low(2.f * kPi * kPi * st.u_h.x * std::sin(theta_h), 1e-6f) * 4.f * cos_d;
    const float pdf = vndf_density * lum_density / jacobian;
    if (!(pdf > 0.f) || !std::isfinite(pdf)) return false;
    s.wo = fold.apply(wo);  // the flips are their own inverse
    s.pdf = pdf;
    if (weight) {
        eval_data(st, query, weight);
        float factor = 1.f / pdf;
        if (m_jacobian) {
            const float sigma = m_sigma.eval(st.u_i, SliceBlend());
            factor = sigma > 0.f ? m_ndf.eval(st.u_h, SliceBlend()) / (4.f * sigma * pdf) : 0.f;
        }
        for (std::size_t k = 0; k < query.size(); ++k) weight[k] *= factor;
    }
    return true;
}

}  // namespace npf
