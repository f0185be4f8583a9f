// End-to-end tests of `npf synth`: the built tool writes RGL files from flags and from recipes,
// `npf info` describes them and `npf eval` reads them back close to the analytic material
// evaluated in-process; failures exit with status 1, name the problem and leave no file (not
// even a temporary one) behind. Grids are tiny everywhere so that each run takes milliseconds.
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/color/spectrum.h>
#include <npf/materials/analytic/analytic_brdf.h>
#include <npf/materials/material_recipe.h>
#include <npf/core/channels.h>
#include <npf/core/vec.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

using npf::Vec3;
using namespace npf::testing;  // run_tool, describe, contains, ...

// The small grid every run uses: 5 phi_i x 4 theta_i, 8 x 32 NDF, 24 x 24 VNDF, 8 x 8 data.
const std::vector<std::string> kSmallGrid = {"--phi", "5",   "--theta", "4",  "--vndf",     "24",
                                             "--data", "8", "--ndf",   "32", "--ndf-rows", "8"};

std::vector<std::string> concat(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

// `npf synth <small grid> args... --quiet`; --threads 1 unless `threads` says otherwise. A flag
// given twice takes its last value, so `args` may override the small grid.
ToolRun synth(const std::vector<std::string>& args, const std::string& threads = "1", const std::string& cwd = "") {
    std::vector<std::string> all = concat(concat({"synth"}, kSmallGrid), args);
    all.push_back("--quiet");
    if (!threads.empty()) all.insert(all.end(), {"--threads", threads});
    npf::testing::ToolRunOptions options;
    options.working_dir = cwd;
    return npf::testing::run_tool(all, options);
}


// `npf info path`, checked to succeed.
std::string info(const std::string& path) {
    const ToolRun r = npf::testing::run_tool({"info", path});
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.err, "") << describe(r);
    return r.out;
}

void expect_lines(const std::string& text, const std::vector<std::string>& lines) {
    for (const std::string& l : lines) EXPECT_TRUE(has_line(text, l)) << "missing line '" << l << "' in:\n" << text;
}

// A fresh, empty folder for one test's outputs.
std::string fresh_folder(const std::string& tag) { return npf::testing::temporary_folder("synth_" + tag); }

// ---- The anisotropic spectral copper made by flags ------------------------------------------

// The narrow lobe (alpha 0.08 along the tangent) needs a finer NDF table than the small grid's
// for the read-back to follow the analytic material (relative RMS 0.2 with 32 x 8 and data 8,
// 0.023 with these, 0.006 with the default grid).
const std::vector<std::string> kCopperFlags = {"--conductor", "Cu",        "--alpha", "0.08,0.35", "--diffuse",
                                               "0.02",        "--wavelengths", "400:700:7", "--ndf", "64",
                                               "--ndf-rows",  "32",        "--data",  "16"};

// The same material, built in-process.
npf::AnalyticMaterial copper_material() {
    npf::AnalyticMaterial m;
    npf::SpecularLobe lobe;
    lobe.ndf.type = npf::MicrofacetDistribution::Ggx;
    lobe.ndf.alpha_x = 0.08f;
    lobe.ndf.alpha_y = 0.35f;
    lobe.fresnel = npf::conductor_fresnel("Cu", "test");
    m.specular.push_back(lobe);
    m.diffuse = npf::color::SampledSpectrum::constant(0.02);
    m.wavelengths = npf::parse_wavelength_list("400:700:7", "test");
    return m;
}

struct CopperFile {
    std::string folder, path;
    ToolRun run;
};

// Written once (with the default thread count, the tool's ordinary path) and shared.
const CopperFile& copper_file() {
    static const CopperFile f = [] {
        CopperFile c;
        c.folder = fresh_folder("copper");
        c.path = c.folder + "/copper.bsdf";
        c.run = synth(concat({"-o", c.path}, kCopperFlags), "");
        return c;
    }();
    return f;
}

