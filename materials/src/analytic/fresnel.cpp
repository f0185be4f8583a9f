// Unpolarised Fresnel reflectance from air (index 1). Conductors use the exact real-valued
// closed form for a complex index (the same quantity as the complex-amplitude form, without
// complex arithmetic); thin films use the complex amplitudes of npf-method-notes.md sec. 3.
#include <npf/materials/analytic/fresnel.h>

#include "fresnel_avx2.h"

#include <npf/core/clamp.h>
#include <npf/core/error.h>
#include <npf/core/simd_isa.h>
#include <npf/core/vec.h>

#include <cmath>
#include <complex>
#include <limits>
#include <string>
#include <utility>

namespace npf {

namespace {

using Complex = std::complex<double>;

double clamp01(double v) { return clamp_range(v, 0.0, 1.0); }

// Air -> real index eta. For eta < 1 total internal reflection gives 1 past the critical
// angle; from air into any denser medium (eta >= 1) it cannot happen.
double dielectric_reflectance(double c, double eta) {
    if (eta == 1.0) return 0.0;
    const double ct2 = 1.0 - (1.0 - c * c) / (eta * eta);
    if (ct2 <= 0.0) return 1.0;
    const double ct = std::sqrt(ct2);
    const double rs = (c - eta * ct) / (c + eta * ct);
    const double rp = (eta * c - ct) / (eta * c + ct);
    return clamp01(0.5 * (rs * rs + rp * rp));
}

// cos of the refraction angle in a medium of complex index n for incidence sin^2 = s2 from
// air, on the branch with Im(n cos) >= 0 (a wave that decays into the medium).
Complex refracted_cos(double s2, Complex n) {
    Complex c = std::sqrt(1.0 - s2 / (n * n));
    if ((n * c).imag() < 0.0) c = -c;
    return c;
}

// Airy reflectance of air / film (real index n2, thickness d) / base (n3 = eta3 + i k3):
// r = (r12 + r23 e^{2i beta}) / (1 + r12 r23 e^{2i beta}), beta = 2 pi n2 d cos2 / lambda, per
// polarisation, then averaged. cos2 is taken complex too, so that a film of index below 1 past
// its critical angle is an evanescent (frustrated) layer rather than a perfect mirror: then
// d = 0 reproduces the bare base for every index, as it must.
double thin_film_reflectance(double c1, double lambda_nm, double d_nm, double n2_real, double eta3,
                             double k3) {
    const double s2 = 1.0 - c1 * c1;
    const Complex n1(1.0, 0.0), n2(n2_real, 0.0), n3(eta3, k3);
    const Complex cc1(c1, 0.0);
    const Complex cc2 = refracted_cos(s2, n2);
    const Complex cc3 = refracted_cos(s2, n3);
    const Complex r12s = (n1 * cc1 - n2 * cc2) / (n1 * cc1 + n2 * cc2);
    const Complex r12p = (n2 * cc1 - n1 * cc2) / (n2 * cc1 + n1 * cc2);
    const Complex r23s = (n2 * cc2 - n3 * cc3) / (n2 * cc2 + n3 * cc3);
    const Complex r23p = (n3 * cc2 - n2 * cc3) / (n3 * cc2 + n2 * cc3);
    const Complex beta = 2.0 * kPiD * n2 * d_nm * cc2 / lambda_nm;
    const Complex e = std::exp(Complex(0.0, 2.0) * beta);
    const Complex rs = (r12s + r23s * e) / (1.0 + r12s * r23s * e);
    const Complex rp = (r12p + r23p * e) / (1.0 + r12p * r23p * e);
    const double r = 0.5 * (std::norm(rs) + std::norm(rp));
    // Non-finite only in degenerate limits (grazing onto an index-1 layer): a mirror there.
    return std::isfinite(r) ? clamp01(r) : 1.0;
}

void require_nonempty(const color::SampledSpectrum& s, const char* what) {
    if (s.empty()) throw Error("Fresnel", std::string(what) + " spectrum is empty");
}

void require_values(const color::SampledSpectrum& s, const char* what, double lo, bool lo_inclusive,
                    double hi = HUGE_VAL) {
    require_nonempty(s, what);
    for (double v : s.values()) {
        const bool ok = (lo_inclusive ? v >= lo : v > lo) && v <= hi;
        if (!ok) {
            throw Error("Fresnel", std::string(what) + " value " + std::to_string(v) + " is out of range (" +
                                       (lo_inclusive ? "[" : "(") + std::to_string(lo) + ", " +
                                       (hi == HUGE_VAL ? std::string("inf)") : std::to_string(hi) + "]") + ")");
        }
    }
}

#include "conductor_loop.h"

}  // namespace

Fresnel Fresnel::conductor(color::SampledSpectrum eta, color::SampledSpectrum k) {
    require_values(eta, "conductor eta", 0.0, false);
    require_values(k, "conductor k", 0.0, true);
    return Fresnel(Kind::Conductor, std::move(eta), std::move(k));
}

Fresnel Fresnel::dielectric(color::SampledSpectrum eta) {
    require_values(eta, "dielectric eta", 0.0, false);
    return Fresnel(Kind::Dielectric, std::move(eta));
}

Fresnel Fresnel::schlick(color::SampledSpectrum f0) {
    require_values(f0, "Schlick F0", 0.0, true, 1.0);
    return Fresnel(Kind::Schlick, std::move(f0));
}

Fresnel Fresnel::thin_film(double thickness_nm, color::SampledSpectrum film_eta, color::SampledSpectrum base_eta,
                           color::SampledSpectrum base_k) {
    if (!std::isfinite(thickness_nm) || thickness_nm < 0.0)
        throw Error("Fresnel", "thin-film thickness " + std::to_string(thickness_nm) +
                                   " nm is not a finite non-negative number");
    require_values(film_eta, "thin-film eta", 0.0, false);
    require_values(base_eta, "thin-film base eta", 0.0, false);
    require_values(base_k, "thin-film base k", 0.0, true);
    return Fresnel(Kind::ThinFilm, std::move(film_eta), std::move(base_eta), std::move(base_k), thickness_nm);
}

Fresnel Fresnel::one() { return Fresnel(); }

Fresnel::Coefficients Fresnel::coefficients(double lambda_nm) const {
    Coefficients c;
    c.lambda_nm = lambda_nm;
    switch (m_kind) {
    case Kind::Conductor:
        c.a = m_a(lambda_nm);
        c.b = m_b(lambda_nm);
        break;
    case Kind::Dielectric:
    case Kind::Schlick:
        c.a = m_a(lambda_nm);
        break;
    case Kind::ThinFilm:
        c.a = m_a(lambda_nm);
        c.b = m_b(lambda_nm);
        c.c = m_c(lambda_nm);
        break;
    case Kind::One:
        break;
    }
    return c;
}

double Fresnel::eval(double cos_theta_d, const Coefficients& k) const {
    // |cos|: a back-facing microfacet is never evaluated by AnalyticBrdf; clamp for callers.
    const double c = clamp01(std::fabs(cos_theta_d));
    switch (m_kind) {
    case Kind::Conductor: {
        double r = 0.0;
        conductor_reflectance_loop(c, &k, 1, &r);
        return r;
    }
    case Kind::Dielectric:
        return dielectric_reflectance(c, k.a);
    case Kind::Schlick: {
        const double f0 = clamp01(k.a);
        const double m = 1.0 - c, m2 = m * m;
        return f0 + (1.0 - f0) * m2 * m2 * m;
    }
    case Kind::ThinFilm:
        return thin_film_reflectance(c, k.lambda_nm, m_thickness_nm, k.a, k.b, k.c);
    case Kind::One:
        return 1.0;
    }
    return 1.0;
}

void Fresnel::eval(double cos_theta_d, const Coefficients* k, std::size_t n, double* out) const {
    if (m_kind != Kind::Conductor) {
        for (std::size_t j = 0; j < n; ++j) out[j] = eval(cos_theta_d, k[j]);
        return;
    }
    const double c = clamp01(std::fabs(cos_theta_d));
    if (simd_isa() == SimdIsa::Avx2 && fresnel_detail::avx2::conductor_reflectances(c, k, n, out)) return;
    conductor_reflectance_loop(c, k, n, out);
}

double Fresnel::eval(double cos_theta_d, double lambda_nm) const {
    if (m_kind == Kind::One) return 1.0;
    return eval(cos_theta_d, coefficients(lambda_nm));
}

Fresnel conductor_from_ior_files(const std::string& dir, const std::string& name) {
    const std::string base = dir + (dir.empty() || dir.back() == '/' ? "" : "/") + name;
    const std::string eta_path = base + ".eta.spd", k_path = base + ".k.spd";
    color::SampledSpectrum eta = color::read_spd(eta_path);
    color::SampledSpectrum k = color::read_spd(k_path);
    // Range problems name the file (the factory alone could only say "Fresnel").
    for (double v : eta.values())
        if (!(v > 0.0)) throw Error(eta_path, "refractive index " + std::to_string(v) + " is not positive");
    for (double v : k.values())
        if (!(v >= 0.0)) throw Error(k_path, "extinction coefficient " + std::to_string(v) + " is negative");
    return Fresnel::conductor(std::move(eta), std::move(k));
}

}  // namespace npf
