// `npf eval --path` and `npf bench`: the two shading paths from the command line, and the
// benchmark's JSON keys and errors.

#include "npf_test_factors.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/fit/spectral_compression.h>
#include <npf/shading/npf_texture_file.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace {

using npf::testing::contains;
using npf::testing::describe;
using npf::testing::run_tool;
using npf::testing::ToolRun;

const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("cli-bench");
    return dir;
}

std::string spectral_texture() {
    const std::string path = folder() + "/spectral.exr";
    npf::write_npf_texture(npf::compress_factors(npf::testing::make_microfacet_factors(
                                                     {0.1, 0.3, 0.05, 1.0, 8, true, 16, 16, 16, 16, 16}),
                                                 npf::CompressionOptions()),
                           path);
    return path;
}

std::vector<double> numbers(const std::string& line) {
    std::istringstream is(line);
    std::vector<double> v;
    for (double x; is >> x;) v.push_back(x);
    return v;
}

TEST(CliEvalPath, BothPathsPrintTheSameValues) {
    const std::string path = spectral_texture();
    npf::testing::ToolRunOptions o;
    o.stdin_text = "0 0 1 0.3 0.1 0.9\n0.5 0.2 0.7 -0.4 -0.1 0.8\n";
    const ToolRun memory = run_tool({"eval", path, "--path", "memory", "--wavelengths", "450,555.5,610"}, o);
    const ToolRun texture = run_tool({"eval", path, "--path", "texture", "--wavelengths", "450,555.5,610"}, o);
    ASSERT_EQ(memory.status, 0) << describe(memory);
    ASSERT_EQ(texture.status, 0) << describe(texture);
    const std::vector<std::string> a = npf::testing::lines_of(memory.out), b = npf::testing::lines_of(texture.out);
    ASSERT_EQ(a.size(), 4u) << describe(memory);
    ASSERT_EQ(b.size(), 4u) << describe(texture);
    EXPECT_EQ(a[0], "# path memory");
    EXPECT_EQ(b[0], "# path texture (OpenImageIO TextureSystem)");
    for (std::size_t l = 2; l < 4; ++l) {
        const std::vector<double> x = numbers(a[l]), y = numbers(b[l]);
        ASSERT_EQ(x.size(), 3u);
        ASSERT_EQ(y.size(), 3u);
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_GT(x[k], 0.0);
            EXPECT_NEAR(y[k], x[k], 1e-5 * x[k]) << "line " << l;
        }
    }
    // --path is for NPF textures only, and takes one of two words.
    const ToolRun bad_word = run_tool({"eval", path, "--path", "gpu"}, o);
    EXPECT_EQ(bad_word.status, 1);
    EXPECT_TRUE(contains(bad_word.err, "expected 'memory' or 'texture'")) << describe(bad_word);
    const std::string rgl = npf::testing::write_synthetic_rgl({}, folder() + "/iso.bsdf");
    const ToolRun not_npf = run_tool({"eval", rgl, "--path", "texture"}, o);
    EXPECT_EQ(not_npf.status, 1);
    EXPECT_TRUE(contains(not_npf.err, "NPF factor textures (.exr) only")) << describe(not_npf);
}

TEST(CliBench, JsonHasTheDocumentedKeys) {
    const std::string path = spectral_texture();
    const ToolRun r = run_tool({"bench", path, "--json", "--seconds", "0.01", "--threads", "2"});
    ASSERT_EQ(r.status, 0) << describe(r);
    for (const char* key : {"\"eval_memory_ns\": ", "\"eval_texture_ns\": ", "\"sample_ns\": ", "\"eval_raw_ns\": null",
                            "\"eval_memory_full_ns\": ", "\"pdf_ns\": ", "\"threads\": 2"}) {
        EXPECT_TRUE(contains(r.out, key)) << key << "\n" << describe(r);
    }
    EXPECT_EQ(npf::testing::lines_of(r.out).size(), 1u) << "one JSON object on one line";
    // Each timing is a positive number.
    const std::size_t at = r.out.find("\"eval_memory_ns\": ");
    ASSERT_NE(at, std::string::npos);
    EXPECT_GT(std::atof(r.out.c_str() + at + 18), 0.0);

    // The material's path is a JSON string, quotes and backslashes escaped.
    const std::string odd = folder() + "/a \"quoted\" \\ name.exr";
    std::filesystem::copy_file(path, odd, std::filesystem::copy_options::overwrite_existing);
    const ToolRun q = run_tool({"bench", odd, "--json", "--seconds", "0.01", "--threads", "1"});
    ASSERT_EQ(q.status, 0) << describe(q);
    EXPECT_TRUE(contains(q.out, "a \\\"quoted\\\" \\\\ name.exr\", ")) << describe(q);
}

TEST(CliBench, RejectsWhatItCannotTime) {
    const std::string rgl = npf::testing::write_synthetic_rgl({}, folder() + "/iso.bsdf");
    const ToolRun raw = run_tool({"bench", rgl});
    EXPECT_EQ(raw.status, 1);
    EXPECT_TRUE(contains(raw.err, "not an NPF factor texture")) << describe(raw);
    const ToolRun seconds = run_tool({"bench", spectral_texture(), "--seconds", "-1"});
    EXPECT_EQ(seconds.status, 1);
    EXPECT_TRUE(contains(seconds.err, "--seconds")) << describe(seconds);
    // An RGB source against a spectral texture is not the same material.
    const ToolRun mismatch = run_tool({"bench", spectral_texture(), "--against",
                                       std::string(NPF_SOURCE_DIR) + "/data/materials/ilm_l3_37_metallic_rgb.bsdf",
                                       "--seconds", "0.01"});
    EXPECT_EQ(mismatch.status, 1);
    EXPECT_TRUE(contains(mismatch.err, "not the same material")) << describe(mismatch);
}

}  // namespace
