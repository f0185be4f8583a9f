#include <npf/fit/fit_error.h>

#include <npf/core/vec.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace npf {

BrdfSpaceError brdf_space_error(const Brdf& source, const Channels& channels, const ModelEvaluation& model, int pairs,
                                double max_theta_degrees, unsigned seed) {
    const ChannelQuery query = source.query(channels);
    const std::size_t C = query.size();
    std::vector<float> truth(C);
    std::vector<double> fit(C), num(C, 0.0), den(C, 0.0);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const double zmin = std::cos(max_theta_degrees * kPiD / 180.0);
    auto direction = [&] {  // cosine-weighted on the cap: z^2 uniform in [zmin^2, 1]
        const double z = std::sqrt(zmin * zmin + (1.0 - zmin * zmin) * uni(rng)), phi = 2.0 * kPiD * uni(rng);
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        return Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
    };
    for (int i = 0; i < pairs; ++i) {
        const Vec3 wi = direction(), wo = direction();
        source.eval_cos(wi, wo, query, truth.data());
        model(wi, wo, fit.data());
        for (std::size_t c = 0; c < C; ++c) {
            const double t = truth[c] / wo.z;
            num[c] += (fit[c] - t) * (fit[c] - t);
            den[c] += t * t;
        }
    }
    BrdfSpaceError e;
    double num_all = 0.0, den_all = 0.0;
    for (std::size_t c = 0; c < C; ++c) {
        const double r = den[c] > 0.0 ? std::sqrt(num[c] / den[c]) : (num[c] > 0.0 ? INFINITY : 0.0);
        e.relative_rms.push_back(r);
        e.mean_relative_rms += r / double(C);
        e.max_relative_rms = std::max(e.max_relative_rms, r);
        num_all += num[c];
        den_all += den[c];
    }
    e.overall_relative_rms = den_all > 0.0 ? std::sqrt(num_all / den_all) : 0.0;
    return e;
}

}  // namespace npf
