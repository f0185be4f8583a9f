// One way to open a material (issue 18 item 4): every `npf` subcommand that takes a material
// takes every source through npf::open_material (an analytic recipe, a measured file, an NPF
// texture), or says in one line, naming the file, why it needs a particular kind; and one
// parser of channel lists ("rgb" or wavelengths) behind every --wavelengths flag and key.
#include "npf_test_factors.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/batch/config.h>
#include <npf/fit/spectral_compression.h>
#include <npf/materials/material_recipe.h>
#include <npf/materials/open_material.h>
#include <npf/core/channels.h>
#include <npf/core/error.h>
#include <npf/shading/npf_texture_file.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using npf::testing::contains, npf::testing::describe, npf::testing::lines_of, npf::testing::run_tool,
      npf::testing::ToolRun;

const char* kRedPlastic = "configs/materials/red_plastic.yaml";
const std::string kChannelForms = "(a channel list is rgb, a,b,c or start:end:count, in nm)";

const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("open-material");
    return dir;
}

ToolRun in_source_dir(const std::vector<std::string>& args, const std::optional<std::string>& stdin_text = std::nullopt) {
    return run_tool(args, {stdin_text, NPF_SOURCE_DIR});
}

std::vector<double> numbers(const std::string& line) {
    std::istringstream is(line);
    std::vector<double> v;
    for (double x; is >> x;) v.push_back(x);
    return v;
}

// One material of each kind, all small and at the same four wavelengths, so that every command
// runs in moments and bench and albedo can set any against the texture.
struct Sources {
    std::string recipe, rgl, npf;
};

const Sources& sources() {
    static const Sources s = [] {
        Sources r;
        r.recipe = folder() + "/plastic.yaml";
        npf::testing::write_text(r.recipe, "name: test plastic\nwavelengths: 400:700:4\n"
                                           "lobes:\n  - {distribution: ggx, alpha: 0.3, fresnel: {dielectric: 1.5}}\n"
                                           "diffuse: {srgb: [0.5, 0.4, 0.3]}\n");
        npf::testing::SyntheticRglSpec rgl;
        rgl.spectral = true;
        r.rgl = npf::testing::write_synthetic_rgl(rgl, folder() + "/measured.bsdf");
        npf::testing::MicrofacetSpec spec;
        spec.spectral = true;
        spec.channels = 4;
        spec.d_theta = spec.f_theta = spec.g_theta = 16;
        r.npf = folder() + "/fitted.exr";
        npf::write_npf_texture(npf::compress_factors(npf::testing::make_microfacet_factors(spec), npf::CompressionOptions()),
                               r.npf);
        return r;
    }();
    return s;
}

// ---- npf eval and npf info on a recipe ------------------------------------------------------------

TEST(OpenMaterial, EvalTakesARecipe) {
    const ToolRun r = in_source_dir({"eval", kRedPlastic}, std::string("0 0 1 0.3 0.1 0.9\n"));
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), 2u) << describe(r);
    // The recipe's own 41 wavelengths, and the values the library gives for the same pair.
    const std::unique_ptr<npf::Brdf> brdf = npf::open_material(std::string(NPF_SOURCE_DIR) + "/" + kRedPlastic);
    EXPECT_EQ(lines[0], "# " + brdf->info().channels.describe());
    const npf::ChannelQuery q = brdf->query(brdf->info().channels);
    const npf::Vec3 wi(0.f, 0.f, 1.f);
    const double l = std::hypot(0.3, 0.1, 0.9);
    const npf::Vec3 wo(float(0.3 / l), float(0.1 / l), float(0.9 / l));
    std::vector<float> want(q.size());
    brdf->eval_cos(wi, wo, q, want.data());
    const std::vector<double> got = numbers(lines[1]);
    ASSERT_EQ(got.size(), 41u) << describe(r);
    for (std::size_t k = 0; k < got.size(); ++k) {
        EXPECT_GT(got[k], 0.0) << k;
        EXPECT_NEAR(got[k], double(want[k]) / double(wo.z), 1e-6 * got[k]) << k;
    }
}

TEST(OpenMaterial, InfoTakesARecipe) {
    const ToolRun r = in_source_dir({"info", kRedPlastic, sources().rgl});
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::string bytes = std::to_string(fs::file_size(std::string(NPF_SOURCE_DIR) + "/" + kRedPlastic));
    for (const std::string& line : {std::string("file: ") + kRedPlastic,
                                    std::string("format: analytic material recipe (YAML, .yaml; docs/synth.md)"),
                                    std::string("description: red plastic (analytic, npf synth)"),
                                    "size: " + bytes + " bytes (" + bytes + " B)",
                                    std::string("channels: spectral, 41 wavelengths, 380.0 to 780.0 nm"),
                                    std::string("format: RGL measured BRDF (tensor_file 1.0, .bsdf)")}) {
        EXPECT_TRUE(npf::testing::has_line(r.out, line)) << "no line '" << line << "'\n" << describe(r);
    }
}

