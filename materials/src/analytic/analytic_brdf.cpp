// AnalyticBrdf: the formula and the sampling mixture of analytic_brdf.h.
//
// The specular term is evaluated as D F / (4 sigma(wi) sigma(wo)) (f_r), which equals
// D F G1 G1 / (4 cos_i cos_o) because G1(w) = w.z / sigma(w), but has no 0/0 at grazing
// directions: sigma stays >= about alpha/2 there, so mirror-sharp lobes stay finite.
#include <npf/core/number_text.h>
#include <npf/materials/analytic/analytic_brdf.h>

#include <npf/core/error.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace npf {

namespace {

// RGB is integrated on 360..830 nm every 5 nm (the CIE table's range): 95 wavelengths.
constexpr std::size_t kGridSize = 95;
constexpr float kGridStart = 360.f, kGridStep = 5.f;
constexpr double kInvPi = 1.0 / kPiD;
constexpr double kInv2Pi = 0.5 / kPiD;
// Roughness range accepted: below 1e-4 D overflows float products, above 10 nothing is left of
// a lobe (and the fitter never produces it).
constexpr float kMinAlpha = 1e-4f, kMaxAlpha = 10.f;

// Spectral requests are processed in chunks so that the per-direction work needs no heap.
constexpr std::size_t kSpectralChunk = 64;

std::vector<float> default_wavelengths() {
    std::vector<float> w(195);
    for (std::size_t i = 0; i < w.size(); ++i) w[i] = float(360.0 + 640.0 * double(i) / 194.0);
    return w;
}


const char* distribution_name(MicrofacetDistribution d) {
    return d == MicrofacetDistribution::Ggx ? "GGX" : "Beckmann";
}

const char* fresnel_name(Fresnel::Kind k) {
    switch (k) {
    case Fresnel::Kind::Conductor: return "conductor";
    case Fresnel::Kind::Dielectric: return "dielectric";
    case Fresnel::Kind::Schlick: return "Schlick";
    case Fresnel::Kind::ThinFilm: return "thin film";
    case Fresnel::Kind::One: return "one";
    }
    return "?";
}

// Sum of luminance weights times the spectrum over the material's wavelengths, with the mean
// value as a fallback for spectra that are non-zero only where the eye is blind (their lobe
// must still be sampled, or sample() would be biased).
double importance(const std::vector<double>& values, const std::vector<double>& lum) {
    double y = 0.0, mean = 0.0;
    for (std::size_t i = 0; i < values.size(); ++i) {
        y += lum[i] * values[i];
        mean += values[i];
    }
    mean /= double(values.empty() ? 1 : values.size());
    return y > 0.0 ? y : 1e-3 * mean;
}

// Orthonormal basis around a unit vector (Duff et al. 2017).
void basis(const Vec3& n, Vec3& t, Vec3& b) {
    const float sign = std::copysign(1.f, n.z);
    const float a = -1.f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = Vec3(1.f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = Vec3(c, sign + n.y * n.y * a, -n.y);
}

// Checks the material (every problem names it, as `src`); fills in the default wavelengths.
void validate(AnalyticMaterial& m, const std::string& src) {
    if (m.wavelengths.empty()) m.wavelengths = default_wavelengths();
    for (std::size_t i = 0; i < m.wavelengths.size(); ++i) {
        const float l = m.wavelengths[i];
        if (!std::isfinite(l) || l <= 0.f)
            throw Error(src, "wavelength " + number_text(l) + " nm is not a positive finite number");
        if (i > 0 && !(l > m.wavelengths[i - 1]))
            throw Error(src, "wavelengths must be strictly ascending (" + number_text(m.wavelengths[i - 1]) +
                                 " then " + number_text(l) + " nm)");
    }
    auto check_spectrum = [&](const color::SampledSpectrum& s, const std::string& what) {
        for (double v : s.values())
            if (!(v >= 0.0) || !std::isfinite(v))
                throw Error(src, what + " has the value " + number_text(v) + "; it must be finite and >= 0");
    };
    for (std::size_t k = 0; k < m.specular.size(); ++k) {
        const SpecularLobe& lobe = m.specular[k];
        const std::string what = "specular lobe " + std::to_string(k);
        for (float a : {lobe.ndf.alpha_x, lobe.ndf.alpha_y})
            if (!(a >= kMinAlpha && a <= kMaxAlpha))
                throw Error(src, what + ": roughness " + number_text(a) + " is outside [" + number_text(kMinAlpha) + ", " +
                                     number_text(kMaxAlpha) + "]");
        if (!std::isfinite(lobe.ndf.rotation)) throw Error(src, what + ": rotation is not finite");
        if (lobe.weight.empty()) throw Error(src, what + ": empty weight spectrum");
        check_spectrum(lobe.weight, what + " weight");
    }
    check_spectrum(m.diffuse, "the diffuse albedo");
    check_spectrum(m.retroreflection, "the retro-reflection weight");
    check_spectrum(m.sheen, "the sheen weight");
    if (!(m.retro_exponent >= 0.f && m.retro_exponent <= 1e6f))
        throw Error(src, "retro-reflection exponent " + number_text(m.retro_exponent) + " is outside [0, 1e6]");
    if (!(m.sheen_roughness > 0.f && m.sheen_roughness <= 1.f))
        throw Error(src, "sheen roughness " + number_text(m.sheen_roughness) + " is outside (0, 1]");
}

// The value bound (brdf.h): each term's largest f_r cos_i cos_o.
double value_bound(const AnalyticMaterial& m) {
    // Specular: w D F G1 G1 / 4 with F, G1 <= 1 and D <= 1 / (pi alpha_x alpha_y) (GGX and
    // Beckmann peak at the pole); retro: w (n + 1) / (2 pi); sheen: w D_s cos_i cos_o /
    // (4 (cos_i + cos_o - cos_i cos_o)) <= w (2 + 1/a) / (8 pi); diffuse rho_d / pi. Spectra are
    // interpolated between their samples, so their largest sample bounds them.
    const auto largest = [](const color::SampledSpectrum& s) {
        return s.empty() ? 0.0 : *std::max_element(s.values().begin(), s.values().end());
    };
    double bound = largest(m.diffuse) / kPi;
    for (const SpecularLobe& lobe : m.specular)
        bound += largest(lobe.weight) / (4.0 * kPiD * double(lobe.ndf.alpha_x) * double(lobe.ndf.alpha_y));
    bound += largest(m.retroreflection) * (double(m.retro_exponent) + 1.0) / (2.0 * kPiD);
    bound += largest(m.sheen) * (2.0 + 1.0 / double(m.sheen_roughness)) / (8.0 * kPiD);
    return bound;
}

// What `npf info` shows.
void describe(const AnalyticMaterial& m, BrdfInfo& info) {
    info.format = "analytic";
    info.path = "";
    info.description = m.name;
    info.isotropic = std::all_of(m.specular.begin(), m.specular.end(),
                                   [](const SpecularLobe& l) { return l.ndf.isotropic(); });
    info.channels = Channels::spectral(m.wavelengths);
    info.details.emplace_back("specular lobes", std::to_string(m.specular.size()));
    for (std::size_t k = 0; k < m.specular.size(); ++k) {
        const MicrofacetNdf& n = m.specular[k].ndf;
        info.details.emplace_back("lobe " + std::to_string(k),
                                    std::string(distribution_name(n.type)) + " alpha " + number_text(n.alpha_x) + " x " +
                                        number_text(n.alpha_y) + ", rotation " + number_text(n.rotation) + " rad, " +
                                        fresnel_name(m.specular[k].fresnel.kind()) + " Fresnel");
    }
    info.details.emplace_back("diffuse", m.diffuse.empty() ? "no" : "yes");
    info.details.emplace_back("retro-reflection",
                                m.retroreflection.empty() ? "no" : "yes, exponent " + number_text(m.retro_exponent));
    info.details.emplace_back("sheen", m.sheen.empty() ? "no" : "yes, roughness " + number_text(m.sheen_roughness));
}

}  // namespace

AnalyticBrdf::AnalyticBrdf(AnalyticMaterial material) : m_material(std::move(material)) {
    const std::string& src = m_material.name.empty() ? std::string("analytic material") : m_material.name;
    AnalyticMaterial& m = m_material;

    validate(m, src);
    const double bound = value_bound(m);
    check_value_bound(src, bound, "the sum of its lobes' peaks");
    m_info.value_bound = bound;
    describe(m, m_info);

    // ---- lookup tables ----
    m_rgb_wavelengths.resize(kGridSize);
    for (std::size_t j = 0; j < kGridSize; ++j) m_rgb_wavelengths[j] = kGridStart + kGridStep * float(j);
    m_rgb_weights = color::linear_srgb_weights(m_rgb_wavelengths);
    m_grid_table = make_table(m_rgb_wavelengths);
    m_native_table = make_table(m.wavelengths);

    // ---- sampling mixture ----
    const std::vector<double> lum = color::luminance_weights(m.wavelengths);
    const std::size_t count = m.specular.size() + 3;
    std::vector<double> imp(count, 0.0);
    for (std::size_t k = 0; k < m.specular.size(); ++k) {
        // Weight times the cosine-weighted hemispherical mean of F (midpoints in cos^2).
        const SpecularLobe& lobe = m.specular[k];
        std::vector<double> v = m_native_table.lobe_weight[k];
        if (lobe.fresnel.kind() != Fresnel::Kind::One) {
            constexpr int kAngles = 32;
            for (std::size_t i = 0; i < v.size(); ++i) {
                double f = 0.0;
                for (int a = 0; a < kAngles; ++a)
                    f += lobe.fresnel.eval(std::sqrt((a + 0.5) / kAngles), m_native_table.fresnel[k][i]);
                v[i] *= f / kAngles;
            }
        }
        imp[k] = importance(v, lum);
    }
    const std::size_t kd = m.specular.size(), kr = kd + 1, ks = kd + 2;
    if (!m.diffuse.empty()) imp[kd] = importance(m_native_table.diffuse, lum);
    if (!m.retroreflection.empty()) imp[kr] = importance(m_native_table.retro, lum);
    if (!m.sheen.empty()) imp[ks] = importance(m_native_table.sheen, lum);
    double total = 0.0;
    for (double v : imp) total += v;
    if (!(total > 0.0)) {  // nothing reflects: any valid density will do
        std::fill(imp.begin(), imp.end(), 0.0);
        imp[kd] = total = 1.0;
    }
    // The cdf is computed once in float and the probabilities are read back from it, so that
    // the selection in sample() and the weights in pdf() are the same numbers.
    m_lobe_cdf.assign(count + 1, 0.f);
    double run = 0.0;
    std::size_t last = 0;
    for (std::size_t k = 0; k < count; ++k) {
        run += imp[k];
        m_lobe_cdf[k + 1] = float(run / total);
        if (imp[k] > 0.0) last = k;
    }
    for (std::size_t k = last + 1; k <= count; ++k) m_lobe_cdf[k] = 1.f;
    m_lobe_probability.resize(count);
    for (std::size_t k = 0; k < count; ++k) m_lobe_probability[k] = m_lobe_cdf[k + 1] - m_lobe_cdf[k];
}

AnalyticBrdf::SpectralTable AnalyticBrdf::make_table(const std::vector<float>& wavelengths) const {
    const AnalyticMaterial& m = m_material;
    SpectralTable t;
    t.wavelengths = wavelengths;
    for (const SpecularLobe& lobe : m.specular) {
        t.lobe_weight.push_back(lobe.weight.sample(wavelengths));
        std::vector<Fresnel::Coefficients> c(wavelengths.size());
        for (std::size_t j = 0; j < wavelengths.size(); ++j) c[j] = lobe.fresnel.coefficients(wavelengths[j]);
        t.fresnel.push_back(std::move(c));
    }
    if (!m.diffuse.empty()) t.diffuse = m.diffuse.sample(wavelengths);
    if (!m.retroreflection.empty()) t.retro = m.retroreflection.sample(wavelengths);
    if (!m.sheen.empty()) t.sheen = m.sheen.sample(wavelengths);
    return t;
}

const AnalyticBrdf::SpectralTable* AnalyticBrdf::table_for(const std::vector<float>& wavelengths) const {
    if (wavelengths == m_native_table.wavelengths) return &m_native_table;
    for (const auto& slot : m_query_tables->slots) {
        const SpectralTable* t = slot.load(std::memory_order_acquire);
        if (!t) break;
        if (t->wavelengths == wavelengths) return t;
    }
    return nullptr;
}

ChannelQuery AnalyticBrdf::query(const Channels& requested) const {
    const std::string& src = m_material.name.empty() ? std::string("analytic material") : m_material.name;
    ChannelQuery q;
    q.requested = requested;
    if (!requested.is_rgb()) {
        const std::vector<float>& wl = requested.wavelengths();
        if (wl.empty()) throw Error(src, "no wavelengths requested");
        for (float l : wl)
            if (!std::isfinite(l) || l <= 0.f)
                throw Error(src, "requested wavelength " + number_text(l) + " nm is not a positive finite number");
        // Once the slots are full, further lists are looked up per evaluation (as correct, slower).
        QueryTables& tables = *m_query_tables;
        std::lock_guard<std::mutex> lock(tables.adding);
        if (!table_for(wl) && tables.owned.size() < QueryTables::kSlots) {
            tables.owned.push_back(std::make_unique<const SpectralTable>(make_table(wl)));
            tables.slots[tables.owned.size() - 1].store(tables.owned.back().get(), std::memory_order_release);
        }
    }
    // Unused by this source (it computes every channel), sized as the interface promises.
    const std::size_t n = requested.size();
    q.index0.assign(n, 0);
    q.index1.assign(n, 0);
    q.weight1.assign(n, 0.f);
    return q;
}

template <typename Acc>
void AnalyticBrdf::accumulate(const Vec3& wi, const Vec3& wo, const SpectralTable* table, std::size_t first,
                              const float* lambda, std::size_t n, Acc* acc) const {
    const AnalyticMaterial& m = m_material;
    const double ci = wi.z, co = wo.z;
    const Vec3 h = normalize(wi + wo);
    const double cd = std::clamp(double(dot(wi, h)), 0.0, 1.0);

    for (std::size_t k = 0; k < m.specular.size(); ++k) {
        const SpecularLobe& lobe = m.specular[k];
        const double d = lobe.ndf.eval(h);
        if (!(d > 0.0)) continue;
        const double geo =
            d * co / (4.0 * double(lobe.ndf.projected_area(wi)) * double(lobe.ndf.projected_area(wo)));
        if (!(geo > 0.0) || !std::isfinite(geo)) continue;
        const bool one = lobe.fresnel.kind() == Fresnel::Kind::One;
        if (table) {
            const double* w = table->lobe_weight[k].data() + first;
            const Fresnel::Coefficients* fc = table->fresnel[k].data() + first;
            for (std::size_t j0 = 0; j0 < n; j0 += kSpectralChunk) {
                const std::size_t len = std::min(kSpectralChunk, n - j0);
                double f[kSpectralChunk];
                lobe.fresnel.eval(cd, fc + j0, len, f);
                for (std::size_t j = 0; j < len; ++j) acc[j0 + j] += Acc(geo * w[j0 + j] * f[j]);
            }
        } else {
            for (std::size_t j = 0; j < n; ++j)
                acc[j] += Acc(geo * lobe.weight(lambda[j]) * (one ? 1.0 : lobe.fresnel.eval(cd, lambda[j])));
        }
    }
    // factor * spectrum, the spectrum from `table` (its member `column`) or looked up.
    auto add = [&](const color::SampledSpectrum& s, std::vector<double> SpectralTable::*column, double factor) {
        if (!(factor > 0.0) || !std::isfinite(factor)) return;
        if (table) {
            const double* v = (table->*column).data() + first;
            for (std::size_t j = 0; j < n; ++j) acc[j] += Acc(factor * v[j]);
        } else {
            for (std::size_t j = 0; j < n; ++j) acc[j] += Acc(factor * s(lambda[j]));
        }
    };
    if (!m.diffuse.empty()) add(m.diffuse, &SpectralTable::diffuse, co * kInvPi);
    if (!m.retroreflection.empty()) {
        const double c = dot(wi, wo);
        if (c > 0.0) {
            const double e = m.retro_exponent;
            add(m.retroreflection, &SpectralTable::retro, (e + 1.0) * kInv2Pi * std::pow(c, e) * co);
        }
    }
    if (!m.sheen.empty()) {
        // Charlie D_s(h) = (2 + 1/a) sin^(1/a) theta_h / (2 pi) with sin^2 from x, y (exact at
        // the pole) and Neubelt's visibility 1 / (4 (cos_i + cos_o - cos_i cos_o)).
        const double inv_a = 1.0 / double(m.sheen_roughness);
        const double sin2 = double(h.x) * h.x + double(h.y) * h.y;
        const double ds = (2.0 + inv_a) * std::pow(std::min(sin2, 1.0), 0.5 * inv_a) * kInv2Pi;
        add(m.sheen, &SpectralTable::sheen, ds * co / (4.0 * (ci + co - ci * co)));
    }
}

void AnalyticBrdf::eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const {
    const std::size_t n = query.size();
    for (std::size_t c = 0; c < n; ++c) out[c] = 0.f;
    if (!(wi.z > 0.f && wo.z > 0.f)) return;
    if (query.requested.is_rgb()) {
        double grid[kGridSize] = {};
        accumulate(wi, wo, &m_grid_table, 0, nullptr, kGridSize, grid);
        for (std::size_t c = 0; c < n && c < 3; ++c) {
            const std::vector<double>& w = m_rgb_weights[c];
            double v = 0.0;
            for (std::size_t j = 0; j < kGridSize; ++j) v += w[j] * grid[j];
            if (query.clamp_negative && v < 0.0) v = 0.0;
            out[c] = float(v);
        }
        return;
    }
    const std::vector<float>& wl = query.requested.wavelengths();
    const std::size_t count = std::min(n, wl.size());
    // Known wavelength lists (the material's own, those query() has seen) come from a table.
    const SpectralTable* table = table_for(wl);
    for (std::size_t start = 0; start < count; start += kSpectralChunk) {
        const std::size_t len = std::min(kSpectralChunk, count - start);
        double buf[kSpectralChunk] = {};
        accumulate(wi, wo, table, start, wl.data() + start, len, buf);
        for (std::size_t j = 0; j < len; ++j) out[start + j] = float(buf[j]);
    }
}

double AnalyticBrdf::specular_pdf(const SpecularLobe& lobe, const Vec3& wi, const Vec3& wo) const {
    // Density of wo = reflect(wi, m) for m ~ D(m) cos(theta_m): D(m) m.z / (4 |wi.m|).
    const Vec3 m = normalize(wi + wo);
    const double wim = dot(wi, m);
    if (!(wim > 0.0)) return 0.0;
    return double(lobe.ndf.eval(m)) * double(m.z) / (4.0 * wim);
}

float AnalyticBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
    if (!(wi.z > 0.f && wo.z > 0.f)) return 0.f;
    const AnalyticMaterial& m = m_material;
    const std::size_t kd = m.specular.size();
    double p = 0.0;
    for (std::size_t k = 0; k < kd; ++k)
        if (m_lobe_probability[k] > 0.f) p += m_lobe_probability[k] * specular_pdf(m.specular[k], wi, wo);
    const double cosine = double(wo.z) * kInvPi;
    p += double(m_lobe_probability[kd]) * cosine;  // diffuse
    if (m_lobe_probability[kd + 1] > 0.f) {       // retro
        const double c = dot(wi, wo);
        const double e = m.retro_exponent;
        if (c > 0.0) p += m_lobe_probability[kd + 1] * (e + 1.0) * kInv2Pi * std::pow(c, e);
    }
    p += double(m_lobe_probability[kd + 2]) * cosine;  // sheen
    return float(p);
}

