// The MERL reader against missing, empty, truncated, oversized and non-finite files: an
// npf::Error that names the file and the problem.

#include "merl_geometry.h"
#include "merl_writer.h"

#include <npf/core/error.h>
#include <npf/materials/merl_brdf.h>

#include <chi2.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace npf::testing::merl;
using npf::MerlBrdf, npf::MerlLookup, npf::Vec3;

// ---- Bad input -------------------------------------------------------------------------

void expect_load_error(const std::string& path, const std::vector<std::string>& words) {
    try {
        MerlBrdf::load(path);
        ADD_FAILURE() << "no error for " << path;
    } catch (const npf::Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(path), std::string::npos) << what;
        for (const std::string& word : words)
            EXPECT_NE(what.find(word), std::string::npos) << "'" << word << "' not in: " << what;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not an npf::Error: " << e.what();
    }
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::uint8_t> header_bytes(std::int32_t a, std::int32_t b, std::int32_t c) {
    std::vector<std::uint8_t> bytes;
    for (std::int32_t v : {a, b, c}) {
        const auto u = static_cast<std::uint32_t>(v);
        for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(u >> (8 * i)));
    }
    return bytes;
}

TEST(MerlBrdf, MissingDirectoryEmpty) {
    expect_load_error(merl_file("does-not-exist.binary"), {"not found"});
    const std::string folder = merl_file("a-folder.binary");
    fs::create_directories(folder);
    expect_load_error(folder, {"directory"});
    const std::string empty = merl_file("empty.binary");
    write_bytes(empty, {});
    expect_load_error(empty, {"empty"});
}

TEST(MerlBrdf, TruncatedAndOversized) {
    const std::string good = merl_file("good.binary");
    npf::testing::write_merl(good, 2, 3, 4,
                    [](int, int, int, double rgb[3]) { rgb[0] = rgb[1] = rgb[2] = 1; });
    std::vector<std::uint8_t> bytes = read_bytes(good);
    ASSERT_EQ(bytes.size(), 12u + 2 * 3 * 4 * 3 * 8);
    EXPECT_NO_THROW(MerlBrdf::load(good));

    const std::string cut = merl_file("cut.binary");
    write_bytes(cut, std::vector<std::uint8_t>(bytes.begin(), bytes.end() - 5));
    expect_load_error(cut, {"truncated", "2 x 3 x 4"});

    const std::string short_header = merl_file("short-header.binary");
    write_bytes(short_header, std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 7));
    expect_load_error(short_header, {"truncated", "header"});

    const std::string longer = merl_file("longer.binary");
    bytes.push_back(0);
    write_bytes(longer, bytes);
    expect_load_error(longer, {"size mismatch"});
}

TEST(MerlBrdf, BadDimensions) {
    const std::string zero = merl_file("zero-dim.binary");
    write_bytes(zero, header_bytes(90, 0, 180));
    expect_load_error(zero, {"dimensions", "positive"});

    const std::string negative = merl_file("negative-dim.binary");
    std::vector<std::uint8_t> bytes = header_bytes(-1, -1, 1);
    bytes.resize(12 + 3 * 8, 0);  // (-1)(-1)(1) = 1 bin would match this size
    write_bytes(negative, bytes);
    expect_load_error(negative, {"dimensions", "positive"});

    const std::string huge = merl_file("huge-dim.binary");
    bytes = header_bytes(2147483647, 2147483647, 2147483647);
    bytes.resize(64, 0);
    write_bytes(huge, bytes);
    expect_load_error(huge, {"dimensions", "too large"});
}

TEST(MerlBrdf, NonFiniteValues) {
    const std::string nan_path = merl_file("nan.binary");
    npf::testing::write_merl(nan_path, 2, 3, 4, [](int ith, int itd, int ipd, double rgb[3]) {
        rgb[0] = rgb[1] = rgb[2] = 1.0;
        if (ith == 1 && itd == 2 && ipd == 3) rgb[1] = std::numeric_limits<double>::quiet_NaN();
    });
    expect_load_error(nan_path, {"non-finite", "channel G", "index 23"});

    const std::string inf_path = merl_file("inf.binary");
    npf::testing::write_merl(inf_path, 2, 3, 4, [](int ith, int itd, int ipd, double rgb[3]) {
        rgb[0] = rgb[1] = rgb[2] = 1.0;
        if (ith == 0 && itd == 1 && ipd == 0) rgb[2] = -std::numeric_limits<double>::infinity();
    });
    expect_load_error(inf_path, {"non-finite", "channel B", "index 4"});

    const std::string big_path = merl_file("big.binary");
    npf::testing::write_merl(big_path, 2, 3, 4, [](int ith, int, int, double rgb[3]) {
        rgb[0] = rgb[1] = rgb[2] = ith == 1 ? 1e300 : 1.0;
    });
    expect_load_error(big_path, {"out-of-range", "channel R"});
}

}  // namespace