TEST(CliSynthFlags, AnisotropicSpectralCopper) {
    const CopperFile& f = copper_file();
    ASSERT_EQ(f.run.status, 0) << describe(f.run);
    EXPECT_EQ(f.run.err, "") << describe(f.run);
    EXPECT_EQ(f.run.out.rfind("wrote " + f.path + ": anisotropic, 7 wavelengths, 5 phi_i x 4 theta_i, ", 0), 0u)
        << describe(f.run);
    EXPECT_EQ(folder_entries(f.folder), std::vector<std::string>{"copper.bsdf"});  // nothing else left behind
    const std::string text = info(f.path);
    expect_lines(text, {
                           "format: RGL measured BRDF (tensor_file 1.0, .bsdf)",
                           "description: synthetic material",
                           "isotropic: no",
                           "channels: spectral, 7 wavelengths, 400.0 to 700.0 nm",
                           "wavelengths (nm): 400 450 500 550 600 650 700",
                           "phi_i reduction: 1 (phi_i covers 2 pi / 1)",
                           "phi_i: 5 values: -3.1416 -1.5708 0 1.5708 3.1416",
                           "data grid: 5 x 4 x 7 x 16 x 16 (spectra)",
                           "ndf grid: 32 x 64",
                           "sigma grid: 32 x 64",
                           "vndf grid: 5 x 4 x 24 x 24",
                           "jacobian: 1 (data are the ratio to the VNDF pdf)",
                       });
    EXPECT_TRUE(contains(text, "\ntheta_i: 4 values: 0 ")) << text;
    EXPECT_TRUE(contains(text, " 1.5708\n")) << text;  // theta_i ends at pi/2
}

TEST(CliSynthFlags, OneThreadWritesTheSameBytes) {
    const CopperFile& f = copper_file();
    ASSERT_EQ(f.run.status, 0) << describe(f.run);
    const std::string folder = fresh_folder("copper1");
    const ToolRun r = synth(concat({"-o", folder + "/copper.bsdf"}, kCopperFlags), "1");
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::string a = npf::testing::read_text(f.path), b = npf::testing::read_text(folder + "/copper.bsdf");
    EXPECT_FALSE(a.empty());
    EXPECT_TRUE(a == b) << "the file depends on the thread count";
}

// Random pairs above the horizon, not too grazing (theta up to 81 degrees), deterministic.
std::vector<std::array<Vec3, 2>> random_pairs(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uni(0.f, 1.f);
    std::vector<std::array<Vec3, 2>> out;
    for (int i = 0; i < n; ++i) {
        const Vec3 wi = npf::spherical_direction(float(0.45 * npf::kPiD) * uni(rng), float(2 * npf::kPiD) * uni(rng));
        const Vec3 wo = npf::spherical_direction(float(0.45 * npf::kPiD) * uni(rng), float(2 * npf::kPiD) * uni(rng));
        out.push_back({wi, wo});
    }
    return out;
}

TEST(CliSynthFlags, EvalMatchesTheAnalyticMaterial) {
    const CopperFile& f = copper_file();
    ASSERT_EQ(f.run.status, 0) << describe(f.run);
    const std::vector<std::array<Vec3, 2>> pairs = random_pairs(400, 7);
    std::string text;
    char buf[256];
    for (const auto& p : pairs) {
        std::snprintf(buf, sizeof(buf), "%.9g %.9g %.9g %.9g %.9g %.9g\n", p[0].x, p[0].y, p[0].z, p[1].x, p[1].y,
                      p[1].z);
        text += buf;
    }
    npf::testing::ToolRunOptions options;
    options.stdin_text = text;
    const ToolRun r = npf::testing::run_tool({"eval", f.path, "--cos"}, options);
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), pairs.size() + 1) << describe(r);
    EXPECT_EQ(lines[0], "# 400 450 500 550 600 650 700");

    const npf::AnalyticBrdf brdf(copper_material());
    const npf::ChannelQuery q = brdf.query(npf::Channels::spectral(npf::parse_wavelength_list("400:700:7", "test")));
    double diff2 = 0.0, ref2 = 0.0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
        float want[7];
        brdf.eval_cos(pairs[i][0], pairs[i][1], q, want);
        std::istringstream is(lines[i + 1]);
        for (int k = 0; k < 7; ++k) {
            double got = 0.0;
            ASSERT_TRUE(bool(is >> got)) << "line " << i + 2 << ": " << lines[i + 1];
            ASSERT_TRUE(std::isfinite(got) && got >= 0.0) << "line " << i + 2 << ": " << lines[i + 1];
            diff2 += (got - want[k]) * (got - want[k]);
            ref2 += double(want[k]) * want[k];
        }
    }
    ASSERT_GT(ref2, 0.0);
    const double rms = std::sqrt(diff2 / ref2);
    std::printf("relative RMS of npf eval --cos against the analytic copper: %.4f\n", rms);
    EXPECT_LT(rms, 0.05);
}

