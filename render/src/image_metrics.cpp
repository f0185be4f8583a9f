// PSNR, SSIM, relMSE and MAPE of a test image against a reference (docs/metrics.md).
#include <npf/render/image_metrics.h>

#include <npf/color/spectrum.h>
#include <npf/core/error.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace npf::render {

namespace {

std::string size_text(const color::FloatImage& image) {
    return std::to_string(image.width) + " x " + std::to_string(image.height);
}

std::string channel_text(int channels) {
    return std::to_string(channels) + (channels == 4 ? " channels (colour and alpha)" : " channels (colour, no alpha)");
}

void check_shape(const color::FloatImage& image, const std::string& name) {
    if (image.channels != 3 && image.channels != 4)
        throw Error(name, "has " + std::to_string(image.channels) + " channels; the metrics take 3 (colour) or 4 "
                                                                    "(colour and alpha)");
    const std::size_t nc = static_cast<std::size_t>(image.channels);
    if (image.width != 0 && image.height > std::numeric_limits<std::size_t>::max() / nc / image.width)
        throw Error(name, "image size " + size_text(image) + " is too large");
    if (image.pixels.size() != image.width * image.height * nc)
        throw Error(name, "holds " + std::to_string(image.pixels.size()) + " values, not " + size_text(image) +
                              " x " + std::to_string(image.channels));
}

void check_finite(const color::FloatImage& image, const std::string& name, color::SceneSpace space) {
    static const char* const kRgb[] = {"R", "G", "B", "A"};
    static const char* const kXyz[] = {"X", "Y", "Z", "A"};
    const char* const* channel_names = space == color::SceneSpace::CieXyzD65 ? kXyz : kRgb;
    const std::size_t nc = static_cast<std::size_t>(image.channels);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const float v = image.pixels[i];
        if (std::isfinite(v)) continue;
        const std::size_t pixel = i / nc, c = i % nc;
        throw Error(name, "pixel (" + std::to_string(pixel % image.width) + ", " + std::to_string(pixel / image.width) +
                              ") channel " + channel_names[c] + " is " + (std::isnan(v) ? "NaN" : "infinite") +
                              "; images with NaN or infinite values cannot be compared");
    }
}

// Both images checked against each other, colours as linear Rec.709 in double, and which
// pixels the metrics compare.
struct Prepared {
    std::size_t width = 0, height = 0;
    std::vector<double> reference, test;  // width * height * 3
    std::vector<unsigned char> covered;   // width * height
    std::size_t covered_count = 0;
};

std::vector<double> linear_rgb(const color::FloatImage& image, color::SceneSpace space) {
    const std::size_t count = image.width * image.height, nc = static_cast<std::size_t>(image.channels);
    std::vector<double> rgb(count * 3);
    for (std::size_t p = 0; p < count; ++p) {
        const float* px = &image.pixels[p * nc];
        std::array<double, 3> c = {px[0], px[1], px[2]};
        if (space == color::SceneSpace::CieXyzD65) c = color::xyz_to_linear_srgb(c);
        std::copy(c.begin(), c.end(), &rgb[p * 3]);
    }
    return rgb;
}

// `other` has the reference's size and channel count (the reference itself already checked).
void check_matches(const color::FloatImage& reference, const color::FloatImage& other,
                   const std::string& reference_name, const std::string& other_name) {
    check_shape(other, other_name);
    if (reference.width != other.width || reference.height != other.height)
        throw Error(other_name, "is " + size_text(other) + " but the reference " + reference_name + " is " +
                                    size_text(reference) + "; only images of the same size can be compared");
    if (reference.channels != other.channels)
        throw Error(other_name, "has " + channel_text(other.channels) + " but the reference " + reference_name +
                                    " has " + channel_text(reference.channels));
}

