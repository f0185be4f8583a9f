// Thin-film Fresnel edit (paper sec. 4.3.4): a dielectric film (thickness d, index eta_2) on the
// material, by the Airy reflectance of air / film / base (Belcour & Barla 2017; the exact
// complex-amplitude form of npf/materials/analytic/fresnel.h).
//
// Let K(theta_d) = rho_s F(theta_d) be the material's specular colour and R_film, R_bare the
// Airy reflectance with the film and without it (d = 0, the bare base). Two modes:
//   Ratio (default): K' = K R_film / R_bare. The measured F's departures from any Fresnel curve
//     are kept; d = 0 returns K exactly.
//   Replace: K' = K(0) R_film(theta_d) / R_bare(0). F becomes the Airy curve of the base (given
//     or fitted); d = 0 returns the base's own Fresnel (normalised as the gauge wants).
// Either way the result is put back in the gauge: F' = 1 in the first theta_d cell, the rest in
// rho_s. D and G are untouched.
//
// The base index: given (a number, a metal of the shipped tables, or eta and k spectra), or fitted
// per channel to the material's own F: F0 = 4 rho_s (the microfacet relation in this gauge,
// rho_s = F0 / 4), and along the one-parameter family of complex indices with that F0 the one
// whose normalised Fresnel curve F(theta_d) / F(0) fits the stored F best (theta_d <= 80
// degrees). RGB models are evaluated spectrally (1 nm, 360..830 nm, the base's index linear
// between the channels' dominant wavelengths 611, 549 and 464 nm) and brought back to RGB by the
// colour of the reflectance spectra, so that thick films do not alias.
#pragma once

#include <npf/color/spectrum.h>
#include <npf/edit/edit_record.h>
#include <npf/shading/npf_model.h>

#include <string>
#include <vector>

namespace npf::edit {

struct FilmBase {
    bool fitted = true;                  // from the material's own F (above); else eta, k
    color::SampledSpectrum eta, k;       // given base; k empty means 0 (a dielectric)
    std::string label;                   // for the record ("Au", "eta 1.5", ...)
};

enum class FilmMode { Ratio, Replace };

struct ThinFilm {
    double thickness_nm = 0.0;
    color::SampledSpectrum film_eta = color::SampledSpectrum::constant(1.33);
    FilmBase base;
    FilmMode mode = FilmMode::Ratio;
};

// The fitted base index per stored channel (RGB: at 611, 549 and 464 nm).
struct FittedBase {
    std::vector<double> wavelengths_nm, eta, k, f0;
    std::vector<double> rms;  // misfit of the normalised curve, per channel
    std::size_t clamped_f0 = 0;  // channels whose 4 rho_s was outside [1e-4, 0.98]
};
FittedBase fit_base_ior(const NpfModel& model);

// Unpolarised Fresnel reflectance from air onto the complex index eta + i k at cos theta.
double fresnel_reflectance(double cos_theta, double eta, double k);

// Throws npf::Error (source "thin film") for a negative or non-finite thickness, film or base
// indices that are not positive, or a base without reflectance (index 1).
NpfModel apply_thin_film(const NpfModel& model, const ThinFilm& film, EditRecord* record = nullptr);

}  // namespace npf::edit
