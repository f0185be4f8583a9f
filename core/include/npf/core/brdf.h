// The one BRDF interface every material source implements: measured RGL and MERL files,
// analytic models and fitted NPF materials. Every tool (`info`, `eval`, `convert`, `render`,
// `compare`) works on this interface and so on every source.
//
// Conventions, fixed project-wide:
//  - Local frame: z = surface normal, x = tangent (azimuth 0), y = bitangent. Directions are
//    unit vectors pointing away from the surface.
//  - `wi` is the direction a query is conditioned on: the RGL files' "incident" direction and
//    the camera-side direction of a renderer (Mitsuba's si.wi, pbrt's wo). `wo` is the other
//    direction, the one `sample` draws. Measured data need not be reciprocal, so order matters.
//    Closure-style APIs that name the two the other way round convert at their edge.
//  - Values are f_r(wi, wo) cos(theta_o) in 1/sr, the "projected" BRDF that RGL files store
//    and Mitsuba's eval returns. Divide by wo.z for f_r.
//  - Angles in radians, wavelengths in nanometres.
//  - Either direction at or below the horizon gives 0 (one-sided materials) and a pdf of 0.
//
// Implementations are immutable after loading, so one object may be used from many threads.
// eval/pdf/sample do not throw and do not allocate.
#pragma once

#include <npf/core/channels.h>
#include <npf/core/vec.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace npf {

// The largest |value| a material file may store (f_r, f_r cos or a table of them, in 1/sr).
// A perfect mirror sampled over 1e-6 sr is 1e6; squares and sums of values must stay finite in
// float (fit weights, error sums, albedo estimates). Readers reject larger values as corrupt, so
// that a finite but absurd table (3e38) cannot turn into infinities and NaNs downstream.
inline constexpr double kMaxMaterialValue = 1e12;

// What a material can produce, not only what it stores: every reader computes from its tables, when
// it opens a file, an upper bound of f_r cos(theta_i) cos(theta_o) over all direction pairs and
// channels (BrdfInfo::value_bound; products of table values, so that five factors each under the
// cap cannot multiply to 6e59). This projected form, rather than f_r or f_r cos(theta_o), because it
// is finite for every physical material, the paper's model with G open at the horizon included
// (there f_r itself grows like 1 / cos at grazing angles). A material whose bound is not finite or
// is above kMaxMaterialValue is refused (check_value_bound), so that no evaluation, sample, render
// or albedo of an accepted material can overflow.
//
// Throws npf::Error naming `source` when `bound` is not finite or above kMaxMaterialValue;
// `terms` says which tables' product it is ("rho_s x D x F x G x G").
void check_value_bound(const std::string& source, double bound, const std::string& terms);

struct BrdfInfo {
    std::string format;       // "rgl", "merl", ...
    std::string path;         // where it was read from, empty for in-memory materials
    std::string description;  // the file's own description, if any
    bool isotropic = true;
    Channels channels;        // what the source stores (RGB, or its wavelengths)
    std::uint64_t file_bytes = 0;
    // An upper bound of f_r cos(theta_i) cos(theta_o) in 1/sr over all pairs and channels, from the
    // tables (see kMaxMaterialValue); at most kMaxMaterialValue for anything a reader accepted.
    double value_bound = 0.0;
    // Format-specific facts for `npf info`, in display order (grid sizes, flags, ...).
    std::vector<std::pair<std::string, std::string>> details;
};

struct BrdfSample {
    Vec3 wo;          // the sampled direction
    float pdf = 0.f;  // solid-angle density of wo
};

class Brdf {
public:
    virtual ~Brdf() = default;

    virtual const BrdfInfo& info() const = 0;

    // Writes query.size() values of f_r(wi, wo) cos(theta_o) to `out`.
    virtual void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query,
                          float* out) const = 0;

    // Solid-angle density with which `sample` draws wo given wi.
    virtual float pdf(const Vec3& wi, const Vec3& wo) const = 0;

    // Draws wo given wi from a uniform point `u` in [0,1)^2. On success fills `s` and, when
    // `weight` is not null, writes query.size() values of f_r cos(theta_o) / pdf. Returns false
    // (and leaves weight at 0) when no direction above the horizon results.
    virtual bool sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                        float* weight) const = 0;

    // The directional albedo at wi (directional_albedo.h) by a deterministic quadrature the
    // material integrates on its own tables, for query.size() channels; false when it has none,
    // and npf::directional_albedo then uses its Monte Carlo estimator. Called only with wi
    // strictly above the horizon. A factor texture in memory answers (NpfBrdf).
    virtual bool albedo_by_quadrature(const Vec3& wi, const ChannelQuery& query, std::vector<double>& albedo) const;

    // The request resolved against this source's stored channels (throws npf::Error when the
    // source cannot provide it). Sources that compute any channel (analytic models) override.
    virtual ChannelQuery query(const Channels& requested) const;
    // All stored channels, as stored.
    ChannelQuery native_query() const { return query(info().channels); }
};

}  // namespace npf
