#include <npf/edit/thin_film.h>

#include "tables.h"

#include <npf/materials/analytic/fresnel.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/vec.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

namespace npf::edit {

namespace {

const char* const kSource = "thin film";
// Dominant wavelengths of the sRGB primaries R, G, B (nm): where an RGB channel's index sits.
constexpr double kRgbWavelengths[3] = {611.0, 549.0, 464.0};
constexpr double kFitMaxThetaDeg = 80.0;
// Above this RMS misfit of the normalised F curve the fitted base is reported as a guess.
constexpr double kPoorFit = 0.05;

// The complex index with normal reflectance f0 on the one-parameter family t in [-1, 1]:
// k = k_max (1 - |t|), eta on the lower root (metals, eta < (1 + f0) / (1 - f0)) for t < 0 and on
// the upper root (dielectrics at t = 1) for t >= 0. f0 = ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2).
void index_of(double f0, double t, double& eta, double& k) {
    const double k_max = 2.0 * std::sqrt(f0) / (1.0 - f0);
    k = k_max * (1.0 - std::fabs(t));
    const double disc = std::max(0.0, (1.0 + f0) * (1.0 + f0) - (1.0 - f0) * (1.0 - f0) * (1.0 + k * k));
    eta = ((1.0 + f0) + (t < 0.0 ? -1.0 : 1.0) * std::sqrt(disc)) / (1.0 - f0);
    eta = std::max(eta, 1e-6);
}

struct Curve {
    std::vector<double> cos_theta, target;  // F(theta_k) / F(theta_0) at the fitted cells
    double cos0 = 1.0;
};

double misfit(const Curve& c, double eta, double k) {
    const double r0 = fresnel_reflectance(c.cos0, eta, k);
    if (!(r0 > 0.0)) return INFINITY;
    double s = 0.0;
    for (std::size_t i = 0; i < c.cos_theta.size(); ++i) {
        const double e = fresnel_reflectance(c.cos_theta[i], eta, k) / r0 - c.target[i];
        s += e * e;
    }
    return s / double(std::max<std::size_t>(1, c.cos_theta.size()));
}

std::string spectrum_text(const color::SampledSpectrum& s) {
    if (s.empty()) return "0";
    const auto [lo, hi] = std::minmax_element(s.values().begin(), s.values().end());
    return *lo == *hi ? number_text(*lo, 4) : number_text(*lo, 4) + ".." + number_text(*hi, 4);
}

std::string range_text(const std::vector<double>& v) {
    if (v.empty()) return "-";
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return *lo == *hi ? number_text(*lo, 4) : number_text(*lo, 4) + ".." + number_text(*hi, 4);
}

void require_positive(const color::SampledSpectrum& s, const std::string& what, bool allow_zero) {
    if (s.empty()) throw Error(kSource, what + " is empty");
    for (double v : s.values()) {
        if (!std::isfinite(v) || v < 0.0 || (!allow_zero && v == 0.0)) {
            throw Error(kSource, what + " value " + number_text(v) + " is not " + (allow_zero ? ">= 0" : "positive"));
        }
    }
}

// The base's complex index as spectra, given or fitted to the model's F (`fitted` then).
struct BaseIndex {
    color::SampledSpectrum eta, k;
    FittedBase fitted;
};

BaseIndex base_index(const NpfModel& model, const FilmBase& given) {
    BaseIndex b;
    if (given.fitted) {
        b.fitted = fit_base_ior(model);
        std::vector<double> wl = b.fitted.wavelengths_nm, eta = b.fitted.eta, k = b.fitted.k;
        if (model.channels.is_rgb()) {  // ascending: B, G, R
            std::reverse(wl.begin(), wl.end());
            std::reverse(eta.begin(), eta.end());
            std::reverse(k.begin(), k.end());
        }
        b.eta = color::SampledSpectrum(wl, eta);
        b.k = color::SampledSpectrum(wl, k);
    } else {
        require_positive(given.eta, "the base index eta", false);
        b.eta = given.eta;
        b.k = given.k.empty() ? color::SampledSpectrum::constant(0.0) : given.k;
        require_positive(b.k, "the base index k", true);
    }
    return b;
}

// R_film and R_bare per channel at every theta_d centre of F: [channels][f_theta].
struct Reflectances {
    std::vector<double> film, bare;
    std::size_t negative = 0;  // RGB components below 0 (outside the gamut), set to 0
};

double theta_d_cosine(int i, int n) { return std::cos(kHalfPiD * (i + 0.5) / n); }

// A spectral model's channels: the reflectances at their wavelengths.
void spectral_reflectances(const NpfModel& model, const Fresnel& with, const Fresnel& bare, Reflectances& r) {
    const int n = model.f_theta;
    const std::vector<float>& wl = model.channels.wavelengths();
    for (std::size_t c = 0; c < model.channel_count(); ++c) {
        const Fresnel::Coefficients kw = with.coefficients(wl[c]), kb = bare.coefficients(wl[c]);
        for (int i = 0; i < n; ++i) {
            const double ct = theta_d_cosine(i, n);
            r.film[c * std::size_t(n) + std::size_t(i)] = with.eval(ct, kw);
            r.bare[c * std::size_t(n) + std::size_t(i)] = bare.eval(ct, kb);
        }
    }
}

// An RGB model's channels: the colours of the reflectance spectra (1 nm, 360..830 nm).
void rgb_reflectances(const NpfModel& model, const Fresnel& with, const Fresnel& bare, Reflectances& r) {
    const int n = model.f_theta;
    std::vector<float> grid;
    for (int l = 360; l <= 830; ++l) grid.push_back(float(l));
    const auto w = color::linear_srgb_weights(grid);
    std::vector<Fresnel::Coefficients> kw, kb;
    for (float l : grid) kw.push_back(with.coefficients(l)), kb.push_back(bare.coefficients(l));
    for (int i = 0; i < n; ++i) {
        const double ct = theta_d_cosine(i, n);
        double a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
        for (std::size_t j = 0; j < grid.size(); ++j) {
            const double rf = with.eval(ct, kw[j]), rb = bare.eval(ct, kb[j]);
            for (int c = 0; c < 3; ++c) a[c] += w[std::size_t(c)][j] * rf, b[c] += w[std::size_t(c)][j] * rb;
        }
        for (std::size_t c = 0; c < 3; ++c) {
            if (a[c] < 0.0) a[c] = 0.0, ++r.negative;
            r.film[c * std::size_t(n) + std::size_t(i)] = a[c];
            r.bare[c * std::size_t(n) + std::size_t(i)] = b[c];
        }
    }
}

Reflectances reflectances(const NpfModel& model, const Fresnel& with, const Fresnel& bare) {
    Reflectances r;
    r.film.resize(model.channel_count() * std::size_t(model.f_theta));
    r.bare.resize(r.film.size());
    if (model.channels.is_rgb()) rgb_reflectances(model, with, bare, r);
    else spectral_reflectances(model, with, bare, r);
    return r;
}

// Channel c of `out` (a copy of `model`) with the film: F and rho_s by the film's mode.
void apply_to_channel(const NpfModel& model, FilmMode mode, const Reflectances& r, const BaseIndex& base, std::size_t c,
                      NpfModel& out) {
    const int n = model.f_theta;
    const double* rf = &r.film[c * std::size_t(n)];
    const double* rb = &r.bare[c * std::size_t(n)];
    float* f = out.F.data() + c * std::size_t(n);
    const float* f_in = model.F.data() + c * std::size_t(n);
    const double k0_before = double(model.rho_s[c]) * f_in[0];
    for (int i = 0; i < n; ++i) {
        if (!(rb[i] > 1e-12)) {
            throw Error(kSource, "the base (index " + number_text(base.eta(kRgbWavelengths[1]), 4) +
                                     ") reflects nothing: the film's effect is undefined");
        }
    }
    if (mode == FilmMode::Ratio) {
        const double g = rf[0] / rb[0];
        if (g > 0.0) {
            for (int i = 0; i < n; ++i) f[i] = float(double(f_in[i]) * (rf[i] / rb[i]) / g);
            out.rho_s[c] = float(double(model.rho_s[c]) * g);
        } else {  // the film cancels the reflection at normal incidence
            for (int i = 0; i < n; ++i) f[i] = float(double(f_in[i]) * (rf[i] / rb[i]));
        }
    } else {
        if (rf[0] > 0.0) {
            for (int i = 0; i < n; ++i) f[i] = float(rf[i] / rf[0]);
            out.rho_s[c] = float(k0_before * rf[0] / rb[0]);
        } else {
            for (int i = 0; i < n; ++i) f[i] = float(rf[i] / rb[0]);
            out.rho_s[c] = float(k0_before);
        }
    }
}

// rho_s F at normal incidence per channel.
std::vector<double> normal_specular(const NpfModel& model) {
    std::vector<double> k0(model.channel_count());
    for (std::size_t c = 0; c < k0.size(); ++c) k0[c] = double(model.rho_s[c]) * model.F[c * std::size_t(model.f_theta)];
    return k0;
}

// "(r, g, b)" of a per-channel quantity (its colour for a spectral model).
std::string colour_text(const NpfModel& model, const std::vector<double>& v) {
    std::vector<double> rgb = v;
    if (!model.channels.is_rgb()) {
        const auto w = color::linear_srgb_weights(model.channels.wavelengths());
        rgb.assign(3, 0.0);
        for (std::size_t k = 0; k < 3; ++k) {
            for (std::size_t c = 0; c < v.size(); ++c) rgb[k] += w[k][c] * v[c];
        }
    }
    return "(" + number_text(rgb[0], 4) + ", " + number_text(rgb[1], 4) + ", " + number_text(rgb[2], 4) + ")";
}

// The warnings of a film on `model`: a poorly fitted base, colours out of gamut, fringes the
// stored wavelengths do not resolve.
void warn_film(const NpfModel& model, const ThinFilm& film, const FittedBase& fitted, std::size_t negative,
               EditRecord* record) {
    if (film.base.fitted && fitted.clamped_f0 > 0) {
        detail::warn(record, std::to_string(fitted.clamped_f0) + " channel(s) have 4 rho_s outside [1e-4, 0.98] (not a "
                             "microfacet material's gauge): the fitted base's F0 was clamped");
    }
    if (film.base.fitted && !fitted.rms.empty() && *std::max_element(fitted.rms.begin(), fitted.rms.end()) > kPoorFit) {
        detail::warn(record, "the material's F is far from every Fresnel curve with F0 = 4 rho_s (normalised curve RMS up to " +
                                 number_text(*std::max_element(fitted.rms.begin(), fitted.rms.end()), 3) +
                                 "): the fitted base index is a rough guess; give the base (a metal, eta or eta,k) if known");
    }
    if (negative > 0) {
        detail::warn(record, "the film's colour lies outside the sRGB gamut at " + std::to_string(negative) +
                                 " theta_d cell(s); negative components set to 0");
    }
    if (!model.channels.is_rgb() && film.thickness_nm > 0.0) {
        const std::vector<float>& wl = model.channels.wavelengths();
        double spacing = 0.0;
        for (std::size_t c = 1; c < wl.size(); ++c) spacing = std::max(spacing, double(wl[c] - wl[c - 1]));
        const double l0 = wl.front(), period = l0 * l0 / (2.0 * film.film_eta(l0) * film.thickness_nm);
        if (wl.size() < 2 || spacing > 0.5 * period) {
            detail::warn(record, "the stored wavelengths (spacing up to " + number_text(spacing, 4) +
                                     " nm) do not resolve the film's fringes (period about " + number_text(period, 3) +
                                     " nm at " + number_text(l0, 4) + " nm): the colours alias");
        }
    }
}

void record_film(const NpfModel& model, const NpfModel& out, const ThinFilm& film, const BaseIndex& b,
                 std::size_t negative, EditRecord& record) {
    std::string base;
    if (film.base.fitted) {
        base = "fitted to F (F0 = 4 rho_s " + range_text(b.fitted.f0) + ", eta " + range_text(b.fitted.eta) + ", k " +
               range_text(b.fitted.k) + ", curve RMS " + range_text(b.fitted.rms) + ")";
    } else {
        base = (film.base.label.empty() ? "given" : film.base.label) + " (eta " + spectrum_text(b.eta) + ", k " +
               spectrum_text(b.k) + ")";
    }
    record.summary = "thin film " + number_text(film.thickness_nm) + " nm of index " + spectrum_text(film.film_eta) +
                     " on base " + base + ", mode " + (film.mode == FilmMode::Ratio ? "ratio" : "replace") +
                     ": rho_s F at normal incidence " + colour_text(model, normal_specular(model)) + " -> " +
                     colour_text(model, normal_specular(out));
    warn_film(model, film, b.fitted, negative, &record);
}

}  // namespace

double fresnel_reflectance(double cos_theta, double eta, double k) {
    using Complex = std::complex<double>;
    const double c = std::clamp(std::fabs(cos_theta), 0.0, 1.0), s2 = 1.0 - c * c;
    const Complex n(eta, k);
    Complex ct = std::sqrt(1.0 - s2 / (n * n));
    if ((n * ct).imag() < 0.0) ct = -ct;  // the wave that decays into the medium
    const Complex rs = (c - n * ct) / (c + n * ct);
    const Complex rp = (n * c - ct) / (n * c + ct);
    const double r = 0.5 * (std::norm(rs) + std::norm(rp));
    return std::isfinite(r) ? std::clamp(r, 0.0, 1.0) : 1.0;
}

FittedBase fit_base_ior(const NpfModel& model) {
    FittedBase out;
    const std::size_t C = model.channel_count();
    const int n = model.f_theta;
    Curve curve;
    curve.cos0 = std::cos(kHalfPiD * 0.5 / n);
    std::vector<int> cells;
    for (int i = 1; i < n; ++i) {
        const double theta = kHalfPiD * (i + 0.5) / n;
        if (theta * 180.0 / kPiD > kFitMaxThetaDeg) break;
        cells.push_back(i);
        curve.cos_theta.push_back(std::cos(theta));
    }
    for (std::size_t c = 0; c < C; ++c) {
        const float* f = model.F.data() + c * std::size_t(n);
        const double k0 = double(model.rho_s[c]) * f[0];
        double f0 = 4.0 * k0;
        if (!(f0 >= 1e-4 && f0 <= 0.98)) {
            ++out.clamped_f0;
            f0 = std::clamp(std::isfinite(f0) ? f0 : 0.04, 1e-4, 0.98);
        }
        curve.target.clear();
        for (int i : cells) curve.target.push_back(f[0] > 0.f ? double(f[i]) / f[0] : 1.0);
        // A coarse scan of the family, then golden-section search around the best point.
        double best_t = 1.0, best = INFINITY;
        constexpr int kScan = 200;
        for (int s = 0; s <= kScan; ++s) {
            const double t = -1.0 + 2.0 * s / kScan;
            double eta, k;
            index_of(f0, t, eta, k);
            const double e = misfit(curve, eta, k);
            if (e < best) best = e, best_t = t;
        }
        double lo = std::max(-1.0, best_t - 2.0 / kScan), hi = std::min(1.0, best_t + 2.0 / kScan);
        const double g = 0.5 * (std::sqrt(5.0) - 1.0);
        auto cost = [&](double t) {
            double eta, k;
            index_of(f0, t, eta, k);
            return misfit(curve, eta, k);
        };
        double a = hi - g * (hi - lo), b = lo + g * (hi - lo), fa = cost(a), fb = cost(b);
        for (int it = 0; it < 40; ++it) {
            if (fa < fb) {
                hi = b, b = a, fb = fa, a = hi - g * (hi - lo), fa = cost(a);
            } else {
                lo = a, a = b, fa = fb, b = lo + g * (hi - lo), fb = cost(b);
            }
        }
        const double t = fa < fb ? a : b;
        if (std::min(fa, fb) < best) best_t = t, best = std::min(fa, fb);
        double eta, k;
        index_of(f0, best_t, eta, k);
        out.eta.push_back(eta);
        out.k.push_back(k);
        out.f0.push_back(f0);
        out.rms.push_back(std::sqrt(best));
        out.wavelengths_nm.push_back(model.channels.is_rgb() ? kRgbWavelengths[c] : double(model.channels.wavelengths()[c]));
    }
    return out;
}

NpfModel apply_thin_film(const NpfModel& model, const ThinFilm& film, EditRecord* record) {
    if (!std::isfinite(film.thickness_nm) || film.thickness_nm < 0.0) {
        throw Error(kSource, "thickness " + number_text(film.thickness_nm) + " nm is not a finite number >= 0");
    }
    require_positive(film.film_eta, "the film index", false);
    const BaseIndex base = base_index(model, film.base);
    const Fresnel with = Fresnel::thin_film(film.thickness_nm, film.film_eta, base.eta, base.k);
    const Fresnel bare = Fresnel::thin_film(0.0, film.film_eta, base.eta, base.k);
    const Reflectances r = reflectances(model, with, bare);
    NpfModel out = model;
    for (std::size_t c = 0; c < model.channel_count(); ++c) apply_to_channel(model, film.mode, r, base, c, out);
    out.validate(kSource);
    if (record) record_film(model, out, film, base, r.negative, *record);
    if (out.F != model.F) detail::drop_detail(out, record, "the film changes F, and the residual was fitted under the old one");
    return out;
}

}  // namespace npf::edit
