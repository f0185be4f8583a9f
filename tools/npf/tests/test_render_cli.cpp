// End-to-end tests of `npf render`: the built tool renders a small material under a small map
// (and under the shipped default map), writes an RGBA OpenEXR with its metadata and a PNG,
// reproduces itself bit for bit for any thread count, and fails on bad input with status 1, a
// message naming the file or option, and no output left behind.
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using npf::testing::contains;
using npf::testing::describe;
using npf::testing::folder_entries;
using npf::testing::ToolRun;

struct Exr {
    int width = 0, height = 0, channels = 0;
    std::vector<std::string> names;
    std::vector<float> pixels;
    OIIO::ImageSpec spec;
};

Exr read_exr(const std::string& path) {
    Exr e;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        ADD_FAILURE() << "cannot read " << path << ": " << OIIO::geterror();
        return e;
    }
    e.spec = in->spec();
    e.width = e.spec.width, e.height = e.spec.height, e.channels = e.spec.nchannels;
    e.names = e.spec.channelnames;
    e.pixels.resize(std::size_t(e.width) * std::size_t(e.height) * std::size_t(e.channels));
    EXPECT_TRUE(in->read_image(0, 0, 0, e.channels, OIIO::TypeFloat, e.pixels.data()));
    return e;
}

void write_exr(const std::string& path, int w, int h, const std::vector<float>& rgb) {
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeFloat);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeFloat, rgb.data()) && out->close());
}

// A folder with a small RGB material and a 16 x 8 map with a bright texel.
struct Fixture {
    std::string dir, material, env;
};

Fixture make_fixture(const std::string& tag) {
    Fixture f;
    f.dir = npf::testing::temporary_folder(tag);
    npf::testing::SyntheticRglSpec spec;
    spec.description = "render test material";
    f.material = npf::testing::write_synthetic_rgl(spec, f.dir + "/material.bsdf");
    std::vector<float> rgb(16 * 8 * 3, 0.3f);
    for (int k = 0; k < 3; ++k) rgb[(2 * 16 + 9) * 3 + k] = 40.f;
    f.env = f.dir + "/env.exr";
    write_exr(f.env, 16, 8, rgb);
    return f;
}

ToolRun render(std::vector<std::string> args) {
    args.insert(args.begin(), "render");
    return npf::testing::run_tool(args);
}

void expect_no_temporaries(const std::string& dir) {
    for (const std::string& name : folder_entries(dir)) EXPECT_FALSE(contains(name, ".tmp-")) << name;
}

