// Readers allocate what a file holds, not what it claims (issue 17 item 4 and the small ones of
// item 7): sparse files that claim gigabytes, fields and tables above the documented caps,
// shapes of absurd rank, finite but absurd values, MERL files of the wrong size, overflowing
// direction components, images whose alpha could pass for blue.
#include "error_of.h"
#include "merl_writer.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/materials/merl_brdf.h>
#include <npf/materials/open_material.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/materials/tensor_file.h>
#include <npf/core/brdf.h>
#include <npf/core/error.h>
#include <npf/core/openexr_header.h>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <functional>
#include <optional>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace {

using npf::testing::error_of;

namespace fs = std::filesystem;
using npf::testing::ToolRun;

long peak_rss_kib() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_maxrss;
}

// Extends `path` to `bytes` without writing them (a sparse file: no disk used).
void extend_sparse(const std::string& path, std::uint64_t bytes) {
    ASSERT_EQ(::truncate(path.c_str(), off_t(bytes)), 0) << path;
}

void le(std::vector<std::uint8_t>& b, std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) b.push_back(std::uint8_t(v >> (8 * i)));
}

// A tensor_file with one f32 field of the given shape at byte 64 (its payload not written).
std::vector<std::uint8_t> one_field_header(const std::vector<std::uint64_t>& shape) {
    std::vector<std::uint8_t> b(npf::TensorFile::kMagic, npf::TensorFile::kMagic + 12);
    b.push_back(1);
    b.push_back(0);
    le(b, 1, 4);
    le(b, 4, 2);
    for (char c : std::string("data")) b.push_back(std::uint8_t(c));
    le(b, shape.size(), 2);
    b.push_back(std::uint8_t(npf::DType::F32));
    le(b, 64 + 8 * shape.size(), 8);
    for (std::uint64_t e : shape) le(b, e, 8);
    return b;
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

TEST(BoundedReaders, ASparseRglFileCostsWhatItsFieldsHoldNotWhatItsSizeClaims) {
    const std::string dir = npf::testing::temporary_folder("bounded-sparse");
    const std::string path = npf::testing::write_synthetic_rgl({}, dir + "/sparse.bsdf");
    const std::uint64_t real = fs::file_size(path);
    extend_sparse(path, std::uint64_t(6) << 30);  // 6 GiB claimed, a few KB on disk
    const long before = peak_rss_kib();
    const auto t0 = std::chrono::steady_clock::now();
    const auto brdf = npf::open_material(path);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(brdf->info().format, "rgl");
    // Reading the whole file (as before) costs 6 GiB of memory and tens of seconds.
    EXPECT_LT(peak_rss_kib() - before, 256 * 1024) << "KiB of peak memory for a file of " << real << " real bytes";
    EXPECT_LT(seconds, 5.0);
}

TEST(BoundedReaders, AFieldAboveTheCapIsRefusedBeforeAnyAllocation) {
    const std::string dir = npf::testing::temporary_folder("bounded-field");
    const std::string path = dir + "/claims.bsdf";
    write_bytes(path, one_field_header({std::uint64_t(1) << 31}));  // 8 GiB of f32
    extend_sparse(path, (std::uint64_t(8) << 30) + 4096);
    const long before = peak_rss_kib();
    const std::string e = error_of([&] { npf::open_material(path); });
    EXPECT_NE(e.find(path), std::string::npos) << e;
    EXPECT_NE(e.find("more than the 1024 MiB a field may hold"), std::string::npos) << e;
    EXPECT_LT(peak_rss_kib() - before, 64 * 1024);
}

TEST(BoundedReaders, AbsurdRankGivesAShortErrorLine) {
    const std::string dir = npf::testing::temporary_folder("bounded-rank");
    const std::string path = dir + "/rank.bsdf";
    write_bytes(path, one_field_header(std::vector<std::uint64_t>(65535, 1)));
    const std::string e = error_of([&] { npf::open_material(path); });
    EXPECT_NE(e.find("65535 dimensions"), std::string::npos) << e.substr(0, 300);
    EXPECT_LT(e.size(), 300u) << "a " << e.size() << "-byte error line";
    // A shape string names at most eight extents.
    npf::TensorField f;
    f.shape.assign(40, 7);
    EXPECT_EQ(f.shape_string(), "[7, 7, 7, 7, 7, 7, 7, 7, ... (40 dimensions)]");
}

TEST(BoundedReaders, FiniteButAbsurdValuesAreRefused) {
    using npf::testing::SyntheticField;
    std::vector<SyntheticField> fields = npf::testing::synthetic_rgl_fields({});
    SyntheticField* rgb = npf::testing::find_field(fields, "rgb");
    ASSERT_NE(rgb, nullptr);
    std::vector<float> v = rgb->floats();
    v[17] = 3e38f;
    rgb->set_floats(v);
    const std::string dir = npf::testing::temporary_folder("bounded-values");
    const std::string path = dir + "/huge.bsdf";
    npf::testing::to_writer(fields).write(path);
    const std::string e = error_of([&] { npf::open_material(path); });
    EXPECT_NE(e.find("field 'rgb' holds an out-of-range value (3e+38) at index 17"), std::string::npos) << e;
    // And through the tool: one line, exit 1, never a 'null' albedo with exit 0.
    const ToolRun r = npf::testing::run_tool({"albedo", path, "--json"});
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.err.find("out-of-range"), std::string::npos) << r.err;
}