bool AnalyticBrdf::sample(const Vec3& wi, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                          float* weight) const {
    const std::size_t n = query.size();
    if (weight)
        for (std::size_t c = 0; c < n; ++c) weight[c] = 0.f;
    if (!(wi.z > 0.f)) return false;

    // Choose a lobe with u.x and reuse the rest of u.x for the lobe's own draw.
    const std::size_t count = m_lobe_probability.size();
    std::size_t k = 0;
    while (k + 1 < count && u.x >= m_lobe_cdf[k + 1]) ++k;
    const float p = m_lobe_probability[k];
    if (!(p > 0.f)) return false;
    float ux = (u.x - m_lobe_cdf[k]) / p;
    ux = std::clamp(ux, 0.f, 0.99999994f);
    const Vec2 v{ux, u.y};

    const std::size_t kd = m_material.specular.size();
    Vec3 wo;
    if (k < kd) {
        const Vec3 mf = m_material.specular[k].ndf.sample(v);
        const float wim = dot(wi, mf);
        if (!(wim > 0.f)) return false;  // a facet wi cannot see (wo would be below the horizon)
        wo = normalize(mf * (2.f * wim) - wi);
    } else if (k == kd + 1) {
        // Cosine-power lobe around wi: cos a = v.x^(1/(n+1)).
        const double ca = std::pow(double(v.x), 1.0 / (double(m_material.retro_exponent) + 1.0));
        const double sa = std::sqrt(std::max(0.0, 1.0 - ca * ca));
        const double phi = 2.0 * kPiD * double(v.y);
        Vec3 t, b;
        basis(wi, t, b);
        wo = normalize(t * float(sa * std::cos(phi)) + b * float(sa * std::sin(phi)) + wi * float(ca));
    } else {
        // Diffuse and sheen: cosine-weighted.
        const double r = std::sqrt(double(v.x));
        const double phi = 2.0 * kPiD * double(v.y);
        wo = Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(std::sqrt(std::max(0.0, 1.0 - v.x))));
    }
    if (!(wo.z > 0.f)) return false;
    const float pd = pdf(wi, wo);
    if (!(pd > 0.f) || !std::isfinite(pd)) return false;
    s.wo = wo;
    s.pdf = pd;
    if (weight && n > 0) {
        eval_cos(wi, wo, query, weight);
        for (std::size_t c = 0; c < n; ++c) weight[c] /= pd;
    }
    return true;
}

const MicrofacetNdf* AnalyticBrdf::single_ndf() const {
    const AnalyticMaterial& m = m_material;
    if (m.specular.size() == 1 && m.retroreflection.empty() && m.sheen.empty()) return &m.specular[0].ndf;
    return nullptr;
}

std::function<float(const Vec3&)> AnalyticBrdf::ndf_function() const {
    const MicrofacetNdf* ndf = single_ndf();
    if (!ndf) return {};
    const MicrofacetNdf copy = *ndf;
    return [copy](const Vec3& m) { return copy.eval(m); };
}

}  // namespace npf