// ---- every subcommand that takes a material -------------------------------------------------------

TEST(OpenMaterial, EveryMaterialCommandTakesEverySource) {
    const std::string out = folder() + "/every";
    fs::create_directories(out);
    const Sources& s = sources();
    for (const std::string& source : {s.recipe, s.rgl, s.npf}) {
        const std::string tag = fs::path(source).extension().string().substr(1);
        const std::vector<std::vector<std::string>> commands = {
            {"info", source},
            {"eval", source, "--pdf"},
            {"convert", source, "-o", out + "/" + tag + ".exr", "--preset", "preview", "--no-predict", "--threads", "1"},
            {"render", source, "-o", out + "/" + tag + "_render.exr", "--size", "8", "--spp", "1", "--threads", "1",
             "--quiet"},
            {"albedo", source, "--theta", "0,60", "--samples", "8"},
            {"albedo", s.npf, "--against", source, "--theta", "0,60", "--samples", "8"},
            {"bench", s.npf, "--against", source, "--seconds", "0.001", "--threads", "1", "--json"},
        };
        for (const std::vector<std::string>& args : commands) {
            const ToolRun r = in_source_dir(args, std::string("0 0 1 0.3 0.1 0.9\n"));
            EXPECT_EQ(r.status, 0) << describe(r);
            EXPECT_FALSE(contains(r.err, "error")) << describe(r);
        }
    }
    // What convert wrote from each source is itself a source for every command.
    const ToolRun info = in_source_dir({"info", out + "/yaml.exr", out + "/bsdf.exr", out + "/exr.exr"});
    EXPECT_EQ(info.status, 0) << describe(info);
}

// `npf edit` needs an NPF texture, and `npf bench` times one: any other source is refused in one
// line that names the file and says what to do, before any work.
TEST(OpenMaterial, CommandsThatNeedATextureSaySoNamingTheFile) {
    const Sources& s = sources();
    const std::string out = folder() + "/edited.exr";
    const ToolRun good = in_source_dir({"edit", s.npf, "-o", out, "--rotate", "30", "--no-albedo-check"});
    ASSERT_EQ(good.status, 0) << describe(good);
    struct Case {
        std::vector<std::string> args;
        std::string file, message;
    };
    const std::string edit_message = "not an NPF factor texture; npf edit works on fitted materials (convert it first: npf convert)";
    const Case cases[] = {
        {{"edit", s.recipe, "-o", out, "--rotate", "30"}, s.recipe, "npf edit: error: " + s.recipe + ": " + edit_message},
        {{"edit", s.rgl, "-o", out, "--rotate", "30"}, s.rgl, "npf edit: error: " + s.rgl + ": " + edit_message},
        {{"edit", s.npf, "-o", out, "--diffuse-from", s.recipe}, s.recipe,
         "npf edit: error: --diffuse-from: " + s.recipe + ": " + edit_message},
        {{"edit", s.npf, "-o", out, "--specular-from", s.rgl}, s.rgl,
         "npf edit: error: --specular-from: " + s.rgl + ": " + edit_message},
        {{"bench", s.recipe}, s.recipe, "npf bench: error: " + s.recipe + ": not an NPF factor texture (convert it first: npf convert)"},
    };
    for (const Case& c : cases) {
        fs::remove(out);
        const ToolRun r = in_source_dir(c.args);
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_EQ(r.err, c.message + "\n") << describe(r);
        EXPECT_EQ(r.out, "") << describe(r);
        EXPECT_FALSE(fs::exists(out)) << describe(r);
    }
}

// ---- the channel list parser -------------------------------------------------------------------