TEST(BoundedReaders, MerlFilesOfTheWrongSizeSayWhatIsWrong) {
    const std::string dir = npf::testing::temporary_folder("bounded-merl");
    const std::string good = dir + "/good.binary";
    npf::testing::write_merl(good, 90, 90, 180, [](int, int, int, double rgb[3]) { rgb[0] = rgb[1] = rgb[2] = 0.1; });
    std::vector<std::uint8_t> bytes(fs::file_size(good));
    {
        std::ifstream in(good, std::ios::binary);
        in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    // Under names that do not say MERL: the standard header does.
    const std::string cut = dir + "/cut.dat", padded = dir + "/padded.dat";
    write_bytes(cut, std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 100000));
    std::vector<std::uint8_t> more = bytes;
    more.push_back(0);
    write_bytes(padded, more);
    EXPECT_NE(error_of([&] { npf::open_material(cut); }).find("truncated"), std::string::npos) << error_of([&] { npf::open_material(cut); });
    EXPECT_NE(error_of([&] { npf::open_material(padded); }).find("trailing data"), std::string::npos);
    // Any plausible header, not only MERL's standard one: a 2 x 3 x 4 table with a byte too many.
    const std::string small = dir + "/small.binary", small_padded = dir + "/small.dat";
    npf::testing::write_merl(small, 2, 3, 4, [](int, int, int, double rgb[3]) { rgb[0] = rgb[1] = rgb[2] = 0.1; });
    {
        std::ifstream in(small, std::ios::binary);
        std::vector<std::uint8_t> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        b.push_back(0);
        write_bytes(small_padded, b);
    }
    EXPECT_NE(error_of([&] { npf::open_material(small_padded); }).find("trailing data"), std::string::npos)
        << error_of([&] { npf::open_material(small_padded); });
    // A .binary whose header claims a table above the cap, in a sparse file of exactly that size.
    const std::string huge = dir + "/huge.binary";
    std::vector<std::uint8_t> header;
    le(header, 1000, 4);
    le(header, 1000, 4);
    le(header, 1000, 4);
    write_bytes(huge, header);
    extend_sparse(huge, 12 + std::uint64_t(1000) * 1000 * 1000 * 24);
    const long before = peak_rss_kib();
    const std::string e = error_of([&] { npf::open_material(huge); });
    EXPECT_NE(e.find("more than the 1024 MiB a MERL file may hold"), std::string::npos) << e;
    EXPECT_LT(peak_rss_kib() - before, 64 * 1024);
}

TEST(BoundedReaders, FactorTextureTablesAboveTheFormatCapsAreRefused) {
    // A small OpenEXR file whose part "D" claims an 8192 x 8192 D table: the reader stops at the
    // attributes, before it sizes or decompresses anything.
    const std::string dir = npf::testing::temporary_folder("bounded-exr");
    const std::string path = dir + "/claims.exr";
    OIIO::ImageSpec spec(4, 4, 1, OIIO::TypeFloat);
    spec.channelnames = {"D.u000"};
    spec.attribute("oiio:subimagename", "D");
    spec.attribute("npf:format_version", 1);
    spec.attribute("npf:channel_kind", "rgb");
    spec.attribute("npf:channel_count", 3);
    spec.attribute("npf:isotropic", 0);
    for (const char* a : {"npf:d_theta", "npf:d_phi"}) spec.attribute(a, 8192);
    for (const char* a : {"npf:f_theta", "npf:g_theta", "npf:g_phi"}) spec.attribute(a, 4);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec));
    std::vector<float> zeros(16, 0.f);
    ASSERT_TRUE(out->write_image(OIIO::TypeFloat, zeros.data()));
    ASSERT_TRUE(out->close());
    const std::string e = error_of([&] { npf::open_material(path); });
    EXPECT_NE(e.find("the D table has 67108864 cells, more than the format's 1048576"), std::string::npos) << e;
}

