#include <npf/render/environment_map.h>

#include <npf/color/image_file.h>

#include <npf/core/error.h>
#include <npf/core/openexr_header.h>
#include <npf/core/rec709_luminance.h>
#include <npf/core/text.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

namespace npf::render {

namespace {

// sin(theta) of a unit direction, theta from +y: exact near the poles, unlike sin(acos(y)).
double sin_theta(const Vec3& d) { return std::sqrt(double(d.x) * d.x + double(d.z) * d.z); }

}  // namespace

Vec3 latlong_direction(const Vec2& uv) {
    const double theta = kPiD * double(uv.y), phi = kTwoPiD * (double(uv.x) - 0.5);
    const double st = std::sin(theta);
    return {float(st * std::sin(phi)), float(std::cos(theta)), float(-st * std::cos(phi))};
}

Vec2 latlong_coordinates(const Vec3& d) {
    const double y = std::clamp(double(d.y), -1.0, 1.0);
    // theta = acos(y), written with atan2 so that it keeps its precision near the poles.
    const double theta = std::atan2(sin_theta(d), y);
    const double phi = std::atan2(double(d.x), -double(d.z));  // (-pi, pi]
    return {float(std::clamp(phi / kTwoPiD + 0.5, 0.0, 1.0)), float(std::clamp(theta / kPiD, 0.0, 1.0))};
}

EnvironmentMap::EnvironmentMap(std::size_t width, std::size_t height, std::vector<float> rgb, std::string source)
    : m_width(width), m_height(height), m_rgb(std::move(rgb)), m_source(std::move(source)) {
    if (width == 0 || height == 0) throw Error(m_source, "environment map has no texels");
    if (width > (1u << 16) || height > (1u << 16))
        throw Error(m_source, "environment map larger than 65536 texels on a side");
    if (m_rgb.size() != width * height * 3) throw Error(m_source, "environment map size and pixel count disagree");
    static const char* const kChannel[3] = {"R", "G", "B"};
    for (std::size_t i = 0; i < m_rgb.size(); ++i) {
        float& v = m_rgb[i];
        if (!std::isfinite(v)) {
            const std::size_t texel = i / 3;
            throw Error(m_source, "environment map texel (x " + std::to_string(texel % width) + ", y " +
                                      std::to_string(texel / width) + ") channel " + kChannel[i % 3] + " is " +
                                      (std::isnan(v) ? "NaN" : "infinite") +
                                      "; environment maps must hold finite radiance");
        }
        if (v < 0.f) {
            v = 0.f;
            ++m_clamped;
        }
    }
    build_distribution();
}

EnvironmentMap EnvironmentMap::constant(float r, float g, float b) {
    return EnvironmentMap(1, 1, {r, g, b}, "constant environment");
}

EnvironmentMap EnvironmentMap::load(const std::string& path) {
    std::unique_ptr<OIIO::ImageInput> in = color::open_image_file(path, "an environment map");
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1) throw Error(path, "environment map is not a 2D image");
    const int nc = spec.nchannels;
    if (nc != 1 && nc < 3)
        throw Error(path, "environment map has " + std::to_string(nc) + " channels; it needs RGB (or one, grey)");
    int channel[3] = {0, 1, 2};
    if (nc == 1) {
        channel[1] = channel[2] = 0;
    } else {
        const int r = spec.channelindex("R"), g = spec.channelindex("G"), b = spec.channelindex("B");
        if (r >= 0 && g >= 0 && b >= 0) channel[0] = r, channel[1] = g, channel[2] = b;
    }
    const std::size_t w = std::size_t(spec.width), h = std::size_t(spec.height), all = std::size_t(nc);
    if (w > (1u << 16) || h > (1u << 16)) throw Error(path, "environment map larger than 65536 texels on a side");
    std::vector<float> file(w * h * all);
    if (!in->read_image(0, 0, 0, nc, OIIO::TypeFloat, file.data()))
        throw Error(path, "cannot read the environment map's pixels: " + first_line(in->geterror()));
    in->close();
    std::vector<float> rgb(w * h * 3);
    for (std::size_t p = 0; p < w * h; ++p)
        for (int c = 0; c < 3; ++c) rgb[p * 3 + std::size_t(c)] = file[p * all + std::size_t(channel[c])];
    return EnvironmentMap(w, h, std::move(rgb), path);
}

void EnvironmentMap::build_distribution() {
    std::vector<double> weights(m_width * m_height);
    double total = 0.0;
    for (std::size_t r = 0; r < m_height; ++r) {
        const double st = std::sin(kPiD * (double(r) + 0.5) / double(m_height));
        for (std::size_t c = 0; c < m_width; ++c) {
            const float* p = &m_rgb[(r * m_width + c) * 3];
            const double lum = rec709_luminance(p[0], p[1], p[2]);
            total += (weights[r * m_width + c] = lum * st);
        }
    }
    if (!(total > 0.0) || !std::isfinite(total)) {
        // Black (or absurdly bright) everywhere: uniform in solid angle (weights sin theta).
        for (std::size_t r = 0; r < m_height; ++r) {
            const double st = std::sin(kPiD * (double(r) + 0.5) / double(m_height));
            std::fill(weights.begin() + std::ptrdiff_t(r * m_width), weights.begin() + std::ptrdiff_t((r + 1) * m_width), st);
        }
    }
    m_distribution = PiecewiseConstant2D(weights, m_width, m_height);
}

std::uint32_t EnvironmentMap::texel(const Vec3& direction) const {
    return std::uint32_t(m_distribution.cell_at(latlong_coordinates(direction)));
}

bool EnvironmentMap::sample(const Vec2& rnd, EnvironmentSample& s) const {
    std::size_t cell = 0;
    const Vec2 uv = m_distribution.sample(rnd, cell);
    const double theta = kPiD * double(uv.y), phi = kTwoPiD * (double(uv.x) - 0.5);
    const double st = std::sin(theta);
    s.texel = std::uint32_t(cell);
    s.direction = {float(st * std::sin(phi)), float(std::cos(theta)), float(-st * std::cos(phi))};
    if (!(st > 0.0)) {
        s.pdf = 0.f;
        return false;
    }
    s.pdf = float(m_distribution.density(cell) / (kTwoPiD * kPiD * st));
    return std::isfinite(s.pdf) && s.pdf > 0.f;
}

float EnvironmentMap::pdf(const Vec3& direction, std::uint32_t texel_index) const {
    const double st = sin_theta(direction);
    if (!(st > 0.0)) return 0.f;
    const float p = float(m_distribution.density(texel_index) / (kTwoPiD * kPiD * st));
    return std::isfinite(p) ? p : 0.f;
}

float EnvironmentMap::pdf(const Vec3& direction) const { return pdf(direction, texel(direction)); }

}  // namespace npf::render