TEST(ChannelList, AcceptsRgbAndWavelengthLists) {
    EXPECT_TRUE(npf::parse_channel_list("rgb", "--wavelengths").is_rgb());
    struct Case {
        std::string text;
        std::vector<float> wavelengths;
    };
    const Case cases[] = {
        {"550", {550.f}},
        {"450,550,650", {450.f, 550.f, 650.f}},
        {"700,400", {700.f, 400.f}},  // any order: the caller judges
        {"400:700:4", {400.f, 500.f, 600.f, 700.f}},
        {"555.5:555.5:1", {555.5f}},
        {"4.5e2,5.5E2", {450.f, 550.f}},
    };
    for (const Case& c : cases) {
        const npf::Channels ch = npf::parse_channel_list(c.text, "--wavelengths");
        EXPECT_FALSE(ch.is_rgb()) << c.text;
        EXPECT_EQ(ch.wavelengths(), c.wavelengths) << c.text;
    }
    const npf::Channels many = npf::parse_channel_list("380:780:41", "k");
    ASSERT_EQ(many.size(), 41u);
    EXPECT_EQ(many.wavelengths().front(), 380.f);
    EXPECT_EQ(many.wavelengths().back(), 780.f);
}

TEST(ChannelList, RefusesEverythingElseNamingTheFlag) {
    struct Case {
        std::string text, problem;
    };
    const Case cases[] = {
        {"RGB", "'RGB' in wavelength list 'RGB' is not a positive number (nm)"},
        {" rgb", "' rgb' in wavelength list"},
        {"rgb,450", "'rgb' in wavelength list 'rgb,450'"},
        {"visible", "'visible' in wavelength list 'visible' is not a positive number (nm)"},
        {"", "empty wavelength list"},
        {"450,", "'' in wavelength list '450,'"},
        {"0,500", "'0' in wavelength list"},
        {"-450", "'-450' in wavelength list"},
        {"inf", "'inf' in wavelength list"},
        {"400:700", "wavelength range '400:700' must be start:end:count"},
        {"700:400:4", "wavelength range '700:400:4' ends before it starts"},
        {"400:700:2.5", "count '2.5' in '400:700:2.5' must be a whole number"},
        {"400:700:1", "a range of one wavelength needs start == end"},
    };
    for (const Case& c : cases) {
        try {
            npf::parse_channel_list(c.text, "--wavelengths");
            ADD_FAILURE() << "accepted '" << c.text << "'";
        } catch (const npf::Error& e) {
            EXPECT_EQ(e.source(), "--wavelengths") << c.text;
            EXPECT_EQ(e.problem().rfind(c.problem, 0), 0u) << c.text << ": " << e.what();
            const std::string tail = " " + kChannelForms;
            EXPECT_EQ(e.problem().substr(e.problem().size() - std::min(e.problem().size(), tail.size())), tail)
                << c.text << ": " << e.what();
        }
    }
}

// Every flag and key that takes a channel list fails alike: the flag or key, the problem, the forms.
TEST(ChannelList, EveryFlagAndKeyFailsAlike) {
    const std::string problem = "'visible' in wavelength list 'visible' is not a positive number (nm) " + kChannelForms;
    const Sources& s = sources();
    const std::string out = folder() + "/bad-list";
    const std::vector<std::pair<std::vector<std::string>, std::string>> tools = {
        {{"convert", s.rgl, "-o", out + ".exr", "--wavelengths", "visible"}, "npf convert: error: --wavelengths: "},
        {{"render", s.rgl, "-o", out + ".exr", "--wavelengths", "visible"}, "npf render: error: --wavelengths: "},
        {{"synth", "-o", out + ".bsdf", "--diffuse", "0.5", "--wavelengths", "visible"}, "npf synth: error: --wavelengths: "},
    };
    for (const auto& [args, prefix] : tools) {
        const ToolRun r = in_source_dir(args);
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_EQ(r.err, prefix + problem + "\n") << describe(r);
    }
    // The recipe key, through every command that opens a material.
    const std::string recipe = folder() + "/bad_list.yaml";
    npf::testing::write_text(recipe, "name: x\nwavelengths: visible\ndiffuse: 0.5\n");
    const ToolRun info = in_source_dir({"info", recipe});
    EXPECT_EQ(info.status, 1) << describe(info);
    EXPECT_EQ(info.err, "npf info: error: " + recipe + ":2: key 'wavelengths': " + problem + "\n") << describe(info);
    // The batch key.
    const std::string in = folder() + "/batch-in";
    fs::create_directories(in);
    npf::testing::write_text(in + "/a.bsdf", "x");
    try {
        npf::batch::parse_batch_config("output_dir: out\ninputs: a.bsdf\ndefaults:\n  wavelengths: visible\n", "cfg.yaml", in);
        ADD_FAILURE() << "the batch took 'visible'";
    } catch (const npf::Error& e) {
        EXPECT_EQ(std::string(e.what()), "cfg.yaml:4: key 'defaults.wavelengths': " + problem);
    }
}

}  // namespace
