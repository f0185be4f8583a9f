// Image metrics of a test image against a reference of the same size (npf compare; the paper's
// Tables 1 and 2): PSNR and SSIM on the display-referred image, relMSE and MAPE on the
// scene-linear values, and the per-pixel relMSE that the heatmaps show (heatmap.h).
// Definitions, constants and the reasons for them: docs/metrics.md.
//
// In short, with t the test and r the reference:
//   display image   d = sRGB transfer (IEC 61966-2-1) of the linear Rec.709 colour clamped to
//                   [0, 1] (premultiplied colour as stored, i.e. the picture over black)
//   PSNR            10 log10(1 / MSE(d_t, d_r)), peak 1; +infinity when the MSE is 0
//   SSIM            Wang et al. 2004 on d, 11 x 11 Gaussian window (sigma 1.5), K1 = 0.01,
//                   K2 = 0.03, L = 1, per channel R, G, B; the map averaged over the channels
//                   and the compared pixels whose window lies inside the image (5 or more
//                   pixels from every border, as Wang's code and scikit-image do)
//   relMSE          mean of (t - r)^2 / (r^2 + 0.01) over the compared pixels' R, G, B
//   MAPE            mean of |t - r| / (|r| + 0.01), a fraction (x 100 for the paper's percent)
// Compared pixels: with an alpha channel (Coverage::Alpha), those with alpha > 0 in the
// reference or in the test; pixels with alpha 0 in both are left out of every metric (and
// counted: ImageMetrics::pixels). Without alpha, or with Coverage::AllPixels, every pixel.
#pragma once

#include <npf/color/display.h>
#include <npf/color/display_image.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace npf::render {

inline constexpr double kRelMseEpsilon = 1e-2;  // relMSE denominator r^2 + eps (scene-linear units^2)
inline constexpr double kMapeEpsilon = 1e-2;    // MAPE denominator |r| + eps (scene-linear units)
inline constexpr double kSsimK1 = 0.01;
inline constexpr double kSsimK2 = 0.03;
inline constexpr double kSsimSigma = 1.5;       // Gaussian window, in pixels
inline constexpr int kSsimRadius = 5;           // 11 x 11 window

enum class Coverage {
    Alpha,      // images with alpha: compare pixels with alpha > 0 in either image (default)
    AllPixels,  // compare every pixel, alpha or not
};

struct MetricOptions {
    // What the colour channels of both images hold; XYZ (D65 white at Y = 1) is converted to
    // linear Rec.709 (npf::color::xyz_to_linear_srgb) before anything else.
    color::SceneSpace input = color::SceneSpace::LinearRec709;
    Coverage coverage = Coverage::Alpha;
};

struct ImageMetrics {
    double psnr = 0.0;         // dB; +infinity when the display images agree on every compared pixel
    double ssim = 0.0;         // 1 exactly for identical images
    double relmse = 0.0;
    double mape = 0.0;         // a fraction
    double mse_display = 0.0;  // the MSE behind the PSNR (display values, peak 1)
    std::size_t pixels = 0;        // pixels compared (each with its R, G and B)
    std::size_t pixels_total = 0;  // width x height
    std::size_t ssim_pixels = 0;   // the compared pixels 5 or more from every border: SSIM's mean
};

// The metrics of `test` against `reference`. `reference_name` and `test_name` (file paths,
// usually) name the images in errors. Throws npf::Error for: 3 or 4 channels only; a pixel
// buffer that does not match the size; different sizes or channel counts (alpha in one image
// only); an empty image; a NaN or infinite value (naming the pixel and channel); no pixel to
// compare (alpha 0 everywhere in both); no compared pixel where SSIM's window fits (images
// smaller than 11 x 11, or covered only within 5 pixels of the border).
ImageMetrics compare_images(const color::FloatImage& reference, const color::FloatImage& test,
                            const MetricOptions& options = {}, const std::string& reference_name = "reference",
                            const std::string& test_name = "test");

// Per-pixel relMSE: the mean over R, G, B of (t - r)^2 / (r^2 + kRelMseEpsilon), rows top to
// bottom; `covered` says which pixels the metrics compare (the others hold 0 and show black in
// a heatmap). Same checks and errors as compare_images.
struct RelMseMap {
    std::size_t width = 0, height = 0;
    std::vector<double> values;          // width * height
    std::vector<unsigned char> covered;  // width * height, 1 or 0
};
RelMseMap relmse_map(const color::FloatImage& reference, const color::FloatImage& test,
                     const MetricOptions& options = {}, const std::string& reference_name = "reference",
                     const std::string& test_name = "test");