// ---- Isotropy, channels, names -----------------------------------------------------------

TEST(CliSynthFlags, IsotropicDielectric) {
    const std::string folder = fresh_folder("iso");
    const ToolRun r = synth({"-o", folder + "/d.bsdf", "--dielectric", "1.5", "--alpha", "0.2"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, ": isotropic, 195 wavelengths, 1 phi_i x 4 theta_i, ")) << describe(r);
    const std::string text = info(folder + "/d.bsdf");
    expect_lines(text, {"isotropic: yes", "phi_i: 1 values: 0", "channels: spectral, 195 wavelengths, 360.0 to 1000.0 nm",
                        "data grid: 1 x 4 x 195 x 8 x 8 (spectra)", "ndf grid: 2 x 32", "vndf grid: 1 x 4 x 24 x 24"});
    EXPECT_FALSE(contains(text, "phi_i reduction")) << text;
}

TEST(CliSynthFlags, AnisotropyForced) {
    const std::string folder = fresh_folder("forced");
    ToolRun r = synth({"-o", folder + "/a.bsdf", "--dielectric", "1.5", "--alpha", "0.2", "--anisotropy", "anisotropic"});
    ASSERT_EQ(r.status, 0) << describe(r);
    expect_lines(info(folder + "/a.bsdf"), {"isotropic: no", "phi_i: 5 values: -3.1416 -1.5708 0 1.5708 3.1416",
                                            "ndf grid: 8 x 32", "data grid: 5 x 4 x 195 x 8 x 8 (spectra)"});
    // And the other way round: an anisotropic material written as isotropic when asked.
    r = synth({"-o", folder + "/i.bsdf", "--dielectric", "1.5", "--alpha", "0.1,0.3", "--anisotropy", "isotropic",
               "--wavelengths", "rgb"});
    ASSERT_EQ(r.status, 0) << describe(r);
    expect_lines(info(folder + "/i.bsdf"), {"isotropic: yes", "phi_i: 1 values: 0"});
    // auto detects the anisotropy of the rotated lobe too.
    r = synth({"-o", folder + "/r.bsdf", "--dielectric", "1.5", "--alpha", "0.1,0.3", "--rotation", "30",
               "--wavelengths", "rgb"});
    ASSERT_EQ(r.status, 0) << describe(r);
    expect_lines(info(folder + "/r.bsdf"), {"isotropic: no"});
}

TEST(CliSynthFlags, RgbFile) {
    const std::string folder = fresh_folder("rgb");
    const std::string path = folder + "/plastic.bsdf";
    // A data grid of 16 (not the tiny default of these tests): at 8 x 8 the off-specular
    // diffuse value below is off by a factor of three (the VNDF warp spends the nodes on the lobe).
    const ToolRun r = synth({"-o", path, "--dielectric", "1.5", "--alpha", "0.1", "--diffuse", "0.8,0.08,0.05",
                             "--wavelengths", "rgb", "--name", "my plastic", "--theta", "6", "--data", "16", "--vndf", "48"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, ": isotropic, RGB, 1 phi_i x 6 theta_i, ")) << describe(r);
    const std::string text = info(path);
    expect_lines(text, {"description: my plastic", "channels: RGB (linear sRGB), 3 channels",
                        "data grid: 1 x 6 x 3 x 16 x 16 (rgb)"});
    EXPECT_FALSE(contains(text, "wavelengths (nm)")) << text;
    // Off the highlight the red diffuse term dominates: red well above blue.
    npf::testing::ToolRunOptions options;
    options.stdin_text = "0 0 1  0.6 0 0.8\n";
    const ToolRun e = npf::testing::run_tool({"eval", path}, options);
    ASSERT_EQ(e.status, 0) << describe(e);
    const std::vector<std::string> lines = lines_of(e.out);
    ASSERT_EQ(lines.size(), 2u) << describe(e);
    EXPECT_EQ(lines[0], "# R G B");
    double rgb[3] = {0, 0, 0};
    std::istringstream(lines[1]) >> rgb[0] >> rgb[1] >> rgb[2];
    EXPECT_GT(rgb[0], 5 * rgb[2]) << lines[1];
    EXPECT_NEAR(rgb[0], npf::color::srgb_to_linear(0.8) / npf::kPiD, 0.25 * rgb[0]) << lines[1];
}

