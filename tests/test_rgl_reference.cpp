// RglBrdf checked against references that do not share its code:
//  - golden values of f_r cos computed by the RGL group's own loader (powitacq_rgb, float32,
//    negatives clamped) for the five real database files (RglReferenceGolden);
//  - NaiveRgl, a slow double-precision re-implementation of the published algorithm
//    (tests/support/naive_rgl.h), on the real files and on synthetic files of every kind the
//    reader supports (RglReferenceReal, RglReferenceSynthetic);
//  - symmetry facts that follow from the format (RglReferenceSymmetry);
//  - numerical extremes: no NaN, Inf or negative values anywhere over 1e6 pairs (RglExtremes).
#include "naive_rgl.h"
#include "synthetic_rgl.h"

#include <npf/materials/rgl_brdf.h>
#include <npf/core/brdf.h>
#include <npf/core/channels.h>
#include <npf/core/vec.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using npf::Vec2;
using npf::Vec3;
using npf::testing::NaiveRgl;
using npf::testing::Vec3d;

constexpr double kPi = 3.14159265358979323846;

const std::vector<std::string>& real_materials() {
    static const std::vector<std::string> names = {"acrylic_felt_green_rgb", "cg_sunflower_rgb",
                                                   "ilm_l3_37_metallic_rgb", "paper_white_rgb",
                                                   "vch_golden_yellow_rgb"};
    return names;
}

// ---- Small helpers --------------------------------------------------------------------------

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

