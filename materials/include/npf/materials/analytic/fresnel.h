// Fresnel reflectance of a smooth interface, per wavelength: conductors with complex indices
// (from tables such as ../shared/data/ior/*.spd), dielectrics, Schlick's approximation, and the
// Airy reflectance of a thin dielectric film on a conductor or dielectric base (Belcour &
// Barla 2017; docs in npf-method-notes.md sec. 3). Unpolarised, from air (index 1).
#pragma once

#include <npf/color/spectrum.h>

#include <cstddef>
#include <string>
#include <utility>

namespace npf {

class Fresnel {
public:
    enum class Kind { Conductor, Dielectric, Schlick, ThinFilm, One };

    Fresnel() = default;  // one()
    static Fresnel conductor(color::SampledSpectrum eta, color::SampledSpectrum k);
    static Fresnel dielectric(color::SampledSpectrum eta);
    static Fresnel schlick(color::SampledSpectrum f0);
    // A film of `thickness_nm` and index `film_eta` on a base of complex index base_eta + i base_k
    // (base_k = 0 for a dielectric base). thickness 0 gives the bare base's Fresnel exactly.
    // A film of index below 1 past its critical angle is treated as an evanescent layer
    // (complex cos theta_2) rather than as total reflection, which keeps thickness 0 exact.
    static Fresnel thin_film(double thickness_nm, color::SampledSpectrum film_eta, color::SampledSpectrum base_eta,
                             color::SampledSpectrum base_k);
    static Fresnel one();  // F = 1 (a perfect mirror-like reflector, for tests)

    // Reflectance for the cosine of the angle between the incident direction and the
    // microfacet normal (cos theta_d), at `lambda_nm`. In [0, 1].
    double eval(double cos_theta_d, double lambda_nm) const;
    Kind kind() const { return m_kind; }

    // The spectra looked up at one wavelength, so that callers evaluating many angles at
    // fixed wavelengths (AnalyticBrdf's RGB grid) search the tables once:
    // eval(c, coefficients(l)) == eval(c, l).
    struct Coefficients {
        double a = 0.0, b = 0.0, c = 0.0;  // m_a, m_b, m_c at lambda_nm (0 where unused)
        double lambda_nm = 0.0;
    };
    Coefficients coefficients(double lambda_nm) const;
    double eval(double cos_theta_d, const Coefficients& coefficients) const;
    // out[j] = eval(cos_theta_d, coefficients[j]) for j < n, the same bits: one angle at many
    // wavelengths, the conductor's arithmetic vectorised across them (a spectral source's
    // evaluation was mostly this).
    void eval(double cos_theta_d, const Coefficients* coefficients, std::size_t n, double* out) const;

private:
    Fresnel(Kind kind, color::SampledSpectrum a, color::SampledSpectrum b = {}, color::SampledSpectrum c = {},
            double thickness_nm = 0.0)
        : m_kind(kind), m_a(std::move(a)), m_b(std::move(b)), m_c(std::move(c)), m_thickness_nm(thickness_nm) {}

    Kind m_kind = Kind::One;
    color::SampledSpectrum m_a, m_b, m_c;  // eta/k, eta, f0, or film eta / base eta / base k
    double m_thickness_nm = 0.0;
};

// Reads a metal's complex index from `<dir>/<name>.eta.spd` and `<dir>/<name>.k.spd`.
Fresnel conductor_from_ior_files(const std::string& dir, const std::string& name);

}  // namespace npf
