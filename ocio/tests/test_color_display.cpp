// Tests of the display side of npf_color: the shipped OpenColorIO config, DisplayTransform
// (config search, names, errors, buffers, threads) and the display-encoded PNG writer.
//
// Reference numbers: the sRGB encoding of 0.18 is 1.055 * 0.18^(1/2.4) - 0.055 = 0.461356
// (IEC 61966-2-1); the XYZ <-> linear sRGB matrices are spectrum.h's.
#include <npf/color/display.h>
#include <npf/color/display_image.h>
#include <npf/color/spectrum.h>
#include <npf/core/error.h>

#include <synthetic_rgl.h>

#include <OpenImageIO/imageio.h>
#include "error_of.h"
#include "test_png.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::color;

const std::string kShippedConfig = std::string(NPF_SOURCE_DIR) + "/configs/ocio/config.ocio";

// Sets (or unsets) an environment variable for one scope; the test binary may run every test in
// one process, so the old value comes back.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::optional<std::string>& value) : m_name(name) {
        if (const char* old = std::getenv(name)) m_old = old;
        if (value) ::setenv(name, value->c_str(), 1);
        else ::unsetenv(name);
    }
    ~ScopedEnv() {
        if (m_old) ::setenv(m_name, m_old->c_str(), 1);
        else ::unsetenv(m_name);
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    const char* m_name;
    std::optional<std::string> m_old;
};

using npf::testing::error_of;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

DisplayTransform shipped(SceneSpace input = SceneSpace::LinearRec709, const std::string& display = "",
                         const std::string& view = "") {
    DisplayOptions o;
    o.config_path = kShippedConfig;
    o.input = input;
    o.display = display;
    o.view = view;
    return DisplayTransform(o);
}