const std::string kRedPlastic = "configs/materials/red_plastic.yaml";  // relative to NPF_SOURCE_DIR

TEST(CliSynthRecipe, ShippedRecipeWithGridFlags) {
    const std::string folder = fresh_folder("recipe");
    const std::string path = folder + "/red.bsdf";
    // Run from the source tree, so that the recipe's path is the relative one from the docs.
    const ToolRun r = synth({"--recipe", kRedPlastic, "-o", path}, "1", NPF_SOURCE_DIR);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, ": isotropic, 41 wavelengths, 1 phi_i x 4 theta_i, ")) << describe(r);
    expect_lines(info(path), {"description: red plastic (analytic, npf synth)", "isotropic: yes",
                              "channels: spectral, 41 wavelengths, 380.0 to 780.0 nm",
                              "data grid: 1 x 4 x 41 x 8 x 8 (spectra)", "ndf grid: 2 x 32",
                              "vndf grid: 1 x 4 x 24 x 24"});
    EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"red.bsdf"});
}

TEST(CliSynthRecipe, FlagsOverrideTheRecipe) {
    const std::string folder = fresh_folder("override");
    const std::string recipe = std::string(NPF_SOURCE_DIR) + "/" + kRedPlastic;
    // --name replaces the description, --wavelengths the recipe's, --alpha edits its lobe.
    const ToolRun r = synth({"--recipe", recipe, "-o", folder + "/o.bsdf", "--name", "renamed", "--wavelengths", "rgb",
                             "--alpha", "0.1,0.3"});
    ASSERT_EQ(r.status, 0) << describe(r);
    expect_lines(info(folder + "/o.bsdf"),
                 {"description: renamed", "channels: RGB (linear sRGB), 3 channels", "isotropic: no"});
}

TEST(CliSynthRecipe, OutputFromTheRecipe) {
    const std::string folder = fresh_folder("recipe_output");
    ASSERT_TRUE(npf::testing::write_text(folder + "/grey.yaml", "name: grey\noutput: grey.bsdf\nwavelengths: rgb\n"
                                                                "diffuse: 0.5\n"));
    // Run elsewhere: `output` is relative to the recipe, not to the working folder.
    ToolRun r = synth({"--recipe", folder + "/grey.yaml"}, "1", NPF_SOURCE_DIR);
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(folder_entries(folder), (std::vector<std::string>{"grey.bsdf", "grey.yaml"}));
    expect_lines(info(folder + "/grey.bsdf"), {"description: grey", "isotropic: yes"});
    // -o wins over the recipe's output.
    r = synth({"--recipe", folder + "/grey.yaml", "-o", folder + "/other.bsdf"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(folder_entries(folder), (std::vector<std::string>{"grey.bsdf", "grey.yaml", "other.bsdf"}));
}

// ---- Errors ------------------------------------------------------------------------------

// Runs synth in a fresh folder with `args` ("@OUT@" in them replaced by the folder's path) and,
// when `add_output`, "-o <folder>/out.bsdf"; expects status 1, one line naming `message` on
// standard error, nothing on standard output, and no file (output or temporary) in the folder.
void expect_failure(const std::string& tag, const std::vector<std::string>& args, const std::string& message,
                    bool add_output = true) {
    const std::string folder = fresh_folder(tag);
    std::vector<std::string> all = args;
    for (std::string& a : all) {
        const std::size_t at = a.find("@OUT@");
        if (at != std::string::npos) a.replace(at, 5, folder);
    }
    if (add_output) all = concat({"-o", folder + "/out.bsdf"}, all);
    const ToolRun r = synth(all, "1", folder);
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "npf synth: error: ")) << describe(r);
    EXPECT_TRUE(contains(r.err, message)) << "expected '" << message << "' in the message\n" << describe(r);
    EXPECT_EQ(lines_of(r.err).size(), 1u) << "one line of error expected\n" << describe(r);
    EXPECT_EQ(r.out, "") << describe(r);
    std::vector<std::string> left = folder_entries(folder);
    // Inputs the test put there are fine; anything else is an output or a leftover.
    std::vector<std::string> unexpected;
    for (const std::string& name : left) {
        if (name.size() < 5 || name.compare(name.size() - 5, 5, ".yaml") != 0) unexpected.push_back(name);
    }
    EXPECT_TRUE(unexpected.empty()) << "left behind in " << folder << ": " << unexpected.front() << "\n" << describe(r);
}

