#include <npf/core/cosine_sampling.h>
#include <npf/core/directional_albedo.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/parallel.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace npf {

namespace {

constexpr double kDegToRad = kPiD / 180.0;

// splitmix64's finaliser: a fixed, well-mixed function of the cell index.
std::uint64_t mix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// A fixed position inside cell (i, j) of the n x n grid, different per strategy. Cell centres
// alias with the regular grids of tabulated materials (errors of 0.3 % that no error estimate
// sees); a fixed jitter turns that into honest noise, and the same hash keeps it deterministic.
Vec2 cell_point(int i, int j, int n, std::uint64_t strategy) {
    const std::uint64_t h = mix((strategy << 48) ^ (std::uint64_t(j) << 24) ^ std::uint64_t(i));
    const double a = double(h >> 40) * 0x1p-24, b = double((h >> 16) & 0xffffffu) * 0x1p-24;
    constexpr float kBelowOne = 0x1.fffffep-1f;
    return {std::min(float((i + a) / n), kBelowOne), std::min(float((j + b) / n), kBelowOne)};
}

bool usable_pdf(float p) { return p > 0.f && std::isfinite(p); }


}  // namespace

namespace {

// directional_albedo, and whether the material's quadrature answered.
std::vector<double> estimate(const Brdf& brdf, const Vec3& wi, const ChannelQuery& query,
                             const DirectionalAlbedoOptions& options, std::vector<double>* standard_error,
                             bool& by_quadrature) {
    if (!(wi.z > 0.f) || !std::isfinite(wi.x) || !std::isfinite(wi.y) || !std::isfinite(wi.z))
        throw Error("directional albedo", "wi must point above the horizon (wi.z > 0), got (" + number_text(wi.x) +
                                              ", " + number_text(wi.y) + ", " + number_text(wi.z) + ")");
    if (options.samples < 2 || options.samples > 65536)
        throw Error("directional albedo", "samples must be in 2..65536, got " + std::to_string(options.samples));

    const std::size_t channels = query.size();
    std::vector<double> exact;
    by_quadrature = options.material_quadrature && brdf.albedo_by_quadrature(wi, query, exact);
    if (by_quadrature) {
        if (standard_error) standard_error->assign(channels, 0.0);
        return exact;
    }
    const int n = options.samples;
    const double cells = double(n) * double(n);
    std::vector<float> f(channels);
    std::vector<double> sum(channels, 0.0), cell(channels), previous(channels), squared_pair_diff(channels, 0.0);
    std::size_t pairs = 0;
    BrdfSample s;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            std::fill(cell.begin(), cell.end(), 0.0);
            // Balance heuristic: each direction adds f / (p_material + p_cosine), whichever
            // strategy drew it. Strategy 1, the material's sampler: s.pdf is the density these
            // directions were drawn with; failed draws (below the horizon, ...) add nothing.
            if (brdf.sample(wi, cell_point(i, j, n, 1), query, s, nullptr) && s.wo.z > 0.f && usable_pdf(s.pdf)) {
                brdf.eval_cos(wi, s.wo, query, f.data());
                const double p1 = s.pdf, p2 = double(s.wo.z) / kPiD;
                const double factor = 1.0 / (p1 + p2);
                for (std::size_t c = 0; c < channels; ++c) cell[c] += double(f[c]) * factor;
            }
            // Strategy 2: cosine-weighted directions, which reach what the sampler misses.
            const Vec3 wo = cosine_hemisphere_direction(cell_point(i, j, n, 2));
            if (wo.z > 0.f) {
                const float p = brdf.pdf(wi, wo);
                const double p1 = usable_pdf(p) ? double(p) : 0.0, p2 = double(wo.z) / kPiD;
                const double factor = 1.0 / (p1 + p2);
                brdf.eval_cos(wi, wo, query, f.data());
                for (std::size_t c = 0; c < channels; ++c) cell[c] += double(f[c]) * factor;
            }
            for (std::size_t c = 0; c < channels; ++c) sum[c] += cell[c];
            // Collapsed strata: consecutive cells (the same row, neighbours in u.x) as pairs.
            const std::size_t k = std::size_t(j) * std::size_t(n) + std::size_t(i);
            if (k % 2 == 0) {
                previous = cell;
            } else {
                for (std::size_t c = 0; c < channels; ++c) {
                    const double d = cell[c] - previous[c];
                    squared_pair_diff[c] += d * d;
                }
                ++pairs;
            }
        }
    }
    std::vector<double> albedo(channels);
    for (std::size_t c = 0; c < channels; ++c) albedo[c] = sum[c] / cells;
    if (standard_error) {
        // E[(Y_a - Y_b)^2] >= Var Y_a + Var Y_b: the per-cell variance, then that of the mean.
        standard_error->assign(channels, 0.0);
        for (std::size_t c = 0; c < channels; ++c)
            (*standard_error)[c] = std::sqrt(squared_pair_diff[c] / (2.0 * double(pairs)) / cells);
    }
    return albedo;
}

}  // namespace