std::string write_text_file(const std::string& dir, const std::string& name, const std::string& text) {
    const std::string path = (fs::path(dir) / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

bool has_temporary_files(const std::string& dir) {
    for (const auto& e : fs::directory_iterator(dir))
        if (has(e.path().filename().string(), ".tmp-")) return true;
    return false;
}

// ---------------------------------------------------------------------------------------------
// The shipped config and how a config is found

TEST(ColorDisplay, ShippedConfigIsFoundWithoutOcio) {
    ScopedEnv no_ocio("OCIO", std::nullopt);
    const std::string path = resolve_ocio_config_path();
    EXPECT_TRUE(fs::is_regular_file(path)) << path;
    bool listed = false;
    for (const std::string& c : shipped_ocio_config_candidates())
        listed = listed || fs::path(c).lexically_normal() == fs::path(kShippedConfig).lexically_normal();
    EXPECT_TRUE(listed) << "the source tree's config is one of the candidates";

    const DisplayTransform t;  // all defaults
    EXPECT_EQ(t.display(), "sRGB - Display");
    EXPECT_EQ(t.view(), "Standard");
    EXPECT_EQ(t.input_colorspace(), "Linear Rec.709 (sRGB)");
}

TEST(ColorDisplay, ExplicitPathBeatsOcioWhichBeatsShipped) {
    const std::string dir = npf::testing::temporary_folder("display_env");
    const std::string missing = (fs::path(dir) / "missing.ocio").string();
    ScopedEnv ocio("OCIO", missing);
    EXPECT_EQ(resolve_ocio_config_path(), missing);
    EXPECT_EQ(resolve_ocio_config_path(kShippedConfig), kShippedConfig);
    const std::string message = error_of([] { DisplayTransform t; });
    EXPECT_TRUE(has(message, missing)) << message;
    EXPECT_TRUE(has(message, "$OCIO")) << message;
    {
        ScopedEnv empty_ocio("OCIO", std::string());  // empty counts as unset
        EXPECT_NE(resolve_ocio_config_path(), "");
        EXPECT_NE(resolve_ocio_config_path(), missing);
    }
}

TEST(ColorDisplay, ListsDisplaysAndViewsDefaultsFirst) {
    const std::vector<DisplayViews> list = list_display_views(kShippedConfig);
    ASSERT_EQ(list.size(), 2u);
    EXPECT_EQ(list[0].display, "sRGB - Display");
    EXPECT_EQ(list[0].views, (std::vector<std::string>{"Standard", "Raw"}));
    EXPECT_EQ(list[1].display, "XYZ");
    EXPECT_EQ(list[1].views, (std::vector<std::string>{"Standard", "Raw"}));
}

// ---------------------------------------------------------------------------------------------
// Values

TEST(ColorDisplay, FlatSpectrumThroughXyzIsTheDisplayWhite) {
    const Xyz white = spectrum_to_xyz(SampledSpectrum::constant(1.0));
    const auto encoded = shipped(SceneSpace::CieXyzD65).apply(white);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(encoded[c], 1.0, 1e-3) << "channel " << c;
}

TEST(ColorDisplay, EighteenPercentGreyEncodesTo04614) {
    const double expected = 1.055 * std::pow(0.18, 1.0 / 2.4) - 0.055;  // 0.461356
    EXPECT_NEAR(expected, 0.4614, 5e-5);
    const auto from_linear = shipped().apply({0.18, 0.18, 0.18});
    const auto from_xyz = shipped(SceneSpace::CieXyzD65).apply(linear_srgb_to_xyz({0.18, 0.18, 0.18}));
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(from_linear[c], expected, 1e-4);
        EXPECT_NEAR(from_xyz[c], expected, 1e-4);
    }
}

TEST(ColorDisplay, EncodingFollowsTheSrgbCurve) {
    const DisplayTransform t = shipped();
    for (double v : {0.0, 0.001, 0.0031308, 0.01, 0.05, 0.2140, 0.5, 0.9, 1.0}) {
        const auto e = t.apply({v, v, v});
        EXPECT_NEAR(e[1], linear_to_srgb(v), 1e-4) << v;
    }
}

// The config's scene XYZ space and its view transform use spectrum.h's matrices: XYZ computed
// by npf displays like the linear colour it came from, and the XYZ display returns npf's XYZ.
TEST(ColorDisplay, ConfigMatricesAgreeWithSpectrumH) {
    const DisplayTransform from_linear = shipped(), from_xyz = shipped(SceneSpace::CieXyzD65);
    const DisplayTransform to_xyz = shipped(SceneSpace::LinearRec709, "XYZ", "Standard");
    const std::vector<Rgb> colours = {{0.8, 0.1, 0.05}, {0.1, 0.7, 0.2}, {0.05, 0.1, 0.9},
                                      {0.5, 0.5, 0.5}, {0.9, 0.8, 0.2}, {0.01, 0.02, 0.03}};
    for (const Rgb& rgb : colours) {
        const Xyz xyz = linear_srgb_to_xyz(rgb);
        const auto a = from_linear.apply(rgb), b = from_xyz.apply(xyz), x = to_xyz.apply(rgb);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(a[c], b[c], 2e-6) << rgb[0] << " " << rgb[1] << " " << rgb[2];
            EXPECT_NEAR(x[c], xyz[c], 2e-6) << rgb[0] << " " << rgb[1] << " " << rgb[2];
        }
    }
    // The matrix written into the config, element by element (XYZ unit vectors in, linear out).
    const DisplayTransform xyz_to_linear = [] {
        DisplayOptions o;
        o.config_path = kShippedConfig;
        o.input = SceneSpace::CieXyzD65;
        o.display = "XYZ";
        o.view = "Standard";
        return DisplayTransform(o);
    }();
    for (int c = 0; c < 3; ++c) {
        Xyz e{0.0, 0.0, 0.0};
        e[c] = 1.0;
        const auto round_trip = xyz_to_linear.apply(e);  // XYZ -> scene 709 -> display XYZ
        for (int r = 0; r < 3; ++r) EXPECT_NEAR(round_trip[r], e[r], 1e-6);
    }
}

TEST(ColorDisplay, RawViewLeavesValuesAlone) {
    const auto v = shipped(SceneSpace::LinearRec709, "sRGB - Display", "Raw").apply({0.18, 2.5, -0.25});
    EXPECT_FLOAT_EQ(static_cast<float>(v[0]), 0.18f);
    EXPECT_FLOAT_EQ(static_cast<float>(v[1]), 2.5f);
    EXPECT_FLOAT_EQ(static_cast<float>(v[2]), -0.25f);
}

