// End-to-end test of `npf albedo`: the table (RGB, a few wavelengths, the Y/min/max summary of
// long spectra, azimuth rows for anisotropic files), the comparison with a reference (zero
// against itself, the exact ratio of two Lambertian recipes, RGB against an analytic recipe), the
// JSON output, and the errors (status 1, a message naming the culprit, nothing on stdout).
#include "cli_run.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace npf::testing;  // run_tool, describe, contains, ...

// The lines of the table proper: after the '#' comments, before the "worst" line.
std::vector<std::string> table_lines(const std::string& out) {
    std::vector<std::string> lines;
    for (const std::string& line : npf::testing::lines_of(out))
        if (!line.empty() && line[0] != '#' && line.rfind("worst", 0) != 0) lines.push_back(line);
    return lines;
}

// Count of non-overlapping occurrences of `part` in `text`.
std::size_t count_of(const std::string& text, const std::string& part) {
    std::size_t n = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++n;
    return n;
}

struct Files {
    std::string dir, iso_rgb, iso_spectral, aniso_rgb, lambert05, lambert04;
};

const Files& files() {
    static const Files f = [] {
        Files out;
        out.dir = npf::testing::temporary_folder("cli_albedo");
        npf::testing::SyntheticRglSpec spec;
        out.iso_rgb = npf::testing::write_synthetic_rgl(spec, out.dir + "/iso_rgb.bsdf");
        spec.spectral = true;
        out.iso_spectral = npf::testing::write_synthetic_rgl(spec, out.dir + "/iso_spectral.bsdf");
        spec.spectral = false;
        spec.phi_count = 6;
        out.aniso_rgb = npf::testing::write_synthetic_rgl(spec, out.dir + "/aniso_rgb.bsdf");
        out.lambert05 = out.dir + "/lambert05.yaml";
        out.lambert04 = out.dir + "/lambert04.yaml";
        npf::testing::write_text(out.lambert05, "name: white-ish lambertian\ndiffuse: 0.5\n");
        npf::testing::write_text(out.lambert04, "name: grey lambertian\ndiffuse: 0.4\n");
        return out;
    }();
    return f;
}

ToolRun albedo(std::vector<std::string> args) {
    args.insert(args.begin(), "albedo");
    return npf::testing::run_tool(args);
}

