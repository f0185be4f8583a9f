// End-to-end tests of the `npf` command-line tool: the built binary is run through the shell
// on synthetic (and, when present, real) material files, and its exit status, standard output
// and standard error are checked. This file: the tool itself and `npf info`; `npf eval` in
// test_cli_eval.cpp.

#include "cli_materials.h"
#include "cli_run.h"
#include "synthetic_rgl.h"

#include <npf/materials/material_formats.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include <sys/stat.h>

namespace {

using namespace npf::testing;  // run_npf, cli_materials, describe, ...

TEST(CliSetup, ToolExists) {
    struct stat st;
    ASSERT_EQ(::stat(NPF_TOOL_PATH, &st), 0) << "npf binary not found at " << NPF_TOOL_PATH;
    const ToolRun r = run_npf({"--help"});
    EXPECT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "usage: npf <command>")) << describe(r);
    EXPECT_TRUE(contains(r.out, "info")) << describe(r);
    EXPECT_TRUE(contains(r.out, "eval")) << describe(r);
}

TEST(CliSetup, UnknownCommandAndNoArguments) {
    ToolRun r = run_npf({"frobnicate"});
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(contains(r.err, "unknown command 'frobnicate'")) << describe(r);
    r = run_npf({});
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(contains(r.err, "usage: npf")) << describe(r);
}

// ---- npf info -----------------------------------------------------------------------------

TEST(CliInfo, SyntheticSpectralAnisotropic) {
    const std::string path = cli_materials().spectral;
    const ToolRun r = run_npf({"info", path});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.err, "") << describe(r);
    struct stat st;
    ASSERT_EQ(::stat(path.c_str(), &st), 0);
    for (const std::string& line : {
             "file: " + path,
             std::string("format: RGL measured BRDF (tensor_file 1.0, .bsdf)"),
             std::string("description: cli spectral"),
             std::string("isotropic: no"),
             std::string("channels: spectral, 4 wavelengths, 400.0 to 700.0 nm"),
             std::string("wavelengths (nm): 400 500 600 700"),
             std::string("phi_i reduction: 2 (phi_i covers 2 pi / 2)"),
             std::string("theta_i: 6 values: 0 0.31416 0.62832 0.94248 1.2566 1.5708"),
             std::string("data grid: 5 x 6 x 4 x 16 x 16 (spectra)"),
             std::string("ndf grid: 32 x 32"),
             std::string("sigma grid: 32 x 32"),
             std::string("vndf grid: 5 x 6 x 32 x 32"),
             std::string("jacobian: 1 (data are the ratio to the VNDF pdf)"),
         }) {
        EXPECT_TRUE(has_line(r.out, line)) << "missing line '" << line << "'\n" << describe(r);
    }
    EXPECT_TRUE(contains(r.out, "size: " + std::to_string(st.st_size) + " bytes (")) << describe(r);
    EXPECT_TRUE(contains(r.out, "phi_i: 5 values: -3.1416 ")) << describe(r);
}

TEST(CliInfo, SyntheticIsotropicRgb) {
    const ToolRun r = run_npf({"info", cli_materials().rgb});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(has_line(r.out, "isotropic: yes")) << describe(r);
    EXPECT_TRUE(has_line(r.out, "channels: RGB (linear sRGB), 3 channels")) << describe(r);
    EXPECT_FALSE(contains(r.out, "phi_i reduction")) << describe(r);
    EXPECT_TRUE(has_line(r.out, "phi_i: 1 values: 0")) << describe(r);
    EXPECT_FALSE(contains(r.out, "wavelengths (nm)")) << describe(r);
}

TEST(CliInfo, SeveralFiles) {
    const ToolRun r = run_npf({"info", cli_materials().rgb, cli_materials().spectral, cli_materials().rgb_aniso});
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> lines = lines_of(r.out);
    int files = 0, blanks = 0;
    for (const std::string& l : lines) {
        files += l.rfind("file: ", 0) == 0;
        blanks += l.empty();
    }
    EXPECT_EQ(files, 3) << describe(r);
    EXPECT_EQ(blanks, 2) << describe(r);
    EXPECT_TRUE(has_line(r.out, "phi_i reduction: 1 (phi_i covers 2 pi / 1)")) << describe(r);
}

TEST(CliInfo, RealDatabaseFile) {
    const std::string path = npf::testing::shared_data_file("rgl/paper_white_rgb.bsdf");
    if (path.empty()) GTEST_SKIP() << "rgl/paper_white_rgb.bsdf not found in the shared data folder "
                                      "(set NPF_SHARED_DATA to the folder holding rgl/)";
    const ToolRun r = run_npf({"info", path});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.err, "") << describe(r);
    for (const char* line : {"format: RGL measured BRDF (tensor_file 1.0, .bsdf)", "isotropic: yes",
                             "channels: RGB (linear sRGB), 3 channels", "ndf grid: 2 x 128",
                             "sigma grid: 2 x 128", "vndf grid: 1 x 8 x 128 x 128",
                             "data grid: 1 x 8 x 3 x 32 x 32 (rgb)"}) {
        EXPECT_TRUE(has_line(r.out, line)) << "missing line '" << line << "'\n" << describe(r);
    }
    EXPECT_TRUE(contains(r.out, "\ntheta_i: 8 values: 0 ")) << describe(r);
    EXPECT_TRUE(contains(r.out, "\nvalid mask: 1014 of 8192 bits set")) << describe(r);
    EXPECT_TRUE(contains(r.out, "\njacobian: 1")) << describe(r);
}

TEST(CliInfo, Errors) {
    const std::string missing = cli_folder() + "/no_such_material.bsdf";
    ToolRun r = run_npf({"info", missing});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, "npf info: error: " + missing + ": cannot open")) << describe(r);

    const std::string broken = cli_folder() + "/broken_info.bsdf";
    std::vector<std::uint8_t> bytes = npf::testing::make_synthetic_rgl(SyntheticRglSpec()).serialize();
    bytes[12] = 2;  // version 2.0
    ASSERT_TRUE(npf::testing::write_text(broken, std::string(bytes.begin(), bytes.end())));
    r = run_npf({"info", cli_materials().rgb, broken});
    EXPECT_EQ(r.status, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, broken + ": unsupported tensor_file version 2.0")) << describe(r);

    r = run_npf({"info"});
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(contains(r.out, "usage: npf info")) << describe(r);
    r = run_npf({"info", "--bogus", cli_materials().rgb});
    EXPECT_NE(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.err, "unknown option '--bogus'")) << describe(r);
}

// npf info --formats prints what the registry holds: every shipped format's documentation, the
// text docs/measured-readers.md carries (MaterialFormatDocs.*), and takes no FILE.
TEST(CliInfo, FormatsPrintsEachFormatsDocumentation) {
    ToolRun r = run_npf({"info", "--formats"});
    ASSERT_EQ(r.status, 0) << describe(r);
    // (A format a test registers in this process has no documentation, so it is not described.)
    EXPECT_EQ(r.out, npf::describe_material_formats());
    for (const npf::MaterialFormat& f : npf::shipped_material_formats())
        EXPECT_TRUE(contains(r.out, "## " + f.title + "\n")) << f.title;
    r = run_npf({"info", "--formats", cli_materials().rgb});
    EXPECT_EQ(r.status, 2) << describe(r);
    EXPECT_TRUE(contains(r.err, "no FILE with --formats")) << describe(r);
}

// ---- npf eval: output format --------------------------------------------------------------
}  // namespace