TEST(ColorDisplay, BuffersOfThreeAndFourChannels) {
    const DisplayTransform t = shipped();
    std::vector<float> rgb = {0.18f, 0.18f, 0.18f, 1.0f, 0.5f, 0.0f, 0.0f, 0.0f, 0.0f, 0.02f, 0.4f, 0.9f};
    std::vector<float> rgba = {0.18f, 0.18f, 0.18f, 0.5f, 1.0f, 0.5f, 0.0f, 1.0f,
                               0.0f,  0.0f,  0.0f,  0.0f, 0.02f, 0.4f, 0.9f, 0.25f};
    const std::vector<float> alpha_before = {rgba[3], rgba[7], rgba[11], rgba[15]};
    t.apply(rgb.data(), 2, 2, 3);
    t.apply(rgba.data(), 4, 1, 4);
    for (int p = 0; p < 4; ++p) {
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(rgba[p * 4 + c], rgb[p * 3 + c]) << p << " " << c;
        EXPECT_EQ(rgba[p * 4 + 3], alpha_before[p]) << "alpha passes through";
    }
    const auto one = t.apply({0.02, 0.4, 0.9});
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[9 + c], one[c], 1e-6);

    t.apply(nullptr, 0, 0, 3);  // empty: nothing to do
    std::vector<float> two(8, 0.5f);
    EXPECT_TRUE(has(error_of([&] { t.apply(two.data(), 4, 1, 2); }), "3 or 4 channels"));
    EXPECT_TRUE(has(error_of([&] { t.apply(two.data(), 1, 1, 5); }), "3 or 4 channels"));
}

TEST(ColorDisplay, ApplyFromSeveralThreadsAtOnce) {
    const DisplayTransform t = shipped(SceneSpace::CieXyzD65);
    std::vector<float> image(64 * 64 * 3);
    for (std::size_t i = 0; i < image.size(); ++i) image[i] = static_cast<float>((i * 37 % 101) / 100.0);
    std::vector<float> serial = image;
    t.apply(serial.data(), 64, 64, 3);
    std::vector<std::vector<float>> copies(4, image);
    std::vector<std::thread> threads;
    for (auto& copy : copies)
        threads.emplace_back([&t, &copy] {
            for (int repeat = 0; repeat < 8; ++repeat) {
                std::vector<float> work = copy;
                t.apply(work.data(), 64, 64, 3);
                if (repeat == 7) copy = work;
            }
        });
    for (std::thread& th : threads) th.join();
    for (const auto& copy : copies) EXPECT_EQ(copy, serial);
}

// ---------------------------------------------------------------------------------------------
// Errors name the config file and the problem

TEST(ColorDisplay, BadConfigPathsNameTheFile) {
    const std::string dir = npf::testing::temporary_folder("display_bad_config");
    const std::string missing = (fs::path(dir) / "nope.ocio").string();
    auto load = [](const std::string& path) {
        DisplayOptions o;
        o.config_path = path;
        DisplayTransform t(o);
    };
    std::string m = error_of([&] { load(missing); });
    EXPECT_TRUE(has(m, missing) && has(m, "not found")) << m;
    m = error_of([&] { load(dir); });
    EXPECT_TRUE(has(m, dir) && has(m, "folder")) << m;
    const std::string garbage = write_text_file(dir, "garbage.ocio", "this: [is not\n  an ocio config\n");
    m = error_of([&] { load(garbage); });
    EXPECT_TRUE(has(m, garbage) && has(m, "invalid OpenColorIO config")) << m;
    const std::string no_version = write_text_file(dir, "empty.ocio", "");
    m = error_of([&] { load(no_version); });
    EXPECT_TRUE(has(m, no_version)) << m;
    m = error_of([&] { list_display_views(missing); });
    EXPECT_TRUE(has(m, missing)) << m;
}

TEST(ColorDisplay, UnknownDisplayViewOrColourSpaceNameTheConfig) {
    std::string m = error_of([] { shipped(SceneSpace::LinearRec709, "Cinema"); });
    EXPECT_TRUE(has(m, kShippedConfig) && has(m, "unknown display 'Cinema'") && has(m, "sRGB - Display")) << m;
    m = error_of([] { shipped(SceneSpace::LinearRec709, "sRGB - Display", "Filmic"); });
    EXPECT_TRUE(has(m, kShippedConfig) && has(m, "unknown view 'Filmic'") && has(m, "Standard")) << m;
    m = error_of([] {
        DisplayOptions o;
        o.config_path = kShippedConfig;
        o.input_colorspace = "ACEScg";
        DisplayTransform t(o);
    });
    EXPECT_TRUE(has(m, kShippedConfig) && has(m, "unknown colour space 'ACEScg'")) << m;
}