TEST(CliSynthErrors, NoOutput) {
    expect_failure("no_output", {"--diffuse", "0.5"}, "no output file: give -o OUT.bsdf (or 'output' in the recipe)",
                   false);
    expect_failure("no_output_recipe", {"--recipe", std::string(NPF_SOURCE_DIR) + "/" + kRedPlastic},
                   "no output file: give -o OUT.bsdf", false);
}

TEST(CliSynthErrors, UnknownMetal) {
    expect_failure("metal", {"--conductor", "Xx", "--alpha", "0.2"},
                   "--conductor: no refractive index tables for metal 'Xx' (shipped: Ag, Al, Au, Cr, Cu)");
    expect_failure("film_metal", {"--thin-film", "400,1.33,Xx", "--alpha", "0.2"},
                   "--thin-film: no refractive index tables for metal 'Xx'");
}

TEST(CliSynthErrors, BadAlpha) {
    expect_failure("alpha_text", {"--conductor", "Cu", "--alpha", "rough"}, "--alpha: 'rough' is not a number");
    expect_failure("alpha_zero", {"--conductor", "Cu", "--alpha", "0"}, "--alpha: roughness must lie in [1e-4, 4]");
    expect_failure("alpha_big", {"--conductor", "Cu", "--alpha", "0.1,5"}, "--alpha: roughness must lie in [1e-4, 4]");
    expect_failure("alpha_three", {"--conductor", "Cu", "--alpha", "0.1,0.2,0.3"}, "--alpha:");
    expect_failure("alpha_empty", {"--conductor", "Cu", "--alpha", "0.1,"}, "--alpha: '' is not a number");
}

TEST(CliSynthErrors, BadWavelengths) {
    expect_failure("wl_range", {"--diffuse", "0.5", "--wavelengths", "400:700"},
                   "--wavelengths: wavelength range '400:700' must be start:end:count");
    expect_failure("wl_text", {"--diffuse", "0.5", "--wavelengths", "visible"}, "--wavelengths: ");
    expect_failure("wl_zero", {"--diffuse", "0.5", "--wavelengths", "0:700:5"}, "is not a positive number");
    expect_failure("wl_order", {"--diffuse", "0.5", "--wavelengths", "700,400"}, "strictly ascending");
}

TEST(CliSynthErrors, BadGrid) {
    expect_failure("phi", {"--diffuse", "0.5", "--phi", "2"}, "--phi: needs a whole number in [3, 4096], got '2'");
    expect_failure("theta", {"--diffuse", "0.5", "--theta", "4.5"}, "--theta: needs a whole number in [2, 4096]");
    expect_failure("data", {"--diffuse", "0.5", "--data", "5000"}, "--data: needs a whole number");
}