// The noise floor of a PSNR: how much of the display MSE behind ImageMetrics::psnr is Monte
// Carlo noise (it changes with the seed) rather than a difference of the materials (it does
// not), as a PSNR in dB: the PSNR a test would score whose only error were that noise. Both
// kinds are computed over exactly the pixels the PSNR compares (those of the seed-1 pair) and
// divided by the same count, so the noise MSE is a part of the PSNR's MSE. docs/metrics.md.
//
// Paired: the same reference and test rendered again at a second seed. With the display errors
// e_s = d(test_s) - d(reference_s) (d = display_value) and e_s = b + n_s, b the error that stays
// from seed to seed and n_1, n_2 independent noise of mean 0 and equal spread,
//   E[mean(e_1^2)] = mean(b^2) + E[mean(n^2)]   and   E[mean((e_1 - e_2)^2)] / 2 = E[mean(n^2)],
// so mse_noise = mean((e_1 - e_2)^2) / 2 estimates the noise part of the PSNR's MSE without
// bias. It sees the noise of the difference as rendered: with shared random numbers (same seed,
// docs/render.md) much of each image's noise cancels in e_s, and the floor says how much.
//
// Reference: only the reference rendered at a second seed. mse_noise = mean((d(r_2) - d(r_1))^2),
// i.e. the floor is the PSNR of the reference against itself: the noise part of a test whose
// noise is like the reference's and independent of it (a different seed). For a test rendered
// at the reference's seed it overstates the noise (understates the floor) by what the shared
// random numbers cancel; use the paired floor there.
enum class NoiseFloorKind {
    Paired,     // reference and test at a second seed
    Reference,  // the reference alone at a second seed
};

struct NoiseFloor {
    NoiseFloorKind kind = NoiseFloorKind::Paired;
    double psnr = 0.0;       // dB, same display encoding and peak (1) as the PSNR; +infinity without noise
    double mse_noise = 0.0;  // the noise part of ImageMetrics::mse_display (display values, peak 1)
};

// "paired" or "reference" (npf compare's noise_floor_kind).
const char* noise_floor_kind_name(NoiseFloorKind kind);

// The seed of a paired comparison's second pair, the one its noise floor is measured with: the
// next one (npf convert's prediction, the batch's validation renders, docs/metrics.md sec. 5).
inline std::uint64_t noise_floor_seed(std::uint64_t seed) { return seed + 1; }

// The paired floor of compare_images(reference, test): `reference2` and `test2` are the same two
// materials rendered at a second seed (noise_floor_seed). All four images must have the same size and channel
// count; same checks and errors as compare_images (naming the file).
NoiseFloor paired_noise_floor(const color::FloatImage& reference, const color::FloatImage& test,
                              const color::FloatImage& reference2, const color::FloatImage& test2,
                              const MetricOptions& options = {}, const std::string& reference_name = "reference",
                              const std::string& test_name = "test",
                              const std::string& reference2_name = "reference at the second seed",
                              const std::string& test2_name = "test at the second seed");

// The reference floor of compare_images(reference, test): `reference2` is the reference rendered
// at a second seed (`test` only decides which pixels the PSNR compares).
NoiseFloor reference_noise_floor(const color::FloatImage& reference, const color::FloatImage& test,
                                 const color::FloatImage& reference2, const MetricOptions& options = {},
                                 const std::string& reference_name = "reference", const std::string& test_name = "test",
                                 const std::string& reference2_name = "reference at the second seed");

// Within this many dB of its floor (PSNR >= floor - 3.01 dB) at least half of the measured
// MSE is noise: the PSNR then measures the renders' noise more than the materials' difference.
inline constexpr double kNoiseLimitedMarginDb = 3.0102999566398120;  // 10 log10(2)

// True when mse_display <= 2 mse_noise and there is noise (an exact comparison with no noise
// is never noise-limited).
bool noise_limited(const ImageMetrics& metrics, const NoiseFloor& floor);

// The display value the PSNR and SSIM see for one linear value: clamped to [0, 1], then the
// sRGB transfer function (12.92 v up to 0.0031308, 1.055 v^(1/2.4) - 0.055 above).
double display_value(double linear);

// The SSIM map of two single-channel planes of `width` x `height` values (rows top to bottom)
// with dynamic range 1: the Gaussian-windowed statistics at every pixel. Within 5 pixels of a
// border the window is cut to the image and its weights renormalised, so every pixel has a
// value (compare_images averages only the pixels where the whole window fits). Where the local
// means, variances and covariance agree exactly the value is exactly 1. Throws npf::Error when
// the sizes disagree.
std::vector<double> ssim_map(const std::vector<double>& x, const std::vector<double>& y, std::size_t width,
                             std::size_t height);

}  // namespace npf::render