Prepared prepare(const color::FloatImage& reference, const color::FloatImage& test, const MetricOptions& options,
                 const std::string& reference_name, const std::string& test_name) {
    check_shape(reference, reference_name);
    check_matches(reference, test, reference_name, test_name);
    if (reference.width == 0 || reference.height == 0)
        throw Error(test_name, "is empty (" + size_text(test) + "); nothing to compare");
    check_finite(reference, reference_name, options.input);
    check_finite(test, test_name, options.input);

    Prepared p;
    p.width = reference.width;
    p.height = reference.height;
    const std::size_t count = p.width * p.height;
    p.reference = linear_rgb(reference, options.input);
    p.test = linear_rgb(test, options.input);
    p.covered.assign(count, 1);
    if (options.coverage == Coverage::Alpha && reference.channels == 4) {
        for (std::size_t i = 0; i < count; ++i)
            p.covered[i] = reference.pixels[i * 4 + 3] > 0.0f || test.pixels[i * 4 + 3] > 0.0f;
    }
    p.covered_count = static_cast<std::size_t>(std::count(p.covered.begin(), p.covered.end(), 1));
    if (p.covered_count == 0)
        throw Error(test_name, "nothing to compare: alpha is 0 in every pixel of it and of the reference " +
                                   reference_name);
    return p;
}

// Gaussian weights for offsets -kSsimRadius .. kSsimRadius (normalisation does not matter:
// every window is divided by the sum of the weights it uses).
std::array<double, 2 * kSsimRadius + 1> gaussian_weights() {
    std::array<double, 2 * kSsimRadius + 1> w{};
    for (int k = -kSsimRadius; k <= kSsimRadius; ++k)
        w[std::size_t(k + kSsimRadius)] = std::exp(-double(k * k) / (2.0 * kSsimSigma * kSsimSigma));
    return w;
}

// Separable Gaussian blur; the window is cut to the image and renormalised at the borders (a
// product of cut 1-D windows, so renormalising each pass renormalises the 2-D window exactly).
std::vector<double> blur(const std::vector<double>& in, std::size_t width, std::size_t height) {
    static const std::array<double, 2 * kSsimRadius + 1> w = gaussian_weights();
    const long long R = kSsimRadius, W = static_cast<long long>(width), H = static_cast<long long>(height);
    std::vector<double> across(in.size()), out(in.size());
    std::vector<double> norm_x(width);
    for (long long x = 0; x < W; ++x) {
        double norm = 0.0;
        for (long long k = std::max(-R, -x); k <= std::min(R, W - 1 - x); ++k) norm += w[std::size_t(k + R)];
        norm_x[std::size_t(x)] = norm;
    }
    for (long long y = 0; y < H; ++y) {
        const double* row = &in[std::size_t(y * W)];
        for (long long x = 0; x < W; ++x) {
            const long long lo = std::max(-R, -x), hi = std::min(R, W - 1 - x);
            double sum = 0.0;
            for (long long k = lo; k <= hi; ++k) sum += w[std::size_t(k + R)] * row[x + k];
            across[std::size_t(y * W + x)] = sum / norm_x[std::size_t(x)];
        }
    }
    for (long long y = 0; y < H; ++y) {
        const long long lo = std::max(-R, -y), hi = std::min(R, H - 1 - y);
        double norm = 0.0;
        for (long long k = lo; k <= hi; ++k) norm += w[std::size_t(k + R)];
        for (long long x = 0; x < W; ++x) {
            double sum = 0.0;
            for (long long k = lo; k <= hi; ++k) sum += w[std::size_t(k + R)] * across[std::size_t((y + k) * W + x)];
            out[std::size_t(y * W + x)] = sum / norm;
        }
    }
    return out;
}

std::vector<double> product(const std::vector<double>& a, const std::vector<double>& b) {
    std::vector<double> p(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) p[i] = a[i] * b[i];
    return p;
}

}  // namespace