Vec3d to_d(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 to_f(const Vec3d& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

// Unit direction with the given z (cosine of the elevation) and azimuth.
Vec3 direction_with_z(double z, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    return to_f({s * std::cos(phi), s * std::sin(phi), z});
}

Vec3 uniform_hemisphere(Rng& rng) {
    const double z = rng.uniform();
    return direction_with_z(z, 2.0 * kPi * rng.uniform());
}

// z log-uniform in [lo, hi].
Vec3 near_horizon(Rng& rng, double lo, double hi) {
    const double z = lo * std::pow(hi / lo, rng.uniform());
    return direction_with_z(z, 2.0 * kPi * rng.uniform());
}

Vec3 mirror(const Vec3& w) { return {-w.x, -w.y, w.z}; }

std::string str(const Vec3& v) {
    std::ostringstream s;
    s.precision(9);
    s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return s.str();
}

struct Pair {
    Vec3 wi, wo;
};

// The mix of brief (b): 20% with one direction within 1e-6..1e-3 of the horizon, 10% with
// one direction exactly the normal, 10% mirror pairs, the rest uniform on the hemisphere.
std::vector<Pair> comparison_pairs(std::size_t count, std::uint64_t seed) {
    Rng rng(seed);
    std::vector<Pair> out;
    out.reserve(count);
    const Vec3 normal(0.f, 0.f, 1.f);
    for (std::size_t i = 0; i < count; ++i) {
        Pair p;
        const std::size_t kind = i % 10;
        if (kind < 2) {  // grazing
            p.wi = uniform_hemisphere(rng);
            p.wo = near_horizon(rng, 1e-6, 1e-3);
            if (rng.uniform() < 0.5) std::swap(p.wi, p.wo);
        } else if (kind == 2) {  // the normal
            p.wi = uniform_hemisphere(rng);
            p.wo = normal;
            if (rng.uniform() < 0.5) std::swap(p.wi, p.wo);
        } else if (kind == 3) {  // mirror pair
            p.wi = uniform_hemisphere(rng);
            p.wo = mirror(p.wi);
        } else {
            p.wi = uniform_hemisphere(rng);
            p.wo = uniform_hemisphere(rng);
        }
        out.push_back(p);
    }
    return out;
}

// Agreement of `got` (RglBrdf, float32) with `want` (NaiveRgl, double) over a set of values:
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
// the two uniform numbers, and +-2 float rounding errors in the Ramp inversions.
std::vector<npf::testing::NaivePerturbation> conditioning_perturbations(bool sampling) {
    std::vector<npf::testing::NaivePerturbation> out;
    for (int k = 0; k < (sampling ? 14 : 8); ++k) {
        npf::testing::NaivePerturbation p;
        const double d = (k & 1) ? 1.0 : -1.0;
        if (k >= 12) {
            p.ramp = 2.0 * d;
            out.push_back(p);
            continue;
        }
        double* target[6] = {&p.xi_x, &p.xi_y, &p.uh_x, &p.uh_y, &p.u1, &p.u2};
        *target[k / 2] = d * kConditioningStep;
        out.push_back(p);
    }
    return out;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---- Loaded materials -----------------------------------------------------------------------

struct Material {
    std::string name, path;
    std::unique_ptr<npf::RglBrdf> brdf;
    std::unique_ptr<NaiveRgl> naive;
};

// The real file, loaded once per process; nullptr (and the path in `missing`) if absent.
const Material* real_material(const std::string& name, std::string& missing) {
    static std::map<std::string, std::unique_ptr<Material>> cache;
    const std::string relative = "rgl/" + name + ".bsdf";
    auto it = cache.find(name);
    if (it == cache.end()) {
        std::unique_ptr<Material> m;
        const std::string path = npf::testing::shared_data_file(relative);
        if (!path.empty()) {
            m = std::make_unique<Material>();
            m->name = name;
            m->path = path;
            m->brdf = npf::RglBrdf::load(path);
            m->naive = std::make_unique<NaiveRgl>(NaiveRgl::load(path));
        }
        it = cache.emplace(name, std::move(m)).first;
    }
    if (!it->second) missing = relative + " (shared data folder, NPF_SHARED_DATA overrides)";
    return it->second.get();
}

struct SyntheticKind {
    std::string name;
    npf::testing::SyntheticRglSpec spec;
};

std::vector<SyntheticKind> synthetic_kinds() {
    std::vector<SyntheticKind> out;
    auto add = [&](const std::string& name, auto&& edit) {
        SyntheticKind k;
        k.name = name;
        k.spec.description = "rgl reference test: " + name;
        edit(k.spec);
        out.push_back(k);
    };
    auto aniso = [](npf::testing::SyntheticRglSpec& s, int reduction) {
        s.phi_count = 5;
        s.reduction = reduction;
        s.alpha_x = 0.15f;
        s.alpha_y = 0.45f;
    };
    add("iso_rgb", [](auto&) {});
    add("iso_spectral", [](auto& s) { s.spectral = true; });
    add("iso_rgb_jacobian0", [](auto& s) { s.jacobian = false; });
    add("iso_phi_count2", [](auto& s) { s.phi_count = 2; });
    add("aniso_r1_rgb", [&](auto& s) { aniso(s, 1); });
    add("aniso_r2_rgb", [&](auto& s) { aniso(s, 2); });
    add("aniso_r4_rgb", [&](auto& s) { aniso(s, 4); });
    add("aniso_r1_spectral", [&](auto& s) { aniso(s, 1), s.spectral = true; });
    add("aniso_r2_spectral", [&](auto& s) { aniso(s, 2), s.spectral = true; });
    add("aniso_r4_spectral", [&](auto& s) { aniso(s, 4), s.spectral = true; });
    add("aniso_r2_jacobian0", [&](auto& s) { aniso(s, 2), s.jacobian = false; });
    return out;
}

const Material& synthetic_material(const SyntheticKind& kind) {
    static std::map<std::string, std::unique_ptr<Material>> cache;
    auto it = cache.find(kind.name);
    if (it == cache.end()) {
        static const std::string folder = npf::testing::temporary_folder("rgl_reference");
        auto m = std::make_unique<Material>();
        m->name = kind.name;
        m->path = npf::testing::write_synthetic_rgl(kind.spec, folder + "/" + kind.name + ".bsdf");
        m->brdf = npf::RglBrdf::load(m->path);
        m->naive = std::make_unique<NaiveRgl>(NaiveRgl::load(m->path));
        it = cache.emplace(kind.name, std::move(m)).first;
    }
    return *it->second;
}

const Material& synthetic_material(const std::string& name) {
    for (const auto& k : synthetic_kinds())
        if (k.name == name) return synthetic_material(k);
    throw std::runtime_error("no synthetic kind " + name);
}

// ---- Reader versus NaiveRgl -----------------------------------------------------------------

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

double max_abs(const std::vector<double>& v) {
    double m = 0.0;
    for (double x : v) m = std::max(m, std::fabs(x));
    return m;
}

bool is_exact_mirror(const Pair& p) { return p.wo.x == -p.wi.x && p.wo.y == -p.wi.y && p.wo.z == p.wi.z; }

// Evaluates RglBrdf and NaiveRgl on `pairs` (and samples with one u per pair) and compares.
// `wavelengths` empty: the stored channels; else those wavelengths (spectral files).
// The pdf of exact mirror pairs is left out when `skip_exact_mirror_pdf` (a known
// disagreement with its own test).
Comparison compare_with_naive(const Material& m, const std::vector<Pair>& pairs,
                              const std::vector<double>& wavelengths, std::uint64_t seed,
                              bool skip_exact_mirror_pdf = true) {
    const auto t0 = std::chrono::steady_clock::now();
    const npf::RglBrdf& brdf = *m.brdf;
    const NaiveRgl& naive = *m.naive;
    npf::ChannelQuery query;
    if (wavelengths.empty()) {
        query = brdf.native_query();
    } else {
        std::vector<float> wl(wavelengths.begin(), wavelengths.end());
        query = brdf.query(npf::Channels::spectral(wl));
    }
    // Both see exactly the same inputs: the float wavelengths and directions.
    std::vector<double> wl_d;
    for (float w : query.requested.wavelengths()) wl_d.push_back(w);
    const std::size_t nc = query.size();
    const auto perturbations = conditioning_perturbations(false);
    const auto sample_perturbations = conditioning_perturbations(true);

    const std::size_t n = pairs.size();
    std::vector<double> ev_got(n * nc), ev_want(n * nc), pdf_got(n), pdf_want(n);
    struct SampleResult {
        bool ok_got = false, ok_want = false;
        Vec3 wo_got;
        Vec3d wo_want;
        double pdf_got = 0, pdf_want = 0;
        std::vector<double> w_got, w_want;
        Vec2 u;
    };
    std::vector<SampleResult> sr(n);
    Rng rng(seed);
    std::vector<float> out(nc), weight(nc);
    for (std::size_t i = 0; i < n; ++i) {
        const Pair& p = pairs[i];
        brdf.eval_cos(p.wi, p.wo, query, out.data());
        const std::vector<double> want = naive.eval_cos(to_d(p.wi), to_d(p.wo), wl_d, true);
        for (std::size_t k = 0; k < nc; ++k) {
            ev_got[i * nc + k] = out[k];
            ev_want[i * nc + k] = want[k];
        }
        pdf_got[i] = brdf.pdf(p.wi, p.wo);
        pdf_want[i] = naive.pdf(to_d(p.wi), to_d(p.wo));

        SampleResult& s = sr[i];
        // Not u within ~1e-7 of 0 or 1: both clamp to [6e-8, 1 - 6e-8] (sec. 3.4), but there
        // the warps invert CDFs at their flat ends, where float and double legitimately land
        // on different sides of zero-density cells (RglExtremes covers those u).
        s.u = Vec2{rng.uniform_float(), rng.uniform_float()};
        npf::BrdfSample bs;
        s.ok_got = brdf.sample(p.wi, s.u, query, bs, weight.data());
        s.wo_got = bs.wo;
        s.pdf_got = bs.pdf;
        s.w_got.assign(weight.begin(), weight.end());
        s.ok_want = naive.sample(to_d(p.wi), s.u.x, s.u.y, s.wo_want, s.pdf_want, &s.w_want, wl_d,
                                 true);
    }

    Comparison c;
    c.eval.tiny = 1e-4 * max_abs(ev_want);
    c.pdf.tiny = 1e-4 * max_abs(pdf_want);
    std::vector<double> spdf, sweight;
    for (const auto& s : sr) {
        if (!(s.ok_got && s.ok_want)) continue;
        spdf.push_back(s.pdf_want);
        sweight.insert(sweight.end(), s.w_want.begin(), s.w_want.end());
    }
    c.sample_pdf.tiny = 1e-4 * max_abs(spdf);
    c.sample_weight.tiny = 1e-4 * max_abs(sweight);
    c.sample_wo.rel_tol = 1.0;  // wo is compared as |wo_got - wo_want| against 0 ...
    c.sample_wo.tiny = 1e-4;    // ... with an absolute tolerance of 1e-4

    for (std::size_t i = 0; i < n; ++i) {
        const Pair& p = pairs[i];
        const Vec3d wi = to_d(p.wi), wo = to_d(p.wo);
        auto where = [&] { return "wi = " + str(p.wi) + ", wo = " + str(p.wo); };
        // Conditioning of the naive values, computed on first need.
        std::vector<double> eval_spread;
        auto eval_spread_of = [&](std::size_t k) {
            if (eval_spread.empty()) {
                eval_spread.assign(nc, 0.0);
                for (const auto& pt : perturbations) {
                    const auto v = naive.eval_cos(wi, wo, wl_d, true, pt);
                    for (std::size_t j = 0; j < nc; ++j)
                        eval_spread[j] = std::max(eval_spread[j], std::fabs(v[j] - ev_want[i * nc + j]));
                }
            }
            return eval_spread[k];
        };
        for (std::size_t k = 0; k < nc; ++k)
            c.eval.add(ev_got[i * nc + k], ev_want[i * nc + k], [&] { return eval_spread_of(k); },
                       [&] { return where() + ", channel " + std::to_string(k); });
        if (skip_exact_mirror_pdf && is_exact_mirror(p)) {
            ++c.exact_mirror_pdfs_skipped;
        } else {
            c.pdf.add(pdf_got[i], pdf_want[i],
                      [&] {
                          double sp = 0.0;
                          for (const auto& pt : perturbations)
                              sp = std::max(sp, std::fabs(naive.pdf(wi, wo, pt) - pdf_want[i]));
                          return sp;
                      },
                      where);
        }

        const SampleResult& s = sr[i];
        auto swhere = [&] {
            std::ostringstream o;
            o.precision(9);
            o << "wi = " << str(p.wi) << ", u = (" << s.u.x << ", " << s.u.y
              << "), reader wo = " << str(s.wo_got) << ", naive wo = " << str(to_f(s.wo_want));
            return o.str();
        };
        if (s.ok_got && s.ok_want) {
            ++c.sample_success;
            // Spreads of the naive sample under the perturbations: wo, pdf, weights.
            bool have_spread = false;
            double sp_wo = 0.0, sp_pdf = 0.0;
            std::vector<double> sp_w(nc, 0.0);
            auto spreads = [&] {
                if (have_spread) return;
                have_spread = true;
                for (const auto& pt : sample_perturbations) {
                    Vec3d wo2;
                    double pdf2 = 0.0;
                    std::vector<double> w2;
                    if (!naive.sample(wi, s.u.x, s.u.y, wo2, pdf2, &w2, wl_d, true, pt)) continue;
                    sp_wo = std::max(sp_wo, std::sqrt((wo2.x - s.wo_want.x) * (wo2.x - s.wo_want.x) +
                                                      (wo2.y - s.wo_want.y) * (wo2.y - s.wo_want.y) +
                                                      (wo2.z - s.wo_want.z) * (wo2.z - s.wo_want.z)));
                    sp_pdf = std::max(sp_pdf, std::fabs(pdf2 - s.pdf_want));
                    for (std::size_t k = 0; k < nc; ++k)
                        sp_w[k] = std::max(sp_w[k], std::fabs(w2[k] - s.w_want[k]));
                }
            };
            const double dx = s.wo_got.x - s.wo_want.x, dy = s.wo_got.y - s.wo_want.y,
                         dz = s.wo_got.z - s.wo_want.z;
            c.sample_wo.add(std::sqrt(dx * dx + dy * dy + dz * dz), 0.0,
                            [&] { return spreads(), sp_wo; }, swhere);
            c.sample_pdf.add(s.pdf_got, s.pdf_want, [&] { return spreads(), sp_pdf; }, swhere);
            for (std::size_t k = 0; k < nc; ++k)
                c.sample_weight.add(s.w_got[k], s.w_want[k], [&] { return spreads(), sp_w[k]; },
                                    swhere);
        } else if (s.ok_got != s.ok_want) {
            const double z = s.ok_got ? s.wo_got.z : s.wo_want.z;
            if (z < 1e-4) {
                ++c.sample_mismatch_grazing;
            } else {
                if (c.sample_mismatch == 0)
                    c.first_sample_mismatch = swhere() + (s.ok_got ? " (naive failed)"
                                                                   : " (reader failed)");
                ++c.sample_mismatch;
            }
        }
    }
    c.seconds = seconds_since(t0);
    return c;
}

void expect_agreement(const Comparison& c, const std::string& label) {
    std::printf("[ rgl ref  ] %-22s eval %.2g, pdf %.2g, sample wo %.2g, sample pdf %.2g, "
                "weight %.2g (max rel); %zu of %zu within float conditioning only; %.2f s\n",
                label.c_str(), c.eval.max_rel, c.pdf.max_rel, c.sample_wo.max_abs_tiny,
                c.sample_pdf.max_rel, c.sample_weight.max_rel, c.conditioned(), c.count(),
                c.seconds);
    EXPECT_TRUE(c.ok()) << label << "\n" << c.summary();
    // Values that agree only within their float conditioning must stay rare, and so must
    // borderline horizon cases, which may go either way in float versus double.
    EXPECT_LE(c.conditioned(), c.count() / 100 + 1) << label << "\n" << c.summary();
    EXPECT_LE(c.sample_mismatch_grazing, c.eval.count / 1000 + 1) << label << "\n" << c.summary();
}

// ---- (a) Golden values ----------------------------------------------------------------------

std::vector<std::vector<double>> read_rows(const std::string& path, std::size_t columns) {
    std::ifstream in(path);
    std::vector<std::vector<double>> rows;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        std::vector<double> row(columns);
        for (auto& v : row) s >> v;
        if (!s) throw std::runtime_error(path + ": malformed line '" + line + "'");
        rows.push_back(row);
    }
    return rows;
}

// The reference values are float32 results of powitacq_rgb. Relative error 1e-4 is applied
// where |ref| > 1e-3 1/sr; below that (clamped channels, values that are a near-cancellation
// of mixed-sign RGB nodes, far tails) relative error is meaningless and an absolute 1e-6 is
// used instead: at 1e-3 this is 1e-3 relative, and it is 3e-8 of the largest peaks (~31).
constexpr double kGoldenRelTol = 1e-4, kGoldenRelFloor = 1e-3, kGoldenAbsTol = 1e-6;

void run_golden(const std::string& name) {
    std::string missing;
    const Material* m = real_material(name, missing);
    if (!m) GTEST_SKIP() << "missing " << missing;
    const std::string dirs_path = npf::testing::shared_data_file("rgl/reference/dirs.txt");
    const std::string ref_path =
        npf::testing::shared_data_file("rgl/reference/" + name + ".txt");
    if (dirs_path.empty()) GTEST_SKIP() << "missing rgl/reference/dirs.txt (shared data folder)";
    if (ref_path.empty()) GTEST_SKIP() << "missing rgl/reference/" << name << ".txt";
    const auto dirs = read_rows(dirs_path, 6);
    const auto refs = read_rows(ref_path, 3);
    ASSERT_EQ(dirs.size(), 500u);
    ASSERT_EQ(refs.size(), dirs.size());

    const npf::ChannelQuery query = m->brdf->native_query();
    ASSERT_EQ(query.size(), 3u);
    double max_rel_reader = 0, max_abs_reader = 0, max_rel_naive = 0, max_abs_naive = 0;
    int bad_reader = 0, bad_naive = 0;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        const auto& d = dirs[i];
        const double li = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const double lo = std::sqrt(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
        const Vec3 wi = to_f({d[0] / li, d[1] / li, d[2] / li});
        const Vec3 wo = to_f({d[3] / lo, d[4] / lo, d[5] / lo});
        float out[3];
        m->brdf->eval_cos(wi, wo, query, out);
        const std::vector<double> naive = m->naive->eval_cos(to_d(wi), to_d(wo), {}, true);
        for (int k = 0; k < 3; ++k) {
            const double ref = refs[i][static_cast<std::size_t>(k)];
            auto check = [&](double got, double& max_rel, double& max_abs, int& bad,
                             const char* who) {
                const double diff = std::fabs(got - ref);
                bool ok;
                if (std::fabs(ref) > kGoldenRelFloor) {
                    max_rel = std::max(max_rel, diff / std::fabs(ref));
                    ok = diff <= kGoldenRelTol * std::fabs(ref);
                } else {
                    max_abs = std::max(max_abs, diff);
                    ok = diff <= kGoldenAbsTol;
                }
                if (!ok && ++bad <= 5)
                    ADD_FAILURE() << name << " (" << who << "), pair " << i << " wi = " << str(wi)
                                  << " wo = " << str(wo) << " channel " << k << ": got " << got
                                  << ", reference " << ref;
            };
            check(out[k], max_rel_reader, max_abs_reader, bad_reader, "RglBrdf");
            check(naive[static_cast<std::size_t>(k)], max_rel_naive, max_abs_naive, bad_naive,
                  "NaiveRgl");
        }
    }
    ::testing::Test::RecordProperty("max_rel_error_reader", std::to_string(max_rel_reader));
    ::testing::Test::RecordProperty("max_rel_error_naive", std::to_string(max_rel_naive));
    std::printf("[ golden   ] %-24s RglBrdf: max rel %.3g, max abs (|ref|<=1e-3) %.3g;  "
                "NaiveRgl: max rel %.3g, max abs %.3g\n",
                name.c_str(), max_rel_reader, max_abs_reader, max_rel_naive, max_abs_naive);
    EXPECT_EQ(bad_reader, 0) << name << ": RglBrdf values outside tolerance";
    EXPECT_EQ(bad_naive, 0) << name << ": NaiveRgl values outside tolerance";
}

TEST(RglReferenceGolden, AcrylicFeltGreen) { run_golden("acrylic_felt_green_rgb"); }
TEST(RglReferenceGolden, CgSunflower) { run_golden("cg_sunflower_rgb"); }
TEST(RglReferenceGolden, IlmL337Metallic) { run_golden("ilm_l3_37_metallic_rgb"); }
TEST(RglReferenceGolden, PaperWhite) { run_golden("paper_white_rgb"); }
TEST(RglReferenceGolden, VchGoldenYellow) { run_golden("vch_golden_yellow_rgb"); }

// ---- (b) Real files versus NaiveRgl ---------------------------------------------------------

void run_real_comparison(const std::string& name, std::uint64_t seed) {
    std::string missing;
    const Material* m = real_material(name, missing);
    if (!m) GTEST_SKIP() << "missing " << missing;
    const auto pairs = comparison_pairs(20000, seed);
    const Comparison c = compare_with_naive(*m, pairs, {}, seed ^ 0xabcdefULL);
    expect_agreement(c, name);
}

TEST(RglReferenceReal, AcrylicFeltGreen) { run_real_comparison("acrylic_felt_green_rgb", 11); }
TEST(RglReferenceReal, CgSunflower) { run_real_comparison("cg_sunflower_rgb", 12); }
TEST(RglReferenceReal, IlmL337Metallic) { run_real_comparison("ilm_l3_37_metallic_rgb", 13); }
TEST(RglReferenceReal, PaperWhite) { run_real_comparison("paper_white_rgb", 14); }
TEST(RglReferenceReal, VchGoldenYellow) { run_real_comparison("vch_golden_yellow_rgb", 15); }

// Exact mirror pairs (wo = (-wi.x, -wi.y, wi.z), bit for bit) have wi + wo = (0, 0, 2 wi.z),
// so wh is exactly the normal (sec. 5: wh = normalize(wi + wo)) and u_h.x = 0; in the real
// files every VNDF slice is 0 in its u_theta = 0 column, so pdf = 0 there (powitacq, which
// normalises by dividing by the length, gets wh.z = 1 exactly too). Kept apart from the
// comparison above because the reader disagrees here: see the message.
// Returns the number of disagreements, with the first in `first`.
std::size_t run_exact_mirror_pdf(const Material& m, std::string& first) {
    Rng rng(2024);
    std::vector<Pair> pairs;
    for (int i = 0; i < 2000; ++i) {
        Pair p;
        p.wi = uniform_hemisphere(rng);
        p.wo = mirror(p.wi);
        pairs.push_back(p);
    }
    // Scale of the material's pdf, for the threshold of "tiny" values.
    std::vector<double> typical;
    for (const Pair& p : comparison_pairs(2000, 5))
        if (!is_exact_mirror(p)) typical.push_back(m.naive->pdf(to_d(p.wi), to_d(p.wo)));
    Agreement pd{"pdf at exact mirror pairs"};
    pd.tiny = 1e-4 * max_abs(typical);
    const auto perturbations = conditioning_perturbations(false);
    double worst_got = 0.0, worst_want = 0.0;
    for (const Pair& p : pairs) {
        const Vec3d wi = to_d(p.wi), wo = to_d(p.wo);
        const double got = m.brdf->pdf(p.wi, p.wo), want = m.naive->pdf(wi, wo);
        const bool ok = pd.add(got, want,
                               [&] {
                                   double sp = 0.0;
                                   for (const auto& pt : perturbations)
                                       sp = std::max(sp, std::fabs(m.naive->pdf(wi, wo, pt) - want));
                                   return sp;
                               },
                               [&] { return "wi = " + str(p.wi) + ", wo = " + str(p.wo); });
        if (!ok && std::fabs(got - want) > std::fabs(worst_got - worst_want)) {
            worst_got = got;
            worst_want = want;
        }
    }
    std::printf("[ mirror   ] %-22s %zu of %zu exact mirror pdfs disagree (worst: reader %.6g, "
                "published algorithm %.6g; typical pdf scale %.6g)\n",
                m.name.c_str(), pd.bad, pd.count, worst_got, worst_want, max_abs(typical));
    if (pd.bad && first.empty()) first = m.name + ": " + pd.first_bad;
    return pd.bad;
}

TEST(RglReferenceReal, PdfAtExactMirrorPairs) {
    std::size_t bad = 0;
    std::string first;
    for (const auto& name : real_materials()) {
        std::string missing;
        if (const Material* m = real_material(name, missing)) bad += run_exact_mirror_pdf(*m, first);
    }
    bad += run_exact_mirror_pdf(synthetic_material("iso_rgb"), first);
    bad += run_exact_mirror_pdf(synthetic_material("aniso_r1_rgb"), first);
    EXPECT_EQ(bad, 0u)
        << "first: " << first
        << "\n  Cause: npf::normalize (core/include/npf/core/vec.h) multiplies by 1/length, so for "
           "about 15% of z, normalize((0, 0, 2z)).z = 1 - 2^-24 instead of 1; elevation() then "
           "gives 6e-8 rad, the square-root warp turns that into u_h.x = 1.95e-4, where the VNDF "
           "density is no longer its u_theta = 0 value, and the 1e-6 Jacobian floor magnifies "
           "the difference into a large pdf. Dividing by the length (as powitacq does) gives "
           "wh.z = 1 exactly.";
}

// ---- (c) Synthetic kinds versus NaiveRgl ----------------------------------------------------

void run_synthetic_comparison(const std::string& kind) {
    const Material& m = synthetic_material(kind);
    // The loaders agree on what kind of file this is.
    EXPECT_EQ(m.brdf->info().isotropic, m.naive->isotropic) << kind;
    EXPECT_EQ(m.brdf->reduction(), m.naive->reduction) << kind;
    EXPECT_EQ(m.brdf->jacobian(), m.naive->jacobian) << kind;

    const auto pairs = comparison_pairs(6000, std::hash<std::string>()(kind));
    expect_agreement(compare_with_naive(m, pairs, {}, 99), kind);
    if (m.naive->spectral) {
        // Between the stored wavelengths (400, 500, 600, 700 nm), at and beyond the ends.
        const std::vector<double> between = {450.0, 512.5, 599.0, 683.25};
        const std::vector<double> outside = {300.0, 399.0, 700.0, 701.0, 1000.0};
        expect_agreement(compare_with_naive(m, pairs, between, 100), kind + " (between)");
        expect_agreement(compare_with_naive(m, pairs, outside, 101), kind + " (outside)");
    }
}

TEST(RglReferenceSynthetic, IsotropicRgb) { run_synthetic_comparison("iso_rgb"); }
TEST(RglReferenceSynthetic, IsotropicSpectral) { run_synthetic_comparison("iso_spectral"); }
TEST(RglReferenceSynthetic, IsotropicJacobian0) { run_synthetic_comparison("iso_rgb_jacobian0"); }
TEST(RglReferenceSynthetic, IsotropicPhiCount2) { run_synthetic_comparison("iso_phi_count2"); }
TEST(RglReferenceSynthetic, AnisotropicR1Rgb) { run_synthetic_comparison("aniso_r1_rgb"); }
TEST(RglReferenceSynthetic, AnisotropicR2Rgb) { run_synthetic_comparison("aniso_r2_rgb"); }
TEST(RglReferenceSynthetic, AnisotropicR4Rgb) { run_synthetic_comparison("aniso_r4_rgb"); }
TEST(RglReferenceSynthetic, AnisotropicR1Spectral) { run_synthetic_comparison("aniso_r1_spectral"); }
TEST(RglReferenceSynthetic, AnisotropicR2Spectral) { run_synthetic_comparison("aniso_r2_spectral"); }
TEST(RglReferenceSynthetic, AnisotropicR4Spectral) { run_synthetic_comparison("aniso_r4_spectral"); }
TEST(RglReferenceSynthetic, AnisotropicR2Jacobian0) { run_synthetic_comparison("aniso_r2_jacobian0"); }

// Every synthetic kind has a test above.
TEST(RglReferenceSynthetic, EveryKindIsCovered) { EXPECT_EQ(synthetic_kinds().size(), 11u); }

// Spectral evaluation at in-between wavelengths is the linear blend of the neighbouring
// stored ones, and constant outside the stored range (sec. 8), checked on the reader alone.
TEST(RglReferenceSpectral, WavelengthInterpolationIsLinearAndClamped) {
    const Material& m = synthetic_material("aniso_r2_spectral");
    const auto q = m.brdf->query(npf::Channels::spectral({400.f, 500.f, 450.f, 470.f, 350.f,
                                                          700.f, 800.f}));
    const auto pairs = comparison_pairs(500, 7);
    for (const Pair& p : pairs) {
        float v[7];
        m.brdf->eval_cos(p.wi, p.wo, q, v);
        const double scale = std::max({1e-30, double(std::fabs(v[0])), double(std::fabs(v[1]))});
        EXPECT_NEAR(v[2], 0.5 * (v[0] + v[1]), 1e-6 * scale) << str(p.wi) << " " << str(p.wo);
        EXPECT_NEAR(v[3], 0.3 * v[0] + 0.7 * v[1], 1e-6 * scale) << str(p.wi) << " " << str(p.wo);
        EXPECT_EQ(v[4], v[0]);
        EXPECT_EQ(v[6], v[5]);
    }
}

// ---- (d) Symmetry facts ---------------------------------------------------------------------

Vec3 rotate_z(const Vec3& w, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return to_f({c * w.x - s * w.y, s * w.x + c * w.y, w.z});
}

// Evaluation, pdf of `m` at (wi, wo) and at (T wi, T wo) agree exactly (folding makes them
// the same computation) for the maps T given.
void expect_exact_invariance(const Material& m, const std::vector<Vec3 (*)(const Vec3&)>& maps,
                             const std::string& what) {
    const auto q = m.brdf->native_query();
    const std::size_t nc = q.size();
    std::vector<float> a(nc), b(nc);
    const auto pairs = comparison_pairs(4000, 31);
    int failures = 0;
    for (const Pair& p : pairs) {
        m.brdf->eval_cos(p.wi, p.wo, q, a.data());
        const float pa = m.brdf->pdf(p.wi, p.wo);
        for (auto T : maps) {
            m.brdf->eval_cos(T(p.wi), T(p.wo), q, b.data());
            const float pb = m.brdf->pdf(T(p.wi), T(p.wo));
            bool same = pa == pb;
            for (std::size_t k = 0; k < nc; ++k) same = same && a[k] == b[k];
            if (!same && ++failures <= 5)
                ADD_FAILURE() << what << ": wi = " << str(p.wi) << ", wo = " << str(p.wo)
                              << " -> " << str(T(p.wi)) << ", " << str(T(p.wo)) << ": eval "
                              << a[0] << " vs " << b[0] << ", pdf " << pa << " vs " << pb;
        }
    }
    EXPECT_EQ(failures, 0) << what;
}

Vec3 rotate_pi(const Vec3& w) { return {-w.x, -w.y, w.z}; }
Vec3 mirror_x(const Vec3& w) { return {-w.x, w.y, w.z}; }  // about the plane x = 0
Vec3 mirror_y(const Vec3& w) { return {w.x, -w.y, w.z}; }  // about the plane y = 0

TEST(RglReferenceSymmetry, Reduction2IsInvariantUnderHalfTurn) {
    for (const char* kind : {"aniso_r2_rgb", "aniso_r2_spectral", "aniso_r2_jacobian0"})
        expect_exact_invariance(synthetic_material(kind), {&rotate_pi}, kind);
}

TEST(RglReferenceSymmetry, Reduction4IsInvariantUnderMirrors) {
    for (const char* kind : {"aniso_r4_rgb", "aniso_r4_spectral"})
        expect_exact_invariance(synthetic_material(kind), {&rotate_pi, &mirror_x, &mirror_y},
                                kind);
}

// Isotropic files (nP = 1) use only the azimuth of wh relative to wi, so rotating both
// directions about the normal changes the value only through float rounding of the rotated
// directions (allowed for as in compare_with_naive, with twice NaiveRgl's spread, as both
// evaluations round). Not near wh = normal: there the azimuth of wh comes from the rounding
// residue of wi + wo, and the tables need not be continuous in it (the u_theta = 0 column of
// the VNDF inverts to a whole column of data nodes).
void expect_rotation_invariance(const Material& m) {
    const auto q = m.brdf->native_query();
    const std::size_t nc = q.size();
    std::vector<float> a(nc), b(nc);
    Rng rng(77);
    const auto pairs = comparison_pairs(4000, 41);
    Agreement ev{"rotated eval"}, pd{"rotated pdf"};
    const auto perturbations = conditioning_perturbations(false);
    std::vector<double> all_a, all_p;
    struct Row {
        std::vector<float> a, b;
        float pa, pb;
        Pair p;
        double angle;
    };
    std::vector<Row> rows;
    for (const Pair& p : pairs) {
        // At wi = normal, phi_i = atan2(0, 0) = 0 whatever the rotation, so rotating wo alone
        // changes the relative azimuth: no invariance to expect there.
        if (p.wi.x == 0.f && p.wi.y == 0.f) continue;
        const double hx = double(p.wi.x) + p.wo.x, hy = double(p.wi.y) + p.wo.y,
                     hz = double(p.wi.z) + p.wo.z;
        if (std::sqrt(hx * hx + hy * hy) < 1e-2 * std::sqrt(hx * hx + hy * hy + hz * hz)) continue;
        const double angle = 2.0 * kPi * rng.uniform();
        Row r;
        r.p = p;
        r.angle = angle;
        m.brdf->eval_cos(p.wi, p.wo, q, a.data());
        m.brdf->eval_cos(rotate_z(p.wi, angle), rotate_z(p.wo, angle), q, b.data());
        r.a = a;
        r.b = b;
        r.pa = m.brdf->pdf(p.wi, p.wo);
        r.pb = m.brdf->pdf(rotate_z(p.wi, angle), rotate_z(p.wo, angle));
        for (float v : a) all_a.push_back(v);
        all_p.push_back(r.pa);
        rows.push_back(r);
    }
    ev.tiny = 1e-4 * max_abs(all_a);
    pd.tiny = 1e-4 * max_abs(all_p);
    for (const Row& r : rows) {
        auto where = [&] {
            return "wi = " + str(r.p.wi) + ", wo = " + str(r.p.wo) + ", angle " +
                   std::to_string(r.angle);
        };
        const Vec3d wi = to_d(r.p.wi), wo = to_d(r.p.wo);
        std::vector<double> spread;
        auto eval_spread = [&](std::size_t k) {
            if (spread.empty()) {
                spread.assign(nc, 0.0);
                const auto v0 = m.naive->eval_cos(wi, wo, {}, true);
                for (const auto& pt : perturbations) {
                    const auto v = m.naive->eval_cos(wi, wo, {}, true, pt);
                    for (std::size_t j = 0; j < nc; ++j)
                        spread[j] = std::max(spread[j], 2.0 * std::fabs(v[j] - v0[j]));
                }
            }
            return spread[k];
        };
        for (std::size_t k = 0; k < nc; ++k)
            ev.add(r.b[k], r.a[k], [&] { return eval_spread(k); }, where);
        pd.add(r.pb, r.pa,
               [&] {
                   const double p0 = m.naive->pdf(wi, wo);
                   double sp = 0.0;
                   for (const auto& pt : perturbations)
                       sp = std::max(sp, 2.0 * std::fabs(m.naive->pdf(wi, wo, pt) - p0));
                   return sp;
               },
               where);
    }
    std::printf("[ rotation ] %-22s eval max rel %.2g, pdf max rel %.2g; %zu of %zu within "
                "float conditioning only\n",
                m.name.c_str(), ev.max_rel, pd.max_rel, ev.conditioned + pd.conditioned,
                ev.count + pd.count);
    EXPECT_EQ(ev.bad, 0u) << m.name << ": " << ev.summary();
    EXPECT_EQ(pd.bad, 0u) << m.name << ": " << pd.summary();
    EXPECT_LE(ev.conditioned + pd.conditioned, (ev.count + pd.count) / 100 + 1) << m.name;
}

TEST(RglReferenceSymmetry, IsotropicIsInvariantUnderRotation) {
    expect_rotation_invariance(synthetic_material("iso_rgb"));
    expect_rotation_invariance(synthetic_material("iso_spectral"));
    for (const auto& name : real_materials()) {
        std::string missing;
        if (const Material* m = real_material(name, missing)) expect_rotation_invariance(*m);
    }
}

// ---- Numerical extremes ---------------------------------------------------------------------

struct ExtremeStats {
    std::size_t evals = 0, samples_ok = 0, bad = 0;
    std::string first_bad;
};

void record_bad(ExtremeStats& st, const std::string& msg) {
    if (st.bad++ == 0) st.first_bad = msg;
}

// `count` pairs on one material: grazing (z in [1e-7, 1e-6] and 1e-6..1e-3), exactly the
// normal, exact mirror pairs, wo = wi, the horizon itself and below it, and uniform pairs;
// u includes 0 and the largest float below 1.
void run_extremes(const Material& m, std::size_t count, std::uint64_t seed, ExtremeStats& st) {
    Rng rng(seed);
    const auto q = m.brdf->native_query();
    const std::size_t nc = q.size();
    std::vector<float> out(nc), weight(nc);
    const Vec3 normal(0.f, 0.f, 1.f);
    auto pick = [&](int kind) -> Vec3 {
        switch (kind) {
            case 0: return near_horizon(rng, 1e-7, 1e-6);
            case 1: return near_horizon(rng, 1e-6, 1e-3);
            case 2: return normal;
            case 3: return direction_with_z(0.0, 2.0 * kPi * rng.uniform());  // on the horizon
            case 4: return direction_with_z(1.0 - 1e-7 * rng.uniform(), 2.0 * kPi * rng.uniform());
            default: return uniform_hemisphere(rng);
        }
    };
    for (std::size_t i = 0; i < count; ++i) {
        Vec3 wi, wo;
        const std::size_t kind = i % 16;
        if (kind == 0) {
            wi = pick(static_cast<int>(rng.next() % 7));
            wo = mirror(wi);
        } else if (kind == 1) {
            wi = pick(static_cast<int>(rng.next() % 7));
            wo = wi;
        } else if (kind == 2) {  // one direction below the horizon
            wi = pick(static_cast<int>(rng.next() % 7));
            wo = pick(static_cast<int>(rng.next() % 7));
            wo.z = -wo.z;
            if (rng.next() & 1) std::swap(wi, wo);
        } else {
            wi = pick(static_cast<int>(rng.next() % 7));
            wo = pick(static_cast<int>(rng.next() % 7));
        }
        Vec2 u{rng.uniform_float(), rng.uniform_float()};
        if (i % 97 == 0) u.x = 0.f;
        if (i % 89 == 0) u.y = 0.f;
        if (i % 83 == 0) u.x = 1.f - 0x1.0p-24f;
        if (i % 79 == 0) u.y = 1.f - 0x1.0p-24f;

        auto where = [&] {
            return m.name + ": wi = " + str(wi) + ", wo = " + str(wo) + ", u = (" +
                   std::to_string(u.x) + ", " + std::to_string(u.y) + ")";
        };
        m.brdf->eval_cos(wi, wo, q, out.data());
        ++st.evals;
        for (std::size_t k = 0; k < nc; ++k)
            if (!std::isfinite(out[k]) || out[k] < 0.f)
                record_bad(st, "eval_cos " + std::to_string(out[k]) + " at " + where());
        const float p = m.brdf->pdf(wi, wo);
        if (!std::isfinite(p) || p < 0.f)
            record_bad(st, "pdf " + std::to_string(p) + " at " + where());
        if (wi.z <= 0.f || wo.z <= 0.f) {
            bool zero = p == 0.f;
            for (std::size_t k = 0; k < nc; ++k) zero = zero && out[k] == 0.f;
            if (!zero) record_bad(st, "nonzero below the horizon at " + where());
        }

        npf::BrdfSample s;
        if (m.brdf->sample(wi, u, q, s, weight.data())) {
            ++st.samples_ok;
            const double len = std::sqrt(double(s.wo.x) * s.wo.x + double(s.wo.y) * s.wo.y +
                                         double(s.wo.z) * s.wo.z);
            if (!(std::isfinite(s.pdf) && s.pdf > 0.f) || !(s.wo.z > 0.f) ||
                !(std::fabs(len - 1.0) < 1e-4))
                record_bad(st, "sample wo " + str(s.wo) + " pdf " + std::to_string(s.pdf) +
                                   " at " + where());
            for (std::size_t k = 0; k < nc; ++k)
                if (!std::isfinite(weight[k]) || weight[k] < 0.f)
                    record_bad(st, "sample weight " + std::to_string(weight[k]) + " at " +
                                       where());
        } else {
            for (std::size_t k = 0; k < nc; ++k)
                if (weight[k] != 0.f)
                    record_bad(st, "failed sample left weight " + std::to_string(weight[k]) +
                                       " at " + where());
        }
    }
}

void run_all_extremes(std::size_t total) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<const Material*> materials;
    for (const auto& name : real_materials()) {
        std::string missing;
        if (const Material* m = real_material(name, missing)) materials.push_back(m);
    }
    for (const auto& k : synthetic_kinds()) materials.push_back(&synthetic_material(k));
    ExtremeStats st;
    const std::size_t per = total / materials.size() + 1;
    std::uint64_t seed = 1000;
    for (const Material* m : materials) run_extremes(*m, per, seed++, st);
    std::printf("[ extremes ] %zu pairs over %zu materials, %zu successful samples, %.2f s\n",
                st.evals, materials.size(), st.samples_ok, seconds_since(t0));
    EXPECT_EQ(st.bad, 0u) << "first: " << st.first_bad;
}

// 1e6 pairs take about 1 s (Release), so no reduced version is needed.
TEST(RglExtremes, NoNanInfOrNegative) { run_all_extremes(1000000); }

}  // namespace