TEST(RenderCli, WritesExrPngAndSummary) {
    const Fixture f = make_fixture("render_cli");
    const std::string out = f.dir + "/out.exr", png = f.dir + "/out.png";
    const ToolRun r = render({f.material, "--env", f.env, "-o", out, "--png", png, "--size", "24", "--spp", "4",
                              "--seed", "5", "--threads", "2", "--quiet"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.err, "") << describe(r);
    EXPECT_TRUE(contains(r.out, "wrote " + out + " and " + png + ": 24x24, 4 spp, RGB")) << r.out;
    EXPECT_TRUE(contains(r.out, "M samples/s on 2 threads")) << r.out;
    EXPECT_EQ(npf::testing::lines_of(r.out).size(), 1u) << r.out;

    const Exr e = read_exr(out);
    ASSERT_EQ(e.width, 24);
    ASSERT_EQ(e.height, 24);
    ASSERT_EQ(e.channels, 4);
    EXPECT_EQ(e.names, (std::vector<std::string>{"R", "G", "B", "A"}));
    EXPECT_EQ(e.spec.alpha_channel, 3);
    EXPECT_EQ(e.spec.get_string_attribute("npf:material"), f.material);
    EXPECT_EQ(e.spec.get_string_attribute("npf:envmap"), f.env);
    EXPECT_EQ(e.spec.get_string_attribute("npf:spp"), "4");
    EXPECT_EQ(e.spec.get_string_attribute("npf:seed"), "5");
    EXPECT_EQ(e.spec.get_string_attribute("npf:size"), "24x24");
    EXPECT_EQ(e.spec.get_string_attribute("npf:channels"), "rgb");
    EXPECT_EQ(e.spec.get_string_attribute("npf:material_description"), "render test material");
    EXPECT_TRUE(contains(e.spec.get_string_attribute("npf:values"), "scene-linear Rec.709"));
    EXPECT_FALSE(e.spec.get_string_attribute("npf:render_seconds").empty());
    EXPECT_FALSE(e.spec.get_string_attribute("DateTime").empty());
    // Black, transparent corners; a lit, opaque centre.
    for (int c = 0; c < 4; ++c) EXPECT_EQ(e.pixels[std::size_t(c)], 0.f);
    const float* centre = &e.pixels[(12 * 24 + 12) * 4];
    EXPECT_EQ(centre[3], 1.f);
    EXPECT_GT(centre[1], 0.f);
    for (float v : e.pixels) EXPECT_TRUE(std::isfinite(v));

    auto in = OIIO::ImageInput::open(png);
    ASSERT_TRUE(in);
    EXPECT_EQ(in->format_name(), std::string("png"));
    EXPECT_EQ(in->spec().width, 24);
    EXPECT_EQ(in->spec().nchannels, 4);
    expect_no_temporaries(f.dir);
}

TEST(RenderCli, DeterministicAcrossRunsAndThreads) {
    const Fixture f = make_fixture("render_cli_det");
    std::vector<Exr> images;
    for (const char* threads : {"1", "2", "2"}) {
        const std::string out = f.dir + "/t" + std::to_string(images.size()) + ".exr";
        const ToolRun r = render({f.material, "--env", f.env, "-o", out, "--size", "20", "--spp", "3", "--threads", threads});
        ASSERT_EQ(r.status, 0) << describe(r);
        images.push_back(read_exr(out));
    }
    EXPECT_EQ(images[0].pixels, images[1].pixels);
    EXPECT_EQ(images[1].pixels, images[2].pixels);
    // Another seed: another image.
    const std::string other = f.dir + "/seed.exr";
    ASSERT_EQ(render({f.material, "--env", f.env, "-o", other, "--size", "20", "--spp", "3", "--seed", "8"}).status, 0);
    EXPECT_NE(read_exr(other).pixels, images[0].pixels);
}

TEST(RenderCli, DefaultEnvironmentIsTheShippedStudioMap) {
    const Fixture f = make_fixture("render_cli_default");
    const std::string out = f.dir + "/default.exr";
    const ToolRun r = render({f.material, "-o", out, "--size", "8", "--spp", "1", "--quiet"});
    ASSERT_EQ(r.status, 0) << describe(r);
    const Exr e = read_exr(out);
    const std::string env = e.spec.get_string_attribute("npf:envmap");
    EXPECT_TRUE(contains(env, "envmaps/studio.exr")) << env;
    EXPECT_EQ(e.spec.get_string_attribute("npf:envmap_size"), "1024x512");
}

TEST(RenderCli, SpectralRecipeRendersAtItsWavelengths) {
    const Fixture f = make_fixture("render_cli_spectral");
    const std::string recipe = f.dir + "/grey.yaml";
    ASSERT_TRUE(npf::testing::write_text(recipe, "name: grey diffuse\nwavelengths: 380:780:21\ndiffuse: 0.5\n"));
    const std::string out = f.dir + "/grey.exr";
    const ToolRun r = render({recipe, "--env", f.env, "-o", out, "--size", "8", "--spp", "2", "--quiet"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "spectral, 21 wavelengths 380..780 nm")) << r.out;
    const Exr e = read_exr(out);
    EXPECT_EQ(e.spec.get_string_attribute("npf:channels").substr(0, 8), "380,400,");
    EXPECT_TRUE(contains(e.spec.get_string_attribute("npf:values"), "CIE 1931"));
    // Grey material, grey map: neutral pixels.
    const float* p = &e.pixels[(4 * 8 + 4) * 4];
    EXPECT_NEAR(p[0], p[1], 1e-3 * p[1]);
    EXPECT_NEAR(p[2], p[1], 1e-3 * p[1]);
    // --wavelengths rgb renders the same recipe in RGB.
    const ToolRun rgb = render({recipe, "--env", f.env, "-o", out, "--size", "8", "--spp", "2", "--wavelengths", "rgb"});
    ASSERT_EQ(rgb.status, 0) << describe(rgb);
    EXPECT_TRUE(contains(rgb.out, ", RGB,")) << rgb.out;
}

TEST(RenderCli, BadInputFailsCleanlyAndLeavesNothing) {
    const Fixture f = make_fixture("render_cli_bad");
    const std::string out = f.dir + "/never.exr", png = f.dir + "/never.png";
    std::string nan_env = f.dir + "/nan.exr";
    write_exr(nan_env, 2, 1, {1.f, 1.f, 1.f, 1.f, NAN, 1.f});
    const std::string missing = f.dir + "/missing.exr";
    struct Case {
        std::vector<std::string> args;
        std::string expect;
    };
    const std::vector<Case> cases = {
        {{f.material, "--env", missing, "-o", out}, missing},
        {{f.material, "--env", nan_env, "-o", out}, "NaN"},
        {{f.material, "--env", f.material, "-o", out}, f.material},  // not an image
        {{f.dir + "/nope.bsdf", "--env", f.env, "-o", out}, "nope.bsdf"},
        {{f.material, "--env", f.env, "-o", out, "--size", "0"}, "--size"},
        {{f.material, "--env", f.env, "-o", out, "--size", "10x"}, "--size"},
        {{f.material, "--env", f.env, "-o", out, "--spp", "0"}, "--spp"},
        {{f.material, "--env", f.env, "-o", out, "--seed", "1.5"}, "--seed"},
        {{f.material, "--env", f.env, "-o", out, "--threads", "0"}, "--threads"},
        {{f.material, "--env", f.env, "-o", out, "--exposure", "bright"}, "--exposure"},
        {{f.material, "--env", f.env, "-o", out, "--scene", "cube"}, "--scene"},
        {{f.material, "--env", f.env, "-o", out, "--sampling", "both"}, "--sampling"},
        {{f.material, "--env", f.env, "-o", out, "--wavelengths", "700:400:0"}, "--wavelengths"},
        {{f.material, "--env", f.env, "-o", out, "--wavelengths", "450,550,650"}, f.material},  // RGB material
        {{f.material, "--env", f.env, "-o", out, "--png", f.dir + "/no/such/folder/x.png", "--size", "4", "--spp", "1"},
         "no/such/folder"},
        {{f.material, "--env", f.env, "-o", f.dir + "/no/such/folder/x.exr", "--size", "4", "--spp", "1"}, "no/such/folder"},
    };
    for (const Case& c : cases) {
        const ToolRun r = render(c.args);
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_TRUE(contains(r.err, "npf render: error: ")) << describe(r);
        EXPECT_TRUE(contains(r.err, c.expect)) << "expected '" << c.expect << "'\n" << describe(r);
        EXPECT_EQ(r.out, "") << describe(r);
    }
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(png));
    expect_no_temporaries(f.dir);
    // Usage: no output, status 2; --help: status 0.
    EXPECT_EQ(render({f.material}).status, 2);
    const ToolRun help = render({"--help"});
    EXPECT_EQ(help.status, 0);
    EXPECT_TRUE(contains(help.out, "--wavelengths")) << help.out;
}

}  // namespace
