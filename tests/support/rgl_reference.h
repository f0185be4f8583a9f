// Shared by the RglBrdf reference tests (test_rgl_reference*.cpp, test_rgl_extremes.cpp): the
// materials (the five real database files and the synthetic kinds, each loaded once per process
// with its NaiveRgl twin), the direction pairs they are compared on, and the comparison of the
// reader against NaiveRgl with its float-conditioning allowance.
#pragma once

#include "naive_rgl.h"
#include "synthetic_rgl.h"

#include <npf/core/vec.h>
#include <npf/materials/rgl_brdf.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace npf::testing::rgl_reference {

constexpr double kPi = 3.14159265358979323846;

const std::vector<std::string>& real_materials();


// SplitMix64: tiny, deterministic on every platform.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : m_state(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (m_state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
    float uniform_float() { return static_cast<float>(next() >> 40) * 0x1.0p-24f; }  // [0, 1)

private:
    std::uint64_t m_state;
};

inline Vec3d to_d(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 to_f(const Vec3d& v);
// Unit direction with the given z (cosine of the elevation) and azimuth.
Vec3 direction_with_z(double z, double phi);
Vec3 uniform_hemisphere(Rng& rng);
// z log-uniform in [lo, hi].
Vec3 near_horizon(Rng& rng, double lo, double hi);
inline Vec3 mirror(const Vec3& w) { return {-w.x, -w.y, w.z}; }
std::string str(const Vec3& v);

struct Pair {
    Vec3 wi, wo;
};

// The mix of brief (b): 20% with one direction within 1e-6..1e-3 of the horizon, 10% with
// one direction exactly the normal, 10% mirror pairs, the rest uniform on the hemisphere.
std::vector<Pair> comparison_pairs(std::size_t count, std::uint64_t seed);

// relative `rel_tol` where |want| exceeds `tiny`, absolute rel_tol * tiny below.
//
// A float32 implementation cannot do better than the conditioning of the value with respect to
// rounding of its internal coordinates (xi, u_h: float steps of 6e-8 near 1, CDFs stored as
// float), and near the zero end of a steep bilinear ramp that conditioning exceeds 1e-4
// relative (e.g. data falling 100x over the last cell of the data grid). Sampling also inherits
// the cancellation of the published Ramp formula in float when |a - b| is just above
// 1e-4 (a + b) (NaivePerturbation::ramp). So a value outside the plain tolerance is still
// accepted when the difference is within the spread NaiveRgl itself shows when those
// coordinates move by kConditioningStep (and the ramps by 2 float errors); such values are
// counted (`conditioned`) and must stay rare (<= 1%).
constexpr double kConditioningStep = 2.5e-7;  // about 4 float steps at 1

struct Agreement {
    explicit Agreement(std::string name) : what(std::move(name)) {}
    std::string what;
    double rel_tol = 1e-4;
    double tiny = 0.0;
    double max_rel = 0.0;       // over |want| > tiny
    double max_abs_tiny = 0.0;  // over |want| <= tiny
    std::size_t count = 0, bad = 0, conditioned = 0;
    std::string first_bad;

    // `spread()` gives the conditioning allowance, `context()` the message; both are called
    // only when needed. Returns false (and counts) on a disagreement.
    template <class Spread, class Context>
    bool add(double got, double want, Spread&& spread, Context&& context) {
        ++count;
        const double diff = std::fabs(got - want);
        double limit;
        if (std::fabs(want) > tiny) {
            max_rel = std::max(max_rel, diff / std::fabs(want));
            limit = rel_tol * std::fabs(want);
        } else {
            max_abs_tiny = std::max(max_abs_tiny, diff);
            limit = rel_tol * tiny;
        }
        if (std::isfinite(got) && diff <= limit) return true;
        if (std::isfinite(got) && diff <= limit + spread()) {
            ++conditioned;
            return true;
        }
        if (bad == 0) {
            std::ostringstream s;
            s.precision(9);
            s << what << ": got " << got << ", want " << want << " (allowance " << limit << " + "
              << spread() << ") at " << context();
            first_bad = s.str();
        }
        ++bad;
        return false;
    }
    template <class Context>
    bool add(double got, double want, Context&& context) {
        return add(got, want, [] { return 0.0; }, context);
    }

    std::string summary() const {
        std::ostringstream s;
        s << what << ": " << count << " values, max rel " << max_rel << " (|v| > " << tiny
          << "), max abs " << max_abs_tiny << " below; " << conditioned
          << " within float conditioning only; " << bad << " outside tolerance";
        if (bad) s << "; first: " << first_bad;
        return s.str();
    }
};

// The perturbations +-kConditioningStep of xi.x, xi.y, u_h.x, u_h.y and, with `sampling`, of

// The perturbations +-kConditioningStep of xi.x, xi.y, u_h.x, u_h.y and, with `sampling`, of
// the two uniform numbers, and +-2 float rounding errors in the Ramp inversions.
std::vector<NaivePerturbation> conditioning_perturbations(bool sampling);

double seconds_since(std::chrono::steady_clock::time_point t0);

struct Material {
    std::string name, path;
    std::unique_ptr<npf::RglBrdf> brdf;
    std::unique_ptr<NaiveRgl> naive;
};

// The real file, loaded once per process; nullptr (and the path in `missing`) if absent.
const Material* real_material(const std::string& name, std::string& missing);

struct SyntheticKind {
    std::string name;
    SyntheticRglSpec spec;
};
std::vector<SyntheticKind> synthetic_kinds();
// Written and loaded once per process.
const Material& synthetic_material(const SyntheticKind& kind);
const Material& synthetic_material(const std::string& name);

struct Comparison {
    Agreement eval{"eval_cos"}, pdf{"pdf"}, sample_wo{"sample wo"}, sample_pdf{"sample pdf"},
        sample_weight{"sample weight"};
    std::size_t exact_mirror_pdfs_skipped = 0;  // see RglReferenceReal.PdfAtExactMirrorPairs
    std::size_t sample_success = 0;
    std::size_t sample_mismatch_grazing = 0;  // one succeeded with wo.z < 1e-4, the other failed
    std::size_t sample_mismatch = 0;          // any other success mismatch
    std::string first_sample_mismatch;
    double seconds = 0.0;

    bool ok() const {
        return eval.bad == 0 && pdf.bad == 0 && sample_wo.bad == 0 && sample_pdf.bad == 0 &&
               sample_weight.bad == 0 && sample_mismatch == 0;
    }
    std::size_t conditioned() const {
        return eval.conditioned + pdf.conditioned + sample_wo.conditioned +
               sample_pdf.conditioned + sample_weight.conditioned;
    }
    std::size_t count() const {
        return eval.count + pdf.count + sample_wo.count + sample_pdf.count + sample_weight.count;
    }
    std::string summary() const {
        std::ostringstream s;
        s << "  " << eval.summary() << "\n  " << pdf.summary() << "\n  " << sample_wo.summary()
          << "\n  " << sample_pdf.summary() << "\n  " << sample_weight.summary() << "\n  "
          << "samples: " << sample_success << " succeeded in both, " << sample_mismatch_grazing
          << " grazing success mismatches, " << sample_mismatch << " other mismatches"
          << (sample_mismatch ? "; first: " + first_sample_mismatch : std::string()) << "\n  "
          << seconds << " s";
        return s.str();
    }
};

double max_abs(const std::vector<double>& v);
inline bool is_exact_mirror(const Pair& p) {
    return p.wo.x == -p.wi.x && p.wo.y == -p.wi.y && p.wo.z == p.wi.z;
}

// Evaluates RglBrdf and NaiveRgl on `pairs` (and samples with one u per pair) and compares.
// `wavelengths` empty: the stored channels; else those wavelengths (spectral files).
// The pdf of exact mirror pairs is left out when `skip_exact_mirror_pdf` (a known
// disagreement with its own test).
Comparison compare_with_naive(const Material& m, const std::vector<Pair>& pairs,
                              const std::vector<double>& wavelengths, std::uint64_t seed,
                              bool skip_exact_mirror_pdf = true);

// Prints the comparison's figures and expects it to agree, with values that agree only within
// their float conditioning and grazing sample mismatches rare.
void expect_agreement(const Comparison& c, const std::string& label);

}  // namespace npf::testing::rgl_reference
