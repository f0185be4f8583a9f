// The environment map's texels as spectra, for spectral renders: each linear Rec.709 texel is
// upsampled once with Jakob & Hanika's sigmoid (npf::color::RgbUnboundedSpectrum: scale
// 2 max(rgb) times a sigmoid in [0, 1], linear in the texel's magnitude, flat for greys).
//
// What the values mean. An emitter of RGB colour c has the spectral radiance
//     L(l) = U_c(l) E_D65(l) / integral(E_D65 ybar)
// (npf::color::RgbIlluminantSpectrum: RGB (1, 1, 1) is D65 at unit luminance). The renderer
// keeps the smooth factor U_c here and folds the D65 factor into the colour-matching weights
// (npf::color::xyz_weights: the colour of a reflectance-like spectrum under D65): the product
// f_r cos * U_c is smooth, so the quadrature over the material's wavelengths integrates it
// accurately, whereas D65's 5 nm spikes would alias at a coarse quadrature. The two are the
// same integral:  XYZ = integral(cmf L f) = integral(cmf E_D65 (U_c f)) / integral(E_D65 ybar).
#pragma once

#include <npf/color/rgb_sigmoid.h>
#include <npf/render/environment_map.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace npf::render {

class EnvironmentSpectra {
public:
    // Upsamples every texel of `map` on `threads` threads (0: all cores): about 0.1 us per
    // texel (a 1024 x 512 map in 0.03 s on 2 cores).
    explicit EnvironmentSpectra(const EnvironmentMap& map, unsigned threads = 0);

    // U_c(l) of texel `texel` at `n` wavelengths (nm), written to `out`.
    void eval(std::uint32_t texel, const float* wavelengths_nm, std::size_t n, float* out) const {
        const color::RgbUnboundedSpectrum& s = m_spectra[texel];
        if (!(s.scale() > 0.0)) {
            for (std::size_t k = 0; k < n; ++k) out[k] = 0.f;
            return;
        }
        for (std::size_t k = 0; k < n; ++k) out[k] = float(s(double(wavelengths_nm[k])));
    }

    const color::RgbUnboundedSpectrum& spectrum(std::uint32_t texel) const { return m_spectra[texel]; }

private:
    std::vector<color::RgbUnboundedSpectrum> m_spectra;
};

}  // namespace npf::render