TEST(BoundedReaders, OpenExrAttributesMustHaveTheirTypesSize) {
    // OpenEXR reads a known type by its own size, whatever the header declares, and reads on
    // from there: a fuzzed factor texture whose chunkCount declared 260 bytes made it take the
    // next attribute from the wrong place and allocate 1.8 GB (fuzz/corpus/npf_exr/oom-*).
    const std::string dir = npf::testing::temporary_folder("bounded-exr-size");
    const std::string good = dir + "/good.exr";
    const ToolRun synth = npf::testing::run_tool({"convert", "configs/materials/red_plastic.yaml", "-o", good, "--preset",
                                                  "preview", "--no-predict"},
                                                 {std::nullopt, NPF_SOURCE_DIR});
    ASSERT_EQ(synth.status, 0) << synth.err;
    std::vector<std::uint8_t> bytes(fs::file_size(good));
    {
        std::ifstream in(good, std::ios::binary);
        in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    const std::string key("chunkCount\0int\0", 15);
    const auto at = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
    ASSERT_NE(at, bytes.end());
    at[15] = 4 + 0;  // keep the low byte, set the declared size to 260
    at[16] = 1;
    const std::string bad = dir + "/bad.exr";
    write_bytes(bad, bytes);
    const std::string e = error_of([&] { npf::open_material(bad); });
    EXPECT_NE(e.find("attribute 'chunkCount' of type int has 260 bytes, not 4"), std::string::npos) << e;
    // The walk over bytes in memory (the fuzz target's) says what the walk over the file says.
    const std::uint64_t cap = std::uint64_t(1) << 23;
    EXPECT_EQ(npf::openexr_header_problem(bytes.data(), bytes.size(), bytes.size(), cap),
              npf::openexr_header_problem(bad, cap));
    EXPECT_NE(npf::openexr_header_problem(bad, cap), "");
    EXPECT_EQ(npf::openexr_header_problem(good, cap), "");
    // A head that ends inside the headers of a longer file: refused, saying so.
    at[15] = 4;
    at[16] = 0;
    EXPECT_EQ(npf::openexr_header_problem(bytes.data(), bytes.size(), bytes.size(), cap), "");
    EXPECT_EQ(npf::openexr_header_problem(bytes.data(), 200, bytes.size(), cap), "OpenEXR headers longer than 200 bytes");
    // The committed fuzzing input itself.
    for (const auto& entry : fs::directory_iterator(std::string(NPF_SOURCE_DIR) + "/fuzz/corpus/npf_exr")) {
        if (entry.path().filename().string().rfind("oom-", 0) != 0) continue;
        const std::string problem = error_of([&] { npf::open_material(entry.path().string()); });
        EXPECT_NE(problem.find("OpenEXR"), std::string::npos) << entry.path() << ": " << problem;
    }
}

TEST(BoundedReaders, EvalTakesDirectionsOfAnyFiniteScale) {
    const std::string dir = npf::testing::temporary_folder("bounded-eval");
    const std::string material = npf::testing::write_synthetic_rgl({}, dir + "/m.bsdf");
    const std::string dirs = dir + "/dirs.txt";
    // The same pair three times: unit, huge and tiny components.
    ASSERT_TRUE(npf::testing::write_text(dirs, "0.3 0 1  -0.2 0.1 1\n3e307 0 1e308  -2e307 1e307 1e308\n"
                                               "3e-310 0 1e-309  -2e-310 1e-310 1e-309\n"));
    const ToolRun r = npf::testing::run_tool({"eval", material, "--dirs", dirs});
    ASSERT_EQ(r.status, 0) << r.err;
    std::vector<std::string> lines;
    std::string line;
    for (std::istringstream in(r.out); std::getline(in, line);) {
        if (!line.empty() && line[0] != '#') lines.push_back(line);
    }
    ASSERT_EQ(lines.size(), 3u) << r.out;
    EXPECT_GT(std::stod(lines[0]), 0.0) << r.out;  // a lit pair
    EXPECT_EQ(lines[1], lines[0]);
    EXPECT_EQ(lines[2], lines[0]);
}

TEST(BoundedReaders, CompareRefusesAnImageWithTwoColourChannelsAndAlpha) {
    const std::string dir = npf::testing::temporary_folder("bounded-rga");
    const std::string rga = dir + "/rga.exr", rgb = dir + "/rgb.exr";
    for (const std::string& p : {rga, rgb}) {
        OIIO::ImageSpec spec(8, 8, 3, OIIO::TypeFloat);
        if (p == rga) {
            spec.channelnames = {"R", "G", "A"};
            spec.alpha_channel = 2;
        }
        auto out = OIIO::ImageOutput::create(p);
        ASSERT_TRUE(out && out->open(p, spec));
        std::vector<float> px(8 * 8 * 3, 0.5f);
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data()));
        ASSERT_TRUE(out->close());
    }
    const ToolRun r = npf::testing::run_tool({"compare", rgb, rga});
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.err.find(rga), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("three colour channels"), std::string::npos) << r.err;
}

}  // namespace
