// The environment map (npf/render/environment_map.h): the lat-long orientation, the
// piecewise-constant distribution, importance sampling against its own pdf (chi-square on an
// independent grid), the pdf integrating to 1 over the sphere, and loading: bad files, NaN,
// negative values.
#include "chi2.h"
#include "synthetic_rgl.h"

#include <npf/core/error.h>
#include <npf/render/environment_map.h>
#include <npf/render/environment_spectra.h>
#include <npf/render/piecewise_constant_2d.h>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using npf::Vec2;
using npf::Vec3;
using npf::render::EnvironmentMap;
using npf::render::EnvironmentSample;

constexpr double kPi = 3.14159265358979323846;

void expect_direction(const Vec3& d, float x, float y, float z, const char* what) {
    EXPECT_NEAR(d.x, x, 1e-6) << what;
    EXPECT_NEAR(d.y, y, 1e-6) << what;
    EXPECT_NEAR(d.z, z, 1e-6) << what;
}

// A deterministic, strongly non-uniform map: a dim gradient, a bright small "sun", a black
// band and a coloured patch, w x h texels.
EnvironmentMap test_map(std::size_t w = 32, std::size_t h = 16) {
    std::vector<float> rgb(w * h * 3);
    for (std::size_t r = 0; r < h; ++r) {
        for (std::size_t c = 0; c < w; ++c) {
            float* p = &rgb[(r * w + c) * 3];
            const float base = 0.05f + 0.5f * float(c) / float(w) + 0.2f * float(r) / float(h);
            p[0] = p[1] = p[2] = base;
            if (r == h / 2 + 1) p[0] = p[1] = p[2] = 0.f;  // a black row below the horizon
            if (r == 3 && c == 5) p[0] = p[1] = p[2] = 200.f;  // the sun
            if (r == 10 && c >= 20 && c < 24) p[0] = 3.f, p[1] = 0.5f, p[2] = 0.1f;
        }
    }
    // The top row is black too (the pole).
    for (std::size_t c = 0; c < w; ++c) rgb[c * 3] = rgb[c * 3 + 1] = rgb[c * 3 + 2] = 0.f;
    return EnvironmentMap(w, h, std::move(rgb), "test map");
}

void write_exr(const std::string& path, int w, int h, int channels, const std::vector<float>& px) {
    OIIO::ImageSpec spec(w, h, channels, OIIO::TypeFloat);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeFloat, px.data()) && out->close())
        << OIIO::geterror();
}

TEST(RenderEnvironment, LatLongOrientation) {
    // The image centre is straight ahead of the camera (-z), u = 3/4 to its right (+x), the top
    // row is up (+y), the edges are behind the camera (+z).
    expect_direction(npf::render::latlong_direction({0.5f, 0.5f}), 0, 0, -1, "centre");
    expect_direction(npf::render::latlong_direction({0.75f, 0.5f}), 1, 0, 0, "u = 3/4");
    expect_direction(npf::render::latlong_direction({0.25f, 0.5f}), -1, 0, 0, "u = 1/4");
    expect_direction(npf::render::latlong_direction({0.0f, 0.5f}), 0, 0, 1, "u = 0");
    expect_direction(npf::render::latlong_direction({0.3f, 0.0f}), 0, 1, 0, "top row");
    expect_direction(npf::render::latlong_direction({0.3f, 1.0f}), 0, -1, 0, "bottom row");
    // Round trip.
    npf::testing::Pcg32 rng(11);
    for (int i = 0; i < 10000; ++i) {
        const Vec2 uv{rng.next_float(), 0.001f + 0.998f * rng.next_float()};
        const Vec2 back = npf::render::latlong_coordinates(npf::render::latlong_direction(uv));
        EXPECT_NEAR(back.x, uv.x, 2e-6);
        EXPECT_NEAR(back.y, uv.y, 2e-6);
    }
}

TEST(RenderEnvironment, TexelLookupFollowsTheOrientation) {
    // A 4 x 2 map: texel (column c, row r) has value 10 r + c.
    std::vector<float> rgb;
    for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 3; ++k) rgb.push_back(float(10 * r + c));
    const EnvironmentMap map(4, 2, rgb, "4x2");
    auto value = [&](const Vec3& d) { return map.radiance(map.texel(d))[0]; };
    EXPECT_EQ(value({0.f, 0.6f, -0.8f}), 2.f);   // ahead and up: u = 1/2 (column 2), upper row
    EXPECT_EQ(value({0.6f, -0.1f, 0.f}), 13.f);  // right (+x), below the horizon: u = 3/4, lower row
    EXPECT_EQ(value({-0.8f, 0.6f, 0.f}), 1.f);   // left (-x): u = 1/4
    EXPECT_EQ(value({0.1f, 0.5f, 0.8f}), 3.f);   // behind (+z), slightly right: u near 1
    EXPECT_EQ(value({-0.1f, 0.5f, 0.8f}), 0.f);  // behind, slightly left: u near 0
}

