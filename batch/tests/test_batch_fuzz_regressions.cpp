// Regression tests for what fuzzing the readers found (fuzz/, docs/batch.md "Fuzzing"): each
// input that crashed, hung or exhausted memory, reduced to its cause.
#include "npf_test_factors.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/fit/spectral_compression.h>
#include <npf/core/error.h>
#include <npf/shading/npf_texture_file.h>

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <string>

namespace {

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << bytes;
}

// Found by npf_fuzz_npf_exr: a string attribute whose length field claims ~1.4 GB made OpenEXR
// 3.1 allocate and clear that much before noticing the file ends (3 s and 2 GB per file). The
// reader now walks the headers first and refuses such a file at once, with a message.
TEST(BatchFuzzRegression, NpfTextureAttributeLongerThanTheFile) {
    const std::string dir = npf::testing::temporary_folder("fuzz-regression");
    const std::string good = dir + "/good.exr", bad = dir + "/bad.exr";
    npf::testing::MicrofacetSpec spec;
    spec.d_theta = spec.f_theta = spec.g_theta = 8;
    npf::write_npf_texture(npf::compress_factors(npf::testing::make_microfacet_factors(spec), {}), good);
    std::string bytes = read_bytes(good);
    const std::string attribute = std::string("npf:channel_kind") + '\0' + "string" + '\0';
    const std::size_t at = bytes.find(attribute);
    ASSERT_NE(at, std::string::npos);
    const std::size_t length = at + attribute.size();
    for (const std::uint32_t claim : {0x55000003u, 0x7fffffffu, 0xffffffffu /* negative */}) {
        for (int i = 0; i < 4; ++i) bytes[length + std::size_t(i)] = char((claim >> (8 * i)) & 0xff);
        write_bytes(bad, bytes);
        const auto start = std::chrono::steady_clock::now();
        try {
            npf::read_npf_texture(bad);
            ADD_FAILURE() << "a header claiming " << claim << " bytes was accepted";
        } catch (const npf::Error& e) {
            EXPECT_NE(std::string(e.what()).find("npf:channel_kind"), std::string::npos) << e.what();
        }
        EXPECT_FALSE(npf::is_npf_texture(bad));
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
    }
    // The untouched file still reads.
    EXPECT_NO_THROW(npf::read_npf_texture(good));
    EXPECT_TRUE(npf::is_npf_texture(good));
}

}  // namespace

namespace {

// Found by npf_fuzz_npf_exr: a channel of pixel type 3 (OpenEXR knows 0, 1, 2 and passes others
// on) made OpenImageIO 2.4 abort the whole process on an assertion, so one damaged texture took
// down `npf info`, `npf render` and a whole `npf batch`. The reader now refuses the file first.
TEST(BatchFuzzRegression, NpfTextureChannelOfUnknownPixelType) {
    const std::string dir = npf::testing::temporary_folder("fuzz-regression-pixeltype");
    const std::string good = dir + "/good.exr", bad = dir + "/bad.exr";
    npf::testing::MicrofacetSpec spec;
    spec.d_theta = spec.f_theta = spec.g_theta = 8;
    npf::write_npf_texture(npf::compress_factors(npf::testing::make_microfacet_factors(spec), {}), good);
    std::string bytes = read_bytes(good);
    const std::string channel = std::string("D.u000") + '\0';
    const std::size_t at = bytes.find(channel);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(bytes[at + channel.size()], '\2');  // FLOAT
    bytes[at + channel.size()] = '\3';
    write_bytes(bad, bytes);
    try {
        npf::read_npf_texture(bad);
        ADD_FAILURE() << "a channel of pixel type 3 was accepted";
    } catch (const npf::Error& e) {
        EXPECT_NE(std::string(e.what()).find("unknown pixel type"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(npf::is_npf_texture(bad));
    // The tool reports it as any bad file: one line, status 1, no abort.
    const npf::testing::ToolRun info = npf::testing::run_tool({"info", bad});
    EXPECT_EQ(info.status, 1) << npf::testing::describe(info);
    EXPECT_NE(info.err.find("unknown pixel type"), std::string::npos) << npf::testing::describe(info);
}

}  // namespace