double display_value(double linear) {
    const double v = std::clamp(linear, 0.0, 1.0);
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

std::vector<double> ssim_map(const std::vector<double>& x, const std::vector<double>& y, std::size_t width,
                             std::size_t height) {
    if (x.size() != width * height || y.size() != width * height)
        throw Error("ssim_map", "planes of " + std::to_string(x.size()) + " and " + std::to_string(y.size()) +
                                    " values for a " + std::to_string(width) + " x " + std::to_string(height) +
                                    " image");
    const double c1 = (kSsimK1 * 1.0) * (kSsimK1 * 1.0), c2 = (kSsimK2 * 1.0) * (kSsimK2 * 1.0);  // L = 1
    const std::vector<double> mx = blur(x, width, height), my = blur(y, width, height);
    const std::vector<double> exx = blur(product(x, x), width, height), eyy = blur(product(y, y), width, height),
                              exy = blur(product(x, y), width, height);
    std::vector<double> map(x.size());
    for (std::size_t i = 0; i < map.size(); ++i) {
        const double sxx = exx[i] - mx[i] * mx[i], syy = eyy[i] - my[i] * my[i], sxy = exy[i] - mx[i] * my[i];
        // Equal local means, variances and covariance make both factors 1 exactly; say so
        // rather than leave it to rounding (fused multiply-adds may differ between the terms).
        if (mx[i] == my[i] && sxx == syy && sxx == sxy) {
            map[i] = 1.0;
            continue;
        }
        map[i] = ((2.0 * mx[i] * my[i] + c1) * (2.0 * sxy + c2)) /
                 ((mx[i] * mx[i] + my[i] * my[i] + c1) * (sxx + syy + c2));
    }
    return map;
}

ImageMetrics compare_images(const color::FloatImage& reference, const color::FloatImage& test,
                            const MetricOptions& options, const std::string& reference_name,
                            const std::string& test_name) {
    const Prepared p = prepare(reference, test, options, reference_name, test_name);
    const std::size_t count = p.width * p.height;

    double relmse_sum = 0.0, mape_sum = 0.0, mse_sum = 0.0, ssim_sum = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
        if (!p.covered[i]) continue;
        for (std::size_t c = 0; c < 3; ++c) {
            const double r = p.reference[i * 3 + c], t = p.test[i * 3 + c], d = t - r;
            relmse_sum += d * d / (r * r + kRelMseEpsilon);
            mape_sum += std::abs(d) / (std::abs(r) + kMapeEpsilon);
        }
    }
    // SSIM is averaged where the whole window fits inside the image (Wang et al.'s reference
    // code, scikit-image): compared pixels kSsimRadius or more from every border.
    const std::size_t R = kSsimRadius;
    std::vector<unsigned char> in_ssim(count, 0);
    std::size_t ssim_count = 0;
    for (std::size_t y = R; y + R < p.height; ++y)
        for (std::size_t x = R; x + R < p.width; ++x) {
            const std::size_t i = y * p.width + x;
            in_ssim[i] = p.covered[i];
            ssim_count += p.covered[i];
        }
    if (ssim_count == 0)
        throw Error(test_name, "no compared pixel lies " + std::to_string(R) +
                                   " or more pixels inside the border, where SSIM's 11 x 11 window fits (the "
                                   "images are " + size_text(test) + "; SSIM needs at least 11 x 11)");

    std::vector<double> dr(count), dt(count);
    for (std::size_t c = 0; c < 3; ++c) {
        for (std::size_t i = 0; i < count; ++i) {
            dr[i] = display_value(p.reference[i * 3 + c]);
            dt[i] = display_value(p.test[i * 3 + c]);
        }
        const std::vector<double> map = ssim_map(dt, dr, p.width, p.height);
        for (std::size_t i = 0; i < count; ++i) {
            if (!p.covered[i]) continue;
            const double d = dt[i] - dr[i];
            mse_sum += d * d;
            if (in_ssim[i]) ssim_sum += map[i];
        }
    }

    const double n = 3.0 * double(p.covered_count);
    ImageMetrics m;
    m.relmse = relmse_sum / n;
    m.mape = mape_sum / n;
    m.mse_display = mse_sum / n;
    m.psnr = m.mse_display > 0.0 ? -10.0 * std::log10(m.mse_display) : std::numeric_limits<double>::infinity();
    m.ssim = ssim_sum / (3.0 * double(ssim_count));
    m.pixels = p.covered_count;
    m.ssim_pixels = ssim_count;
    m.pixels_total = count;
    return m;
}