std::vector<double> directional_albedo(const Brdf& brdf, const Vec3& wi, const ChannelQuery& query,
                                       const DirectionalAlbedoOptions& options, std::vector<double>* standard_error) {
    bool by_quadrature = false;
    return estimate(brdf, wi, query, options, standard_error, by_quadrature);
}

std::vector<double> default_albedo_thetas() { return {0, 10, 20, 30, 40, 50, 60, 70, 80, 85, 87, 89}; }

std::vector<double> default_albedo_azimuths(bool isotropic) {
    if (isotropic) return {0.0};
    std::vector<double> phi;
    for (int k = 0; k < kAnisotropicAlbedoAzimuths; ++k) phi.push_back(360.0 * k / kAnisotropicAlbedoAzimuths);
    return phi;
}

std::vector<AlbedoRow> directional_albedo_table(const Brdf& brdf, const ChannelQuery& query,
                                                const AlbedoTableOptions& options) {
    if (options.theta_deg.empty()) throw Error("directional albedo", "no view angles (theta) given");
    for (double t : options.theta_deg) {
        if (!std::isfinite(t) || t < 0.0 || t >= 90.0)
            throw Error("directional albedo", "view angle theta " + number_text(t) + " is outside [0, 90) degrees");
    }
    const std::vector<double> phis =
        options.phi_deg.empty() ? default_albedo_azimuths(brdf.info().isotropic) : options.phi_deg;
    for (double p : phis) {
        if (!std::isfinite(p)) throw Error("directional albedo", "azimuth phi is not a finite number");
    }
    if (options.estimator.samples < 2 || options.estimator.samples > 65536)
        throw Error("directional albedo", "samples must be in 2..65536, got " + std::to_string(options.estimator.samples));

    std::vector<AlbedoRow> rows;
    for (double t : options.theta_deg) {
        for (double p : phis) {
            AlbedoRow row;
            row.theta_deg = t;
            row.phi_deg = p;
            rows.push_back(row);
        }
    }
    auto compute = [&](AlbedoRow& row) {
        const Vec3 wi = spherical_direction(float(row.theta_deg * kDegToRad), float(row.phi_deg * kDegToRad));
        row.albedo = estimate(brdf, wi, query, options.estimator, &row.standard_error, row.by_quadrature);
    };

    // Whole directions per item: each row is summed by one thread in a fixed order, so the
    // results are the same for any thread count.
    parallel_for(rows.size(), [&](std::size_t k) { compute(rows[k]); }, options.threads);
    return rows;
}

AlbedoPeak largest_albedo(const std::vector<AlbedoRow>& rows) {
    AlbedoPeak peak;
    bool first = true;
    for (const AlbedoRow& row : rows) {
        for (std::size_t c = 0; c < row.albedo.size(); ++c) {
            if (first || row.albedo[c] > peak.max) {
                peak.max = row.albedo[c];
                peak.theta_deg = row.theta_deg;
                peak.phi_deg = row.phi_deg;
                peak.channel = c;
                first = false;
            }
        }
    }
    return peak;
}

double relative_albedo_difference(double material, double reference) {
    if (reference == 0.0) return material == 0.0 ? 0.0 : (material > 0.0 ? INFINITY : -INFINITY);
    return (material - reference) / reference;
}

AlbedoDifference largest_albedo_difference(const std::vector<AlbedoRow>& material, const std::vector<AlbedoRow>& reference) {
    AlbedoDifference worst;
    bool first = true;
    for (std::size_t r = 0; r < std::min(material.size(), reference.size()); ++r) {
        for (std::size_t c = 0; c < std::min(material[r].albedo.size(), reference[r].albedo.size()); ++c) {
            const double d = relative_albedo_difference(material[r].albedo[c], reference[r].albedo[c]);
            if (first || std::fabs(d) > std::fabs(worst.relative) || (std::isnan(d) && !std::isnan(worst.relative))) {
                worst = {d, r, c};
                first = false;
            }
        }
    }
    return worst;
}

}  // namespace npf