// A config with other names: the known names and aliases are tried first, then the roles.
TEST(ColorDisplay, InputSpacesResolveByNameThenRole) {
    const std::string dir = npf::testing::temporary_folder("display_roles");
    const std::string config = write_text_file(dir, "roles.ocio", R"(ocio_profile_version: 2.1
strictparsing: true
roles: {default: scene, scene_linear: scene, data: raw, cie_xyz_d65_interchange: display_xyz}
file_rules:
  - !<Rule> {name: Default, colorspace: default}
displays:
  monitor:
    - !<View> {name: plain, view_transform: to_xyz, display_colorspace: srgb_monitor}
default_view_transform: to_xyz
view_transforms:
  - !<ViewTransform>
    name: to_xyz
    from_scene_reference: !<MatrixTransform> {matrix: [0.412390799266, 0.357584339384, 0.180480788402, 0, 0.212639005872, 0.715168678768, 0.0721923153607, 0, 0.0193308187156, 0.119194779795, 0.95053215225, 0, 0, 0, 0, 1]}
display_colorspaces:
  - !<ColorSpace> {name: display_xyz}
  - !<ColorSpace>
    name: srgb_monitor
    from_display_reference: !<BuiltinTransform> {style: DISPLAY - CIE-XYZ-D65_to_sRGB}
colorspaces:
  - !<ColorSpace> {name: scene}
  - !<ColorSpace> {name: raw, isdata: true}
)");
    DisplayOptions o;
    o.config_path = config;
    const DisplayTransform linear(o);
    EXPECT_EQ(linear.input_colorspace(), "scene");  // role scene_linear
    EXPECT_EQ(linear.display(), "monitor");
    EXPECT_EQ(linear.view(), "plain");
    o.input = SceneSpace::CieXyzD65;
    const DisplayTransform xyz(o);
    EXPECT_EQ(xyz.input_colorspace(), "display_xyz");  // role cie_xyz_d65_interchange
    const auto grey = xyz.apply(linear_srgb_to_xyz({0.18, 0.18, 0.18}));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(grey[c], 0.461356, 1e-4);

    // The shipped config's aliases resolve to its names.
    DisplayOptions alias;
    alias.config_path = kShippedConfig;
    alias.input_colorspace = "lin_ciexyz_d65";
    EXPECT_EQ(DisplayTransform(alias).input_colorspace(), "CIE XYZ-D65 - Scene-referred");
    alias.input_colorspace = "scene_linear";  // a role
    EXPECT_EQ(DisplayTransform(alias).input_colorspace(), "Linear Rec.709 (sRGB)");
}

// ---------------------------------------------------------------------------------------------
// PNG output

FloatImage grey_ramp(int channels) {
    FloatImage image;
    image.width = 4;
    image.height = 2;
    image.channels = channels;
    const float values[4] = {0.0f, 0.18f, 1.0f, 4.0f};
    for (std::size_t y = 0; y < image.height; ++y)
        for (std::size_t x = 0; x < image.width; ++x) {
            for (int c = 0; c < 3; ++c) image.pixels.push_back(values[x] * (y == 0 ? 1.0f : 0.5f));
            if (channels == 4) image.pixels.push_back(y == 0 ? 1.0f : 0.5f);
        }
    return image;
}

// The 4 x 2 ramps below, read back as stored.
npf::testing::Png read_ramp_png(const std::string& path) {
    npf::testing::Png png = npf::testing::read_png(path);
    EXPECT_EQ(png.width, 4);
    EXPECT_EQ(png.height, 2);
    return png;
}

TEST(ColorDisplayPng, WritesAReadableDisplayEncodedPng) {
    const std::string dir = npf::testing::temporary_folder("display_png");
    const std::string path = (fs::path(dir) / "ramp.png").string();
    write_display_png(path, grey_ramp(3), shipped());
    const npf::testing::Png png = read_ramp_png(path);
    const std::vector<unsigned char>& px = png.pixels;
    ASSERT_EQ(png.channels, 3);
    ASSERT_EQ(px.size(), 24u);
    const int expected_top[4] = {0, 118, 255, 255};  // 0.461356 * 255 = 117.6; 4.0 clips
    for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(px[x * 3 + c], expected_top[x]) << x;
    // Bottom row, half as bright: 0.09 encodes to 0.3318, level 85.
    EXPECT_EQ(px[(4 + 1) * 3], std::lround(linear_to_srgb(0.09) * 255.0));
    EXPECT_EQ(px[(4 + 1) * 3], 85);
    EXPECT_FALSE(has_temporary_files(dir));
}