TEST(RenderEnvironment, PiecewiseConstantDistribution) {
    const std::vector<double> w = {0, 1, 2, 0, 0, 0, 3, 6};  // 4 x 2, row-major
    const npf::render::PiecewiseConstant2D d(w, 4, 2);
    // Densities: weight * cells / total = w * 8 / 12.
    for (std::size_t i = 0; i < 8; ++i) EXPECT_NEAR(d.density(i), w[i] * 8.0 / 12.0, 1e-12);
    npf::testing::Pcg32 rng(5);
    std::vector<int> counts(8, 0);
    const int n = 120000;
    for (int i = 0; i < n; ++i) {
        std::size_t cell = 0;
        const Vec2 uv = d.sample({rng.next_float(), rng.next_float()}, cell);
        ASSERT_EQ(d.cell_at(uv), cell);
        ++counts[cell];
    }
    for (std::size_t i = 0; i < 8; ++i) EXPECT_NEAR(double(counts[i]) / n, w[i] / 12.0, 0.005) << i;
    EXPECT_EQ(counts[0] + counts[3] + counts[4] + counts[5], 0);
    // All zero: uniform.
    const npf::render::PiecewiseConstant2D z(std::vector<double>(6, 0.0), 3, 2);
    for (std::size_t i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(z.density(i), 1.0);
    EXPECT_THROW(npf::render::PiecewiseConstant2D({1.0, -1.0}, 2, 1), npf::Error);
    EXPECT_THROW(npf::render::PiecewiseConstant2D({1.0, NAN}, 2, 1), npf::Error);
    EXPECT_THROW(npf::render::PiecewiseConstant2D({1.0}, 2, 1), npf::Error);
}

// Integral of pdf over the sphere on a grid uniform in (cos, azimuth) about the z axis (not the
// map's y axis, so the texel boundaries cut the cells obliquely): each cell has the same solid
// angle.
double pdf_integral(const EnvironmentMap& map, int rows, int cols) {
    double sum = 0.0;
    for (int r = 0; r < rows; ++r) {
        const double z = -1.0 + 2.0 * (r + 0.5) / rows, s = std::sqrt(1.0 - z * z);
        for (int c = 0; c < cols; ++c) {
            const double phi = 2.0 * kPi * (c + 0.5) / cols;
            sum += map.pdf(Vec3{float(s * std::cos(phi)), float(s * std::sin(phi)), float(z)});
        }
    }
    return sum * 4.0 * kPi / (double(rows) * cols);
}

TEST(RenderEnvironment, PdfIntegratesToOneOverTheSphere) {
    EXPECT_NEAR(pdf_integral(test_map(), 1200, 2400), 1.0, 2e-3);
    EXPECT_NEAR(pdf_integral(test_map(7, 5), 600, 1200), 1.0, 2e-3);
    // One texel: uniform in (u, v), so pdf ~ 1 / sin(theta), integrable but singular at the poles.
    EXPECT_NEAR(pdf_integral(EnvironmentMap::constant(1.f, 2.f, 3.f), 600, 1200), 1.0, 2e-3);
    // A constant map is sampled uniformly: pdf = 1 / (4 pi) everywhere (up to the piecewise-
    // constant sin(theta) of the weights on a single row).
    const EnvironmentMap flat(64, 32, std::vector<float>(64 * 32 * 3, 1.f), "flat");
    EXPECT_NEAR(flat.pdf(Vec3{0.f, 0.f, -1.f}) * 4.0 * kPi, 1.0, 2e-3);
    EXPECT_NEAR(flat.pdf(Vec3{0.6f, 0.8f, 0.f}) * 4.0 * kPi, 1.0, 1e-2);
}

TEST(RenderEnvironment, SamplesFollowThePdf) {
    const EnvironmentMap map = test_map();
    // Chi-square on a 20 x 40 grid uniform in (cos theta_z, azimuth) about z; expected counts by
    // integrating pdf() over each cell on a 12 x 12 sub-grid.
    const int rows = 20, cols = 40, sub = 12;
    const std::uint64_t n = 1000000;
    std::vector<double> expected(rows * cols, 0.0), observed(rows * cols, 0.0);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            double sum = 0.0;
            for (int i = 0; i < sub; ++i)
                for (int j = 0; j < sub; ++j) {
                    const double z = -1.0 + 2.0 * (r + (i + 0.5) / sub) / rows, s = std::sqrt(1.0 - z * z);
                    const double phi = 2.0 * kPi * (c + (j + 0.5) / sub) / cols;
                    sum += map.pdf(Vec3{float(s * std::cos(phi)), float(s * std::sin(phi)), float(z)});
                }
            expected[r * cols + c] = sum / (sub * sub) * 4.0 * kPi / (rows * cols) * double(n);
        }
    npf::testing::Pcg32 rng(2024);
    std::uint64_t failed = 0, pdf_mismatch = 0;
    for (std::uint64_t i = 0; i < n; ++i) {
        EnvironmentSample s;
        if (!map.sample({rng.next_float(), rng.next_float()}, s)) {
            ++failed;
            continue;
        }
        const Vec3& d = s.direction;
        ASSERT_NEAR(std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z), 1.0, 1e-5);
        // The sample's pdf is the pdf of its direction (up to texel-boundary rounding).
        if (std::fabs(map.pdf(d) - s.pdf) > 1e-3f * s.pdf) ++pdf_mismatch;
        // Black texels are never drawn.
        const float* L = map.radiance(s.texel);
        ASSERT_GT(L[0] + L[1] + L[2], 0.f);
        const int r = std::min(rows - 1, int((double(d.z) + 1.0) / 2.0 * rows));
        double phi = std::atan2(double(d.y), double(d.x));
        if (phi < 0) phi += 2.0 * kPi;
        const int c = std::min(cols - 1, int(phi / (2.0 * kPi) * cols));
        observed[r * cols + c] += 1.0;
    }
    EXPECT_EQ(failed, 0u);
    EXPECT_LT(pdf_mismatch, n / 10000);
    // Pool cells expected below 5.
    double chi2 = 0.0, pool_e = 0.0, pool_o = 0.0;
    int dof = -1;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        if (expected[i] < 5.0) {
            pool_e += expected[i], pool_o += observed[i];
            continue;
        }
        chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
        ++dof;
    }
    if (pool_e > 0.0) {
        chi2 += (pool_o - pool_e) * (pool_o - pool_e) / std::max(pool_e, 1e-9);
        ++dof;
    }
    const double p = npf::testing::chi2_sf(chi2, dof);
    EXPECT_GT(p, 1e-3) << "chi2 " << chi2 << " dof " << dof;
}

