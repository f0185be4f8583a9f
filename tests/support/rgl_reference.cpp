#include "rgl_reference.h"

#include <npf/core/brdf.h>
#include <npf/core/channels.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <stdexcept>

namespace npf::testing::rgl_reference {

const std::vector<std::string>& real_materials() {
    static const std::vector<std::string> names = {"acrylic_felt_green_rgb", "cg_sunflower_rgb",
                                                   "ilm_l3_37_metallic_rgb", "paper_white_rgb",
                                                   "vch_golden_yellow_rgb"};
    return names;
}

Vec3 to_f(const Vec3d& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

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

std::string str(const Vec3& v) {
    std::ostringstream s;
    s.precision(9);
    s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return s.str();
}

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


std::vector<NaivePerturbation> conditioning_perturbations(bool sampling) {
    std::vector<NaivePerturbation> out;
    for (int k = 0; k < (sampling ? 14 : 8); ++k) {
        NaivePerturbation p;
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

const Material* real_material(const std::string& name, std::string& missing) {
    static std::map<std::string, std::unique_ptr<Material>> cache;
    const std::string relative = "rgl/" + name + ".bsdf";
    auto it = cache.find(name);
    if (it == cache.end()) {
        std::unique_ptr<Material> m;
        const std::string path = shared_data_file(relative);
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

std::vector<SyntheticKind> synthetic_kinds() {
    std::vector<SyntheticKind> out;
    auto add = [&](const std::string& name, auto&& edit) {
        SyntheticKind k;
        k.name = name;
        k.spec.description = "rgl reference test: " + name;
        edit(k.spec);
        out.push_back(k);
    };
    auto aniso = [](SyntheticRglSpec& s, int reduction) {
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
        static const std::string folder = temporary_folder("rgl_reference");
        auto m = std::make_unique<Material>();
        m->name = kind.name;
        m->path = write_synthetic_rgl(kind.spec, folder + "/" + kind.name + ".bsdf");
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

double max_abs(const std::vector<double>& v) {
    double m = 0.0;
    for (double x : v) m = std::max(m, std::fabs(x));
    return m;
}

namespace {

// What both implementations gave for one pair's sample (one u per pair).
struct SampleResult {
    bool ok_got = false, ok_want = false;
    Vec3 wo_got;
    Vec3d wo_want;
    double pdf_got = 0, pdf_want = 0;
    std::vector<double> w_got, w_want;
    Vec2 u;
};

// The two implementations' values over the pairs, before any comparison; both see exactly the
// same inputs: the float wavelengths and directions.
struct BothValues {
    npf::ChannelQuery query;
    std::vector<double> wl_d;
    std::size_t nc = 0;
    std::vector<double> ev_got, ev_want, pdf_got, pdf_want;
    std::vector<SampleResult> sr;
};

BothValues evaluate_both(const Material& m, const std::vector<Pair>& pairs,
                         const std::vector<double>& wavelengths, std::uint64_t seed) {
    const npf::RglBrdf& brdf = *m.brdf;
    const NaiveRgl& naive = *m.naive;
    BothValues v;
    if (wavelengths.empty()) {
        v.query = brdf.native_query();
    } else {
        std::vector<float> wl(wavelengths.begin(), wavelengths.end());
        v.query = brdf.query(npf::Channels::spectral(wl));
    }
    for (float w : v.query.requested.wavelengths()) v.wl_d.push_back(w);
    const std::size_t nc = v.nc = v.query.size();
    const std::size_t n = pairs.size();
    v.ev_got.resize(n * nc), v.ev_want.resize(n * nc), v.pdf_got.resize(n), v.pdf_want.resize(n);
    v.sr.resize(n);
    Rng rng(seed);
    std::vector<float> out(nc), weight(nc);
    for (std::size_t i = 0; i < n; ++i) {
        const Pair& p = pairs[i];
        brdf.eval_cos(p.wi, p.wo, v.query, out.data());
        const std::vector<double> want = naive.eval_cos(to_d(p.wi), to_d(p.wo), v.wl_d, true);
        for (std::size_t k = 0; k < nc; ++k) {
            v.ev_got[i * nc + k] = out[k];
            v.ev_want[i * nc + k] = want[k];
        }
        v.pdf_got[i] = brdf.pdf(p.wi, p.wo);
        v.pdf_want[i] = naive.pdf(to_d(p.wi), to_d(p.wo));

        SampleResult& s = v.sr[i];
        // Not u within ~1e-7 of 0 or 1: both clamp to [6e-8, 1 - 6e-8] (sec. 3.4), but there
        // the warps invert CDFs at their flat ends, where float and double legitimately land
        // on different sides of zero-density cells (RglExtremes covers those u).
        s.u = Vec2{rng.uniform_float(), rng.uniform_float()};
        npf::BrdfSample bs;
        s.ok_got = brdf.sample(p.wi, s.u, v.query, bs, weight.data());
        s.wo_got = bs.wo;
        s.pdf_got = bs.pdf;
        s.w_got.assign(weight.begin(), weight.end());
        s.ok_want = naive.sample(to_d(p.wi), s.u.x, s.u.y, s.wo_want, s.pdf_want, &s.w_want,
                                 v.wl_d, true);
    }
    return v;
}

// The thresholds of "tiny" values: 1e-4 of the largest naive value of each kind.
void set_tolerances(Comparison& c, const BothValues& v) {
    c.eval.tiny = 1e-4 * max_abs(v.ev_want);
    c.pdf.tiny = 1e-4 * max_abs(v.pdf_want);
    std::vector<double> spdf, sweight;
    for (const auto& s : v.sr) {
        if (!(s.ok_got && s.ok_want)) continue;
        spdf.push_back(s.pdf_want);
        sweight.insert(sweight.end(), s.w_want.begin(), s.w_want.end());
    }
    c.sample_pdf.tiny = 1e-4 * max_abs(spdf);
    c.sample_weight.tiny = 1e-4 * max_abs(sweight);
    c.sample_wo.rel_tol = 1.0;  // wo is compared as |wo_got - wo_want| against 0 ...
    c.sample_wo.tiny = 1e-4;    // ... with an absolute tolerance of 1e-4
}

// Pair i's eval_cos and pdf.
void compare_pair_values(Comparison& c, const NaiveRgl& naive, const BothValues& v,
                         const Pair& p, std::size_t i, bool skip_exact_mirror_pdf,
                         const std::vector<NaivePerturbation>& perturbations) {
    const std::size_t nc = v.nc;
    const Vec3d wi = to_d(p.wi), wo = to_d(p.wo);
    auto where = [&] { return "wi = " + str(p.wi) + ", wo = " + str(p.wo); };
    // Conditioning of the naive values, computed on first need.
    std::vector<double> eval_spread;
    auto eval_spread_of = [&](std::size_t k) {
        if (eval_spread.empty()) {
            eval_spread.assign(nc, 0.0);
            for (const auto& pt : perturbations) {
                const auto e = naive.eval_cos(wi, wo, v.wl_d, true, pt);
                for (std::size_t j = 0; j < nc; ++j)
                    eval_spread[j] = std::max(eval_spread[j], std::fabs(e[j] - v.ev_want[i * nc + j]));
            }
        }
        return eval_spread[k];
    };
    for (std::size_t k = 0; k < nc; ++k)
        c.eval.add(v.ev_got[i * nc + k], v.ev_want[i * nc + k], [&] { return eval_spread_of(k); },
                   [&] { return where() + ", channel " + std::to_string(k); });
    if (skip_exact_mirror_pdf && is_exact_mirror(p)) {
        ++c.exact_mirror_pdfs_skipped;
        return;
    }
    c.pdf.add(v.pdf_got[i], v.pdf_want[i],
              [&] {
                  double sp = 0.0;
                  for (const auto& pt : perturbations)
                      sp = std::max(sp, std::fabs(naive.pdf(wi, wo, pt) - v.pdf_want[i]));
                  return sp;
              },
              where);
}

// Pair i's sample: where both succeed, wo, pdf and weights; else whether both failed.
void compare_pair_sample(Comparison& c, const NaiveRgl& naive, const BothValues& v,
                         const Pair& p, const SampleResult& s,
                         const std::vector<NaivePerturbation>& sample_perturbations) {
    const std::size_t nc = v.nc;
    const Vec3d wi = to_d(p.wi);
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
                if (!naive.sample(wi, s.u.x, s.u.y, wo2, pdf2, &w2, v.wl_d, true, pt)) continue;
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

}  // namespace

Comparison compare_with_naive(const Material& m, const std::vector<Pair>& pairs,
                              const std::vector<double>& wavelengths, std::uint64_t seed,
                              bool skip_exact_mirror_pdf) {
    const auto t0 = std::chrono::steady_clock::now();
    const BothValues v = evaluate_both(m, pairs, wavelengths, seed);
    const auto perturbations = conditioning_perturbations(false);
    const auto sample_perturbations = conditioning_perturbations(true);
    Comparison c;
    set_tolerances(c, v);
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        compare_pair_values(c, *m.naive, v, pairs[i], i, skip_exact_mirror_pdf, perturbations);
        compare_pair_sample(c, *m.naive, v, pairs[i], v.sr[i], sample_perturbations);
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

}  // namespace npf::testing::rgl_reference