TEST(ColorDisplayPng, StraightAlphaFromPremultiplied) {
    const std::string dir = npf::testing::temporary_folder("display_png_alpha");
    const std::string path = (fs::path(dir) / "ramp.png").string();
    write_display_png(path, grey_ramp(4), shipped());
    const npf::testing::Png png = read_ramp_png(path);
    const std::vector<unsigned char>& px = png.pixels;
    ASSERT_EQ(png.channels, 4);
    ASSERT_EQ(px.size(), 32u);
    // Bottom row: colour 0.09 premultiplied by alpha 0.5 is 0.18 straight -> 118.
    EXPECT_EQ(px[(4 + 1) * 4 + 0], 118);
    EXPECT_EQ(px[(4 + 1) * 4 + 3], 128);  // 0.5 * 255 = 127.5 rounds to 128
    EXPECT_EQ(px[(0 + 1) * 4 + 3], 255);
}

TEST(ColorDisplayPng, FailureLeavesNothingBehind) {
    const std::string dir = npf::testing::temporary_folder("display_png_fail");
    // The destination is a folder: the PNG is written to a temporary, the rename fails.
    const std::string folder = (fs::path(dir) / "taken.png").string();
    fs::create_directory(folder);
    std::string m = error_of([&] { write_display_png(folder, grey_ramp(3), shipped()); });
    EXPECT_TRUE(has(m, folder)) << m;
    EXPECT_FALSE(has_temporary_files(dir));
    // A folder that does not exist.
    const std::string nowhere = (fs::path(dir) / "no" / "such" / "out.png").string();
    m = error_of([&] { write_display_png(nowhere, grey_ramp(3), shipped()); });
    EXPECT_TRUE(has(m, nowhere)) << m;
    // Bad images are refused before anything is created.
    FloatImage two = grey_ramp(3);
    two.channels = 2;
    const std::string out = (fs::path(dir) / "out.png").string();
    EXPECT_TRUE(has(error_of([&] { write_display_png(out, two, shipped()); }), "3 or 4 channels"));
    FloatImage short_image = grey_ramp(3);
    short_image.pixels.pop_back();
    EXPECT_TRUE(has(error_of([&] { write_display_png(out, short_image, shipped()); }), "disagree"));
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(has_temporary_files(dir));
}

TEST(ColorDisplayPng, ReadsSceneImages) {
    const std::string dir = npf::testing::temporary_folder("display_read");
    const std::string rgba_path = (fs::path(dir) / "rgba.exr").string();
    {
        OIIO::ImageSpec spec(2, 1, 4, OIIO::TypeFloat);
        spec.alpha_channel = 3;
        const float px[8] = {0.1f, 0.2f, 0.3f, 1.0f, 4.0f, 5.0f, 6.0f, 0.5f};
        auto out = OIIO::ImageOutput::create(rgba_path);
        ASSERT_TRUE(out && out->open(rgba_path, spec) && out->write_image(OIIO::TypeFloat, px) && out->close());
    }
    const FloatImage image = read_scene_image(rgba_path);
    EXPECT_EQ(image.width, 2u);
    EXPECT_EQ(image.height, 1u);
    ASSERT_EQ(image.channels, 4);
    EXPECT_EQ(image.pixels, (std::vector<float>{0.1f, 0.2f, 0.3f, 1.0f, 4.0f, 5.0f, 6.0f, 0.5f}));

    const std::string grey_path = (fs::path(dir) / "y.exr").string();
    {
        OIIO::ImageSpec spec(2, 1, 1, OIIO::TypeFloat);
        const float px[2] = {0.5f, 0.25f};
        auto out = OIIO::ImageOutput::create(grey_path);
        ASSERT_TRUE(out && out->open(grey_path, spec) && out->write_image(OIIO::TypeFloat, px) && out->close());
    }
    std::string m = error_of([&] { read_scene_image(grey_path); });
    EXPECT_TRUE(has(m, grey_path) && has(m, "channel")) << m;
    const std::string missing = (fs::path(dir) / "missing.exr").string();
    m = error_of([&] { read_scene_image(missing); });
    EXPECT_TRUE(has(m, missing)) << m;
}

}  // namespace
