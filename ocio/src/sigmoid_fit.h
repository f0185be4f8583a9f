// Private to npf_color: fitting sigmoid-polynomial spectra to colours, and the coefficient
// table behind rgb_to_sigmoid (rgb_sigmoid.h).
#pragma once

#include <npf/color/rgb_sigmoid.h>

#include <array>
#include <cstddef>
#include <vector>

namespace npf::color::detail {

// Coefficients of the polynomial in the normalised wavelength x = (l - 360) / 470, highest
// power first: better conditioned than nanometres for fitting and interpolating.
using SigmoidCoefficients = std::array<double, 3>;

inline constexpr double kSigmoidFirstNm = 360.0;
inline constexpr double kSigmoidSpanNm = 470.0;

// The same sigmoid with coefficients for l in nanometres.
RgbSigmoid to_nanometres(const SigmoidCoefficients& c);

// How a spectrum's colour is integrated while fitting.
enum class Quadrature {
    // The convention's own rule: the spectrum at every whole nanometre 360..830 (471 points).
    Exact,
    // The spectrum at every 5 nm (95 points), the 1 nm values between interpolated by cubics
    // through the four nearest: the same colour to about 1e-5 for these smooth spectra, five
    // times cheaper. For building the table.
    Coarse,
};

// Gauss-Newton on the CIELAB difference between the spectrum's colour and `rgb` (pbrt-v4's
// rgb2spec_opt, with an analytic Jacobian), starting from `c` and leaving the best coefficients
// found there; coefficients are kept within +-200 (pbrt's bound) so that colours out of the
// family's reach do not diverge. Stops when the squared Lab residual is below
// `tolerance_squared` or after `max_iterations`. Returns the final squared residual.
double fit_sigmoid(const Rgb& rgb, SigmoidCoefficients& c, Quadrature quadrature, double tolerance_squared,
                   int max_iterations);

// The coefficient table (pbrt-v4's RGBToSpectrumTable layout): for each largest component m,
// z = rgb[m] on a nonlinear grid (smoothstep(smoothstep(k / (n - 1))): dense near 0 and 1), and
// x = rgb[m + 1] / z, y = rgb[m + 2] / z on uniform grids.
class SigmoidTable {
public:
    static constexpr int kResolution = 32;
    static constexpr std::size_t kValues = std::size_t(3) * kResolution * kResolution * kResolution * 3;

    // Fits every node, on up to 16 threads (npf::parallel_for): about 0.7 s of CPU. The same
    // table on any number of threads. The build does it once (make_sigmoid_table.cpp).
    static SigmoidTable fit();
    // A table fitted before: kValues coefficients in the layout [largest][z][y][x][3].
    explicit SigmoidTable(std::vector<float> coefficients);

    // Trilinear interpolation; `rgb` in [0, 1]^3, not grey.
    SigmoidCoefficients lookup(const Rgb& rgb) const;
    const std::vector<float>& coefficients() const { return m_coefficients; }

private:
    SigmoidTable();
    std::size_t index(int largest, int zi, int yi, int xi) const;
    void fit_column(int largest, int yi, int xi);

    std::array<double, kResolution> m_z;
    std::vector<float> m_coefficients;  // [largest][z][y][x][3]
};

// The table fitted when npf was built (sigmoid_table_data.cpp, generated), read on first use
// (thread-safe).
const SigmoidTable& sigmoid_table();

}  // namespace npf::color::detail