namespace {

// An image at the second seed, checked against the seed-1 reference, as display values of its
// linear Rec.709 colour (width * height * 3).
std::vector<double> second_seed_display(const color::FloatImage& reference, const std::string& reference_name,
                                        const color::FloatImage& image, const std::string& name,
                                        const MetricOptions& options) {
    check_matches(reference, image, reference_name, name);
    check_finite(image, name, options.input);
    std::vector<double> values = linear_rgb(image, options.input);
    for (double& v : values) v = display_value(v);
    return values;
}

NoiseFloor floor_of(NoiseFloorKind kind, double mse_noise) {
    NoiseFloor f;
    f.kind = kind;
    f.mse_noise = mse_noise;
    f.psnr = mse_noise > 0.0 ? -10.0 * std::log10(mse_noise) : std::numeric_limits<double>::infinity();
    return f;
}

// The mean square of difference(k) over the PSNR's pixels and count (k = pixel * 3 + channel):
// a noise floor's MSE is then a part of the PSNR's MSE.
template <typename Difference>
double covered_mean_square(const Prepared& p, Difference difference) {
    double sum = 0.0;
    for (std::size_t i = 0; i < p.width * p.height; ++i) {
        if (!p.covered[i]) continue;
        for (std::size_t k = i * 3; k < i * 3 + 3; ++k) {
            const double d = difference(k);
            sum += d * d;
        }
    }
    return sum / (3.0 * double(p.covered_count));
}

}  // namespace

const char* noise_floor_kind_name(NoiseFloorKind kind) {
    return kind == NoiseFloorKind::Paired ? "paired" : "reference";
}

NoiseFloor paired_noise_floor(const color::FloatImage& reference, const color::FloatImage& test,
                              const color::FloatImage& reference2, const color::FloatImage& test2,
                              const MetricOptions& options, const std::string& reference_name,
                              const std::string& test_name, const std::string& reference2_name,
                              const std::string& test2_name) {
    const Prepared p = prepare(reference, test, options, reference_name, test_name);
    const std::vector<double> r2 = second_seed_display(reference, reference_name, reference2, reference2_name, options);
    const std::vector<double> t2 = second_seed_display(reference, reference_name, test2, test2_name, options);
    const double mse = covered_mean_square(p, [&](std::size_t k) {
        return (display_value(p.test[k]) - display_value(p.reference[k])) - (t2[k] - r2[k]);
    });
    // e_1 - e_2 = n_1 - n_2 holds the noise of two renders: half of its mean square is one's.
    return floor_of(NoiseFloorKind::Paired, mse / 2.0);
}

NoiseFloor reference_noise_floor(const color::FloatImage& reference, const color::FloatImage& test,
                                 const color::FloatImage& reference2, const MetricOptions& options,
                                 const std::string& reference_name, const std::string& test_name,
                                 const std::string& reference2_name) {
    const Prepared p = prepare(reference, test, options, reference_name, test_name);
    const std::vector<double> r2 = second_seed_display(reference, reference_name, reference2, reference2_name, options);
    const double mse = covered_mean_square(p, [&](std::size_t k) { return r2[k] - display_value(p.reference[k]); });
    // Not halved: a test with independent noise like the reference's carries both renders' noise.
    return floor_of(NoiseFloorKind::Reference, mse);
}

bool noise_limited(const ImageMetrics& metrics, const NoiseFloor& floor) {
    return floor.mse_noise > 0.0 && metrics.mse_display <= 2.0 * floor.mse_noise;
}

RelMseMap relmse_map(const color::FloatImage& reference, const color::FloatImage& test, const MetricOptions& options,
                     const std::string& reference_name, const std::string& test_name) {
    const Prepared p = prepare(reference, test, options, reference_name, test_name);
    RelMseMap map;
    map.width = p.width;
    map.height = p.height;
    map.covered = p.covered;
    map.values.assign(p.width * p.height, 0.0);
    for (std::size_t i = 0; i < map.values.size(); ++i) {
        if (!p.covered[i]) continue;
        double sum = 0.0;
        for (std::size_t c = 0; c < 3; ++c) {
            const double r = p.reference[i * 3 + c], d = p.test[i * 3 + c] - r;
            sum += d * d / (r * r + kRelMseEpsilon);
        }
        map.values[i] = sum / 3.0;
    }
    return map;
}

}  // namespace npf::render