TEST(RenderEnvironment, SamplingPrefersBrightTexels) {
    const EnvironmentMap map = test_map();
    npf::testing::Pcg32 rng(1);
    int sun = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        EnvironmentSample s;
        ASSERT_TRUE(map.sample({rng.next_float(), rng.next_float()}, s));
        sun += s.texel == 3 * 32 + 5;
    }
    // The sun holds most of the luminance x sin(theta).
    EXPECT_GT(sun, n / 2);
}

TEST(RenderEnvironment, NegativeValuesAreClampedAndCounted) {
    std::vector<float> rgb = {1.f, -1e-6f, 2.f, -3.f, 0.5f, 0.5f};
    const EnvironmentMap map(2, 1, rgb, "negatives");
    EXPECT_EQ(map.clamped_values(), 2u);
    EXPECT_EQ(map.radiance(0)[1], 0.f);
    EXPECT_EQ(map.radiance(1)[0], 0.f);
    EXPECT_EQ(map.radiance(1)[1], 0.5f);
}

TEST(RenderEnvironment, NonFiniteValuesAreRejected) {
    try {
        EnvironmentMap(2, 2, {1, 1, 1, 1, 1, 1, 1, NAN, 1, 1, 1, 1}, "nan map");
        FAIL() << "no error";
    } catch (const npf::Error& e) {
        EXPECT_NE(std::string(e.what()).find("nan map"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("(x 0, y 1) channel G is NaN"), std::string::npos) << e.what();
    }
    EXPECT_THROW(EnvironmentMap(1, 1, {1, INFINITY, 1}, "inf"), npf::Error);
    EXPECT_THROW(EnvironmentMap(0, 1, {}, "empty"), npf::Error);
    EXPECT_THROW(EnvironmentMap(2, 1, {1, 1, 1}, "short"), npf::Error);
}

TEST(RenderEnvironment, BlackMapIsSampledUniformly) {
    const EnvironmentMap black(8, 4, std::vector<float>(8 * 4 * 3, 0.f), "black");
    EXPECT_NEAR(pdf_integral(black, 400, 800), 1.0, 2e-3);
    EnvironmentSample s;
    EXPECT_TRUE(black.sample({0.3f, 0.6f}, s));
}

TEST(RenderEnvironment, LoadsFilesAndNamesThemInErrors) {
    const std::string dir = npf::testing::temporary_folder("render_env");
    // RGB with an alpha channel: R, G, B are taken by name.
    const std::string rgba = (fs::path(dir) / "rgba.exr").string();
    std::vector<float> px;
    for (int i = 0; i < 8; ++i) px.insert(px.end(), {float(i), 2.f * float(i), 0.5f, 1.f});
    write_exr(rgba, 4, 2, 4, px);
    const EnvironmentMap m = EnvironmentMap::load(rgba);
    EXPECT_EQ(m.width(), 4u);
    EXPECT_EQ(m.height(), 2u);
    EXPECT_EQ(m.source(), rgba);
    EXPECT_EQ(m.radiance(5)[0], 5.f);
    EXPECT_EQ(m.radiance(5)[1], 10.f);
    EXPECT_EQ(m.radiance(5)[2], 0.5f);
    // One channel: grey.
    const std::string grey = (fs::path(dir) / "grey.exr").string();
    write_exr(grey, 2, 1, 1, {0.25f, 4.f});
    const EnvironmentMap g = EnvironmentMap::load(grey);
    EXPECT_EQ(g.radiance(1)[0], 4.f);
    EXPECT_EQ(g.radiance(1)[2], 4.f);

    auto expect_error = [](const std::string& path, const std::string& part) {
        try {
            EnvironmentMap::load(path);
            ADD_FAILURE() << "no error for " << path;
        } catch (const npf::Error& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    expect_error((fs::path(dir) / "missing.exr").string(), "not found");
    expect_error(dir, "directory");
    const std::string text = (fs::path(dir) / "text.exr").string();
    std::ofstream(text) << "not an image\n";
    expect_error(text, "not an environment map npf reads");
    // What never ends or blocks, and a name OpenImageIO's readers would take parameters from (its
    // null reader made a 20000 x 20000 image from the name alone and aborted).
    expect_error("/dev/zero", "is not a regular file");
    const std::string fifo = (fs::path(dir) / "fifo.exr").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expect_error(fifo, "is not a regular file");
    const std::string named = (fs::path(dir) / "x.null?RES=20000x20000").string();
    std::ofstream(named) << "";
    expect_error(named, "not an environment map npf reads");
    const std::string two = (fs::path(dir) / "two.exr").string();
    write_exr(two, 1, 1, 2, {1.f, 1.f});
    expect_error(two, "2 channels");
    const std::string nan = (fs::path(dir) / "nan.exr").string();
    write_exr(nan, 2, 1, 3, {1.f, 1.f, 1.f, 1.f, INFINITY, 1.f});
    expect_error(nan, "infinite");
}

TEST(RenderEnvironment, ShippedStudioMapLoads) {
    // data/envmaps/studio.exr: 1024 x 512, DWA-compressed, with tiny negative values (clamped).
    const EnvironmentMap m = EnvironmentMap::load(std::string(NPF_SOURCE_DIR) + "/data/envmaps/studio.exr");
    EXPECT_EQ(m.width(), 1024u);
    EXPECT_EQ(m.height(), 512u);
    EXPECT_GT(m.clamped_values(), 0u);
    EXPECT_LT(m.clamped_values(), 1000u);
}

TEST(RenderEnvironment, SpectraOfGreysAreFlatAndScaleWithTheColour) {
    const EnvironmentMap map(3, 1, {0.5f, 0.5f, 0.5f, 0.f, 0.f, 0.f, 1.6f, 0.8f, 0.4f}, "spectra");
    const npf::render::EnvironmentSpectra spectra(map, 1);
    const float wl[3] = {400.f, 550.f, 700.f};
    float out[3];
    spectra.eval(0, wl, 3, out);
    for (float v : out) EXPECT_FLOAT_EQ(v, 0.5f);
    spectra.eval(1, wl, 3, out);
    for (float v : out) EXPECT_EQ(v, 0.f);
    spectra.eval(2, wl, 3, out);
    EXPECT_GT(out[2], out[1]);  // orange: more red than green, more green than blue
    EXPECT_GT(out[1], out[0]);
}

}  // namespace
