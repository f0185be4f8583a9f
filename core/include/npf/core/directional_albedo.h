// Directional albedo of any material, a diagnostic of where a conversion gains or loses energy:
//   a(wi) = integral over the hemisphere of f_r(wi, wo) cos(theta_o) d(wo),
// the share of light from wi that is reflected (wi the conditioned, camera-side direction).
//
// One entry point for every report (npf albedo, npf convert's energy check and metadata, npf
// edit's check and cap): a material that integrates its own tables deterministically answers
// through Brdf::albedo_by_quadrature (a factor texture in memory: shading/npf_albedo.h, within
// about 2e-3); every other material goes to the Monte Carlo estimator below.
//
// Monte Carlo estimator (docs/albedo.md): two strategies, each with one point in every cell of an N x N grid
// over [0,1)^2, combined by multiple importance sampling with the balance heuristic:
//  1. the material's own `sample` (its density s.pdf), which follows sharp lobes;
//  2. cosine-weighted hemisphere directions (density cos(theta_o) / pi), which reach every
//     direction, so that energy a poor or partial sampler never visits is still counted.
// Each of the 2 N^2 directions contributes eval_cos(wi, wo) / (N^2 (p_material + p_cosine)),
// with p_material = pdf(wi, wo) for the cosine directions. The values integrated are always
// eval_cos (the material itself); the sampler only places the directions. The point in each cell
// is jittered by a fixed hash of the cell's index, not by a random generator (cell centres alias
// with tabulated materials' grids), and sums run in double in a fixed order: results are
// bit-identical run to run, on any number of threads.
#pragma once

#include <npf/core/brdf.h>

#include <vector>

namespace npf {

struct DirectionalAlbedoOptions {
    // N: N x N cells per strategy (2 N^2 directions and evaluations), 2..65536. The default
    // keeps the estimate within about 0.1 % on rough and mirror-sharp lobes alike, grazing views
    // included (measured in docs/albedo.md), so that a 1 % difference stands out.
    int samples = 128;
    // false: the Monte Carlo estimator even where the material has a quadrature (to check one
    // against the other).
    bool material_quadrature = true;
};

// a(wi) per channel of `query` (query.size() values). Throws npf::Error when wi is not a finite
// direction strictly above the horizon (wi.z <= 0 has no albedo under the one-sided convention)
// or when options.samples is outside 2..65536. When `standard_error` is not null it receives, per
// channel, the collapsed-strata estimate of the standard error (pairs of neighbouring cells;
// slightly conservative for smooth integrands; measured errors stayed below 2.6 of it), or 0 per
// channel when the material's quadrature answered (deterministic, no sampling error).
std::vector<double> directional_albedo(const Brdf& brdf, const Vec3& wi, const ChannelQuery& query,
                                       const DirectionalAlbedoOptions& options = {},
                                       std::vector<double>* standard_error = nullptr);

// The one set of view angles (degrees) every albedo report uses: dense towards grazing, where
// conversions and measurements disagree most and fits gain light. npf albedo, npf convert's
// energy check (the albedo_max metadata) and npf edit's check after each step measure here.
std::vector<double> default_albedo_thetas();
// Azimuths (degrees) for a material: {0} when isotropic, else kAnisotropicAlbedoAzimuths evenly
// spread over the full circle (0, 90, 180, 270): measured files need not be symmetric.
constexpr int kAnisotropicAlbedoAzimuths = 4;
std::vector<double> default_albedo_azimuths(bool isotropic);

struct AlbedoTableOptions {
    std::vector<double> theta_deg = default_albedo_thetas();  // each in [0, 90)
    // Empty: default_albedo_azimuths(brdf.info().isotropic). Any finite values otherwise.
    std::vector<double> phi_deg;
    DirectionalAlbedoOptions estimator;
    // Directions are shared out over this many threads (core/parallel.h); 0: all cores. The
    // results do not depend on it.
    int threads = 0;
};

struct AlbedoRow {
    double theta_deg = 0.0, phi_deg = 0.0;
    std::vector<double> albedo;          // per channel of the query
    std::vector<double> standard_error;  // per channel, see directional_albedo
    bool by_quadrature = false;          // the material's quadrature answered, not Monte Carlo
};

// One row per (theta, phi), theta outermost, in the order given: anisotropic materials are
// reported per azimuth, not averaged, so that a lobe lost along one direction shows. Throws
// npf::Error for a theta outside [0, 90), a non-finite angle, an empty theta list or samples
// outside 2..65536.
std::vector<AlbedoRow> directional_albedo_table(const Brdf& brdf, const ChannelQuery& query,
                                                const AlbedoTableOptions& options = {});

// The energy error's one rule (npf convert's energy check, npf albedo --against): the signed
// relative difference of a material's albedo from a reference's, (material - reference) /
// reference; where the reference is black, 0 if the material is too, else +-infinity (any light
// there is all error).
double relative_albedo_difference(double material, double reference);

// The largest |relative_albedo_difference| over two tables of the same views and channels (a NaN
// counts as the largest), with where it is; `relative` is signed.
struct AlbedoDifference {
    double relative = 0.0;
    std::size_t row = 0, channel = 0;
};
AlbedoDifference largest_albedo_difference(const std::vector<AlbedoRow>& material, const std::vector<AlbedoRow>& reference);

// The largest albedo of a table over its rows and channels, and where (the first on ties);
// all 0 for an empty table.
struct AlbedoPeak {
    double max = 0.0, theta_deg = 0.0, phi_deg = 0.0;
    std::size_t channel = 0;
};
AlbedoPeak largest_albedo(const std::vector<AlbedoRow>& rows);

}  // namespace npf