TEST(CliAlbedo, TableOfAnRgbMaterial) {
    const ToolRun r = albedo({files().iso_rgb, "--samples", "16"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(r.err, "") << describe(r);
    const std::vector<std::string> all = npf::testing::lines_of(r.out);
    ASSERT_GE(all.size(), 5u) << describe(r);
    EXPECT_EQ(all[1], "# material:  " + files().iso_rgb + " (rgl, isotropic)");
    EXPECT_EQ(all[2], "# channels:  R G B");
    EXPECT_TRUE(contains(all[3], "# estimator: 16 x 16 cells")) << describe(r);
    const std::vector<std::string> lines = table_lines(r.out);
    ASSERT_EQ(lines.size(), 13u) << describe(r);
    EXPECT_EQ(words_of(lines[0]), (std::vector<std::string>{"theta", "R", "G", "B"}));
    const char* thetas[] = {"0", "10", "20", "30", "40", "50", "60", "70", "80", "85", "87", "89"};
    for (std::size_t k = 1; k < lines.size(); ++k) {
        const std::vector<std::string> t = words_of(lines[k]);
        ASSERT_EQ(t.size(), 4u) << lines[k];
        EXPECT_EQ(t[0], thetas[k - 1]);
        for (std::size_t c = 1; c < 4; ++c) {
            const double v = std::strtod(t[c].c_str(), nullptr);
            EXPECT_GT(v, 0.01) << lines[k];
            EXPECT_LT(v, 1.0) << lines[k];
        }
    }
}

// The analytic diffuse term's albedo is its rho exactly: at three wavelengths, and summarised
// (Y, min, max) over the recipe's own 195.
TEST(CliAlbedo, LambertianRecipeShowsItsAlbedo) {
    ToolRun r = albedo({files().lambert05, "--wavelengths", "450,550,650", "--theta", "0,60,89", "--samples", "8"});
    ASSERT_EQ(r.status, 0) << describe(r);
    std::vector<std::string> lines = table_lines(r.out);
    ASSERT_EQ(lines.size(), 4u) << describe(r);
    EXPECT_EQ(words_of(lines[0]), (std::vector<std::string>{"theta", "450nm", "550nm", "650nm"}));
    EXPECT_EQ(words_of(lines[3]), (std::vector<std::string>{"89", "0.50000", "0.50000", "0.50000"}));

    r = albedo({files().lambert05, "--theta", "45", "--samples", "8"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "# channels:  195 wavelengths 360 .. 1000 nm")) << describe(r);
    lines = table_lines(r.out);
    ASSERT_EQ(lines.size(), 2u) << describe(r);
    EXPECT_EQ(words_of(lines[0]), (std::vector<std::string>{"theta", "Y", "min", "max"}));
    EXPECT_EQ(words_of(lines[1]), (std::vector<std::string>{"45", "0.50000", "0.50000", "0.50000"}));
}

TEST(CliAlbedo, MaterialAgainstItselfDiffersByZero) {
    const ToolRun r = albedo({files().iso_spectral, "--against", files().iso_spectral, "--samples", "12"});
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> lines = table_lines(r.out);
    ASSERT_EQ(lines.size(), 13u) << describe(r);
    EXPECT_EQ(words_of(lines[0]),
              (std::vector<std::string>{"theta", "400nm", "500nm", "600nm", "700nm", "|", "ref", "400nm", "ref",
                                        "500nm", "ref", "600nm", "ref", "700nm", "|", "diff", "400nm", "diff",
                                        "500nm", "diff", "600nm", "diff", "700nm"}));
    for (std::size_t k = 1; k < lines.size(); ++k) {
        const std::vector<std::string> t = words_of(lines[k]);
        ASSERT_EQ(t.size(), 15u) << lines[k];
        for (std::size_t c = 1; c <= 4; ++c) EXPECT_EQ(t[c], t[c + 5]) << lines[k];
        for (std::size_t c = 11; c < 15; ++c) EXPECT_EQ(t[c], "+0.00%") << lines[k];
    }
    EXPECT_TRUE(contains(r.out, "\nworst relative difference: +0.00% +- ")) << describe(r);

    const ToolRun j = albedo({files().iso_spectral, "--against", files().iso_spectral, "--samples", "12", "--json"});
    ASSERT_EQ(j.status, 0) << describe(j);
    EXPECT_EQ(count_of(j.out, ", [0, 0, 0, 0]]"), 12u) << describe(j);  // relative_difference, last per row
    EXPECT_TRUE(contains(j.out, "\"worst\": {\"relative_difference\": 0, ")) << describe(j);
}

// Two exact Lambertians: 0.5 against 0.4 is +25 % at every angle and channel.
TEST(CliAlbedo, TwoLambertiansDifferByTheirRatio) {
    const ToolRun r = albedo({files().lambert05, "--against", files().lambert04, "--wavelengths", "500,600",
                              "--theta", "0,89", "--samples", "8"});
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> lines = table_lines(r.out);
    ASSERT_EQ(lines.size(), 3u) << describe(r);
    EXPECT_EQ(words_of(lines[2]), (std::vector<std::string>{"89", "0.50000", "0.50000", "|", "0.40000", "0.40000", "|",
                                                          "+25.00%", "+25.00%"}));
    EXPECT_TRUE(contains(r.out, "worst relative difference: +25.00% +- 0.00% (")) << describe(r);

    const ToolRun j = albedo({files().lambert05, "--against", files().lambert04, "--wavelengths", "500,600",
                              "--theta", "0,89", "--samples", "8", "--json"});
    ASSERT_EQ(j.status, 0) << describe(j);
    const std::string key = "\"worst\": {\"relative_difference\": ";
    const std::size_t at = j.out.find(key);
    ASSERT_NE(at, std::string::npos) << describe(j);
    EXPECT_NEAR(std::strtod(j.out.c_str() + at + key.size(), nullptr), 0.25, 1e-6) << describe(j);
}

TEST(CliAlbedo, JsonHoldsOneArrayPerRow) {
    const ToolRun r = albedo({files().iso_rgb, "--theta", "0:80:5", "--samples", "8", "--json"});
    ASSERT_EQ(r.status, 0) << describe(r);
    ASSERT_EQ(npf::testing::lines_of(r.out).size(), 1u) << describe(r);
    EXPECT_EQ(r.out.front(), '{');
    EXPECT_TRUE(contains(r.out, "{\"material\": \"" + files().iso_rgb + "\", \"channels\": [\"R\", \"G\", \"B\"], "
                                "\"samples\": 8, \"columns\": [\"theta_deg\", \"phi_deg\", \"albedo\", \"albedo_se\"], "
                                "\"rows\": [[0, 0, ["))
        << describe(r);
    for (const char* theta : {"[20, 0, [", "[40, 0, [", "[60, 0, [", "[80, 0, ["}) EXPECT_TRUE(contains(r.out, theta)) << theta;
    EXPECT_EQ(count_of(r.out, ", 0, ["), 5u) << describe(r);
    EXPECT_FALSE(contains(r.out, "worst")) << describe(r);
    EXPECT_TRUE(r.out.size() > 3 && r.out.compare(r.out.size() - 4, 4, "]]}\n") == 0) << describe(r);
}

TEST(CliAlbedo, AnisotropicMaterialsGetAzimuthRows) {
    ToolRun r = albedo({files().aniso_rgb, "--theta", "30,70", "--samples", "8"});
    ASSERT_EQ(r.status, 0) << describe(r);
    std::vector<std::string> lines = table_lines(r.out);
    ASSERT_EQ(lines.size(), 9u) << describe(r);
    EXPECT_EQ(words_of(lines[0]), (std::vector<std::string>{"theta", "phi", "R", "G", "B"}));
    const char* phis[] = {"0", "90", "180", "270"};
    for (std::size_t k = 1; k < lines.size(); ++k) {
        EXPECT_EQ(words_of(lines[k])[0], k <= 4 ? "30" : "70") << lines[k];
        EXPECT_EQ(words_of(lines[k])[1], phis[(k - 1) % 4]) << lines[k];
    }

    r = albedo({files().aniso_rgb, "--theta", "60", "--azimuths", "2", "--samples", "8"});
    ASSERT_EQ(r.status, 0) << describe(r);
    lines = table_lines(r.out);
    ASSERT_EQ(lines.size(), 3u) << describe(r);
    EXPECT_EQ(words_of(lines[2])[1], "180");

    // An isotropic material compared with an anisotropic one gets the azimuths too.
    r = albedo({files().iso_rgb, "--against", files().aniso_rgb, "--theta", "60", "--samples", "8"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_EQ(table_lines(r.out).size(), 5u) << describe(r);
    EXPECT_TRUE(contains(r.out, ") at theta 60, phi ")) << describe(r);
}

// An analytic recipe computes any channel: an RGB material is compared with it in RGB.
TEST(CliAlbedo, RgbMaterialAgainstAnalyticRecipeComparesInRgb) {
    const ToolRun r = albedo({files().iso_rgb, "--against", files().lambert05, "--theta", "40", "--samples", "8"});
    ASSERT_EQ(r.status, 0) << describe(r);
    EXPECT_TRUE(contains(r.out, "# channels:  R G B\n")) << describe(r);
    const std::vector<std::string> lines = table_lines(r.out);
    ASSERT_EQ(lines.size(), 2u) << describe(r);
    EXPECT_EQ(words_of(lines[1])[5], "0.50008");  // the RGB of a constant 0.5 spectrum (D65 white, see spectrum.h)
}

struct ErrorCase {
    std::vector<std::string> args;
    std::string message;
};

void expect_errors(const std::vector<ErrorCase>& cases) {
    for (const ErrorCase& c : cases) {
        const ToolRun r = albedo(c.args);
        EXPECT_EQ(r.status, 1) << describe(r);
        EXPECT_EQ(r.out, "") << describe(r);
        EXPECT_TRUE(contains(r.err, c.message)) << "expected '" << c.message << "'\n" << describe(r);
    }
}

TEST(CliAlbedo, BadThetaListsAreErrors) {
    const std::string m = files().iso_rgb;
    expect_errors({
        {{m, "--theta", "0,90"}, "npf albedo: error: --theta: 90 is outside [0, 90) degrees"},
        {{m, "--theta", "abc"}, "npf albedo: error: --theta: 'abc': 'abc' is not a number"},
        {{m, "--theta", "10,,20"}, "--theta: '10,,20': '' is not a number"},
        {{m, "--theta", "0:80:2.5"}, "--theta: '0:80:2.5': expected 'start:end:count'"},
    });
}

TEST(CliAlbedo, BadCountsAndFlagsAreErrors) {
    const std::string m = files().iso_rgb;
    expect_errors({
        {{m, "--samples", "1"}, "npf albedo: error: --samples: needs a whole number in [2, 4096], got '1'"},
        {{m, "--azimuths", "0"}, "--azimuths: needs a whole number in [1, 360], got '0'"},
        {{m, "--wavelengths", "-3"}, "--wavelengths"},
        {{m, "--bogus"}, "unknown option '--bogus' (see npf albedo --help)"},
    });
}

TEST(CliAlbedo, MissingFilesAndMismatchedChannelsAreErrors) {
    const Files& f = files();
    const std::string missing = f.dir + "/no_such_material.bsdf";
    expect_errors({
        {{missing}, "npf albedo: error: " + missing + ": "},
        {{f.iso_rgb, "--against", missing}, "npf albedo: error: " + missing + ": "},
        {{f.iso_rgb, "--wavelengths", "500"}, f.iso_rgb + ": holds RGB data; --wavelengths needs a spectral file"},
        {{f.iso_spectral, "--against", f.iso_rgb}, f.iso_spectral + ": cannot be compared with " + f.iso_rgb + ": "},
    });
}

TEST(CliAlbedo, UsageAndHelp) {
    const ToolRun none = albedo({});
    EXPECT_EQ(none.status, 2) << describe(none);
    EXPECT_TRUE(contains(none.out, "usage: npf albedo MATERIAL [--against REFERENCE]")) << describe(none);
    const ToolRun help = albedo({"--help"});
    EXPECT_EQ(help.status, 0) << describe(help);
    for (const char* flag : {"--against", "--theta", "--azimuths", "--samples", "--wavelengths", "--json"})
        EXPECT_TRUE(contains(help.out, std::string("\n  ") + flag + " ")) << flag << "\n" << help.out;
}

// A real measured material: a white paper reflects most of the light at every view angle.
TEST(CliAlbedo, RealMeasuredMaterial) {
    const std::string path = npf::testing::shared_data_file("rgl/paper_white_rgb.bsdf");
    if (path.empty()) GTEST_SKIP() << "rgl/paper_white_rgb.bsdf not found in the shared data folder";
    const ToolRun r = albedo({path, "--theta", "0,60,89", "--samples", "32"});
    ASSERT_EQ(r.status, 0) << describe(r);
    const std::vector<std::string> lines = table_lines(r.out);
    ASSERT_EQ(lines.size(), 4u) << describe(r);
    for (std::size_t k = 1; k < lines.size(); ++k) {
        for (std::size_t c = 1; c < 4; ++c) {
            const double v = std::strtod(words_of(lines[k])[c].c_str(), nullptr);
            EXPECT_GT(v, 0.7) << lines[k];
            EXPECT_LT(v, 1.05) << lines[k];
        }
    }
}

}  // namespace