TEST(CliSynthErrors, OtherBadFlags) {
    expect_failure("distribution", {"--alpha", "0.2", "--distribution", "phong"}, "'phong' is not ggx or beckmann");
    expect_failure("anisotropy", {"--diffuse", "0.5", "--anisotropy", "maybe"},
                   "--anisotropy: 'maybe' is not auto, isotropic or anisotropic");
    expect_failure("diffuse", {"--diffuse", "0.5,0.5"}, "--diffuse: '0.5,0.5' is neither one number nor an r,g,b colour");
    expect_failure("thin_film", {"--alpha", "0.2", "--thin-film", "400,1.33"}, "--thin-film: needs THICKNESS_NM,FILM_IOR,BASE");
    expect_failure("thin_film_negative", {"--alpha", "0.2", "--thin-film", "-5,1.33,Al"},
                   "--thin-film: the film thickness must not be negative");
    expect_failure("two_fresnel", {"--alpha", "0.2", "--conductor", "Cu", "--dielectric", "1.5"},
                   "give at most one Fresnel term");
    expect_failure("schlick_range", {"--alpha", "0.2", "--schlick", "2"}, "--schlick: ");
    expect_failure("nothing", {"--wavelengths", "rgb"}, "the material reflects nothing");
    expect_failure("unknown_flag", {"--diffuse", "0.5", "--colour", "red"}, "unknown option '--colour'");
}

TEST(CliSynthErrors, RecipeSyntaxError) {
    const std::string folder = fresh_folder("bad_recipe");
    ASSERT_TRUE(npf::testing::write_text(folder + "/bad.yaml", "name: bad\n\tdiffuse: 0.5\n"));
    const ToolRun r = synth({"--recipe", folder + "/bad.yaml", "-o", folder + "/out.bsdf"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, folder + "/bad.yaml:2: not valid YAML")) << describe(r);
    EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"bad.yaml"});

    ASSERT_TRUE(npf::testing::write_text(folder + "/bad.yaml", "name: bad\nlobes:\n  - alpha: 7\n"));
    const ToolRun r2 = synth({"--recipe", folder + "/bad.yaml", "-o", folder + "/out.bsdf"});
    EXPECT_EQ(r2.status, 1) << describe(r2);
    EXPECT_TRUE(contains(r2.err, folder + "/bad.yaml:3: key 'alpha': roughness must lie in [1e-4, 4]")) << describe(r2);
    EXPECT_EQ(folder_entries(folder), std::vector<std::string>{"bad.yaml"});

    expect_failure("missing_recipe", {"--recipe", "@OUT@/none.yaml"}, "none.yaml: cannot open: file not found");
    expect_failure("dir_recipe", {"--recipe", "@OUT@"}, ": is a directory, not a recipe");
}

TEST(CliSynthErrors, OutputInAMissingFolder) {
    const std::string folder = fresh_folder("missing_dir");
    const std::string path = folder + "/no/such/folder/out.bsdf";
    const ToolRun r = synth({"-o", path, "--diffuse", "0.5", "--wavelengths", "rgb"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, path + ": ")) << describe(r);
    EXPECT_TRUE(contains(r.err, "No such file or directory")) << describe(r);
    EXPECT_TRUE(folder_entries(folder).empty()) << describe(r);
}

TEST(CliSynthErrors, OutputIsAFolder) {
    const std::string folder = fresh_folder("output_dir");
    const ToolRun r = synth({"-o", folder, "--diffuse", "0.5", "--wavelengths", "rgb"});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, folder + ": ")) << describe(r);
    EXPECT_TRUE(folder_entries(folder).empty()) << describe(r);
    // No temporary file next to it either.
    const std::string parent = folder.substr(0, folder.find_last_of('/'));
    for (const std::string& name : folder_entries(parent)) {
        const std::string base = folder.substr(folder.find_last_of('/') + 1);
        EXPECT_FALSE(name != base && name.rfind(base, 0) == 0) << "left behind: " << parent << "/" << name;
    }
}

// ---- Help ----------------------------------------------------------------------------------

TEST(CliSynthHelp, HelpAndUsage) {
    ToolRun r = npf::testing::run_tool({"synth", "--help"});
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "usage: npf synth -o OUT.bsdf")) << describe(r);
    for (const char* flag : {"--recipe", "--conductor", "--alpha", "--wavelengths", "--anisotropy", "--phi", "--data"}) {
        EXPECT_TRUE(contains(r.out, flag)) << flag << "\n" << describe(r);
    }
    r = npf::testing::run_tool({"synth"});
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(contains(r.out, "usage: npf synth")) << describe(r);
}

}  // namespace
