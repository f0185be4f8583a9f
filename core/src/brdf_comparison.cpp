#include <npf/core/brdf_comparison.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace npf {

BrdfComparison::BrdfComparison(std::size_t channels, double max_theta_degrees)
    : m_channels(channels), m_min_cos(std::cos(max_theta_degrees * kPiD / 180.0)),
      m_min_cos_60(std::max(m_min_cos, 0.5)), m_num(channels, 0.0), m_den(channels, 0.0) {}

void BrdfComparison::add(const Vec3& wi, const Vec3& wo, const float* test, const float* reference) {
    const std::size_t index = m_pairs++;
    if (!(double(wi.z) >= m_min_cos && double(wo.z) >= m_min_cos)) return;
    ++m_used;
    const bool within_60 = double(wi.z) >= m_min_cos_60 && double(wo.z) >= m_min_cos_60;
    for (std::size_t c = 0; c < m_channels; ++c) {
        const double t = test[c], r = reference[c], d = t - r;
        m_num[c] += d * d;
        m_den[c] += r * r;
        if (within_60) m_num_60 += d * d, m_den_60 += r * r;
        if (std::fabs(d) > m_worst_difference) {
            m_worst_difference = std::fabs(d);
            m_worst = {index, c, t, r, wi, wo};
        }
    }
}

BrdfComparisonResult BrdfComparison::result() const {
    const auto ratio = [](double num, double den) { return den > 0.0 ? std::sqrt(num / den) : (num > 0.0 ? INFINITY : 0.0); };
    BrdfComparisonResult r;
    r.pairs = m_pairs;
    r.used = m_used;
    double num = 0.0, den = 0.0;
    for (std::size_t c = 0; c < m_channels; ++c) {
        r.channel_relative_rms.push_back(ratio(m_num[c], m_den[c]));
        num += m_num[c];
        den += m_den[c];
    }
    r.relative_rms = ratio(num, den);
    r.relative_rms_60 = ratio(m_num_60, m_den_60);
    r.worst = m_worst;
    return r;
}

BrdfComparisonResult compare_brdfs(const Brdf& test, const Brdf& reference, const Channels& channels,
                                   const std::function<bool(DirectionPair&)>& next, double max_theta_degrees,
                                   bool keep_negative) {
    ChannelQuery tq = test.query(channels), rq = reference.query(channels);
    tq.clamp_negative = rq.clamp_negative = !keep_negative;
    std::vector<float> t(tq.size()), r(rq.size());
    BrdfComparison comparison(tq.size(), max_theta_degrees);
    DirectionPair p;
    while (next(p)) {
        test.eval_cos(p.wi, p.wo, tq, t.data());
        reference.eval_cos(p.wi, p.wo, rq, r.data());
        comparison.add(p.wi, p.wo, t.data(), r.data());
    }
    return comparison.result();
}

BrdfComparisonResult compare_brdfs(const Brdf& test, const Brdf& reference, const Channels& channels,
                                   const std::vector<DirectionPair>& pairs, double max_theta_degrees, bool keep_negative) {
    std::size_t i = 0;
    return compare_brdfs(test, reference, channels, [&](DirectionPair& p) {
        if (i == pairs.size()) return false;
        p = pairs[i++];
        return true;
    }, max_theta_degrees, keep_negative);
}

namespace {

// A fixed stream of numbers in [0, 1): SplitMix64, the same everywhere.
class FixedNumbers {
public:
    double next() {
        std::uint64_t z = (m_state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        z ^= z >> 31;
        return double(z >> 11) * (1.0 / 9007199254740992.0);
    }

private:
    std::uint64_t m_state = 0x6e7066;  // "npf"
};

Vec3 from_angles(double theta, double phi) {
    return Vec3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)));
}

}  // namespace

std::vector<DirectionPair> held_out_pairs() {
    FixedNumbers u;
    const double cap = 80.0 * kPiD / 180.0, zmin = std::cos(cap);
    const auto cosine_weighted = [&] {  // z^2 uniform in [zmin^2, 1]
        const double z = std::sqrt(zmin * zmin + (1.0 - zmin * zmin) * u.next());
        return from_angles(std::acos(std::min(1.0, z)), 2.0 * kPiD * u.next());
    };
    std::vector<DirectionPair> pairs;
    for (int i = 0; i < 100; ++i) {  // mirror pairs, incidence uniform in angle up to the cap
        const Vec3 wi = from_angles(cap * u.next(), 2.0 * kPiD * u.next());
        pairs.push_back({wi, Vec3(-wi.x, -wi.y, wi.z)});
    }
    for (int i = 0; i < 100; ++i) {  // near the mirror direction: within 10 degrees, inside the cap
        const double theta_i = cap * u.next(), phi_i = 2.0 * kPiD * u.next();
        const double theta_o = std::min(cap, std::max(0.0, theta_i + (u.next() - 0.5) * (20.0 * kPiD / 180.0)));
        const double phi_o = phi_i + kPiD + (u.next() - 0.5) * (20.0 * kPiD / 180.0);
        pairs.push_back({from_angles(theta_i, phi_i), from_angles(theta_o, phi_o)});
    }
    for (int i = 0; i < 300; ++i) {
        const Vec3 wi = cosine_weighted();
        pairs.push_back({wi, cosine_weighted()});
    }
    return pairs;
}

}  // namespace npf
