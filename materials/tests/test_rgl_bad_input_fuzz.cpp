// Fuzz-lite for the RGL reader: random single-byte corruptions and truncations of a small
// valid file never crash; anything that fails is an npf::Error naming the source.

#include "rgl_bad_input.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/core/error.h>
#include <npf/materials/open_material.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/materials/tensor_file.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <sys/stat.h>

namespace {

using namespace npf::testing::rgl_bad_input;
using npf::RglBrdf, npf::testing::contains, npf::testing::SyntheticRglSpec;

// ---- Fuzz-lite ----------------------------------------------------------------------------

// Loads `bytes` in memory (the reader's path after the file read) and, if it loads, exercises
// eval, pdf and sample. Returns false if anything other than npf::Error escaped.
bool survives(const Bytes& bytes, const std::string& source, std::string& why) {
    try {
        npf::TensorFile tf = npf::TensorFile::parse(bytes, source);
        std::unique_ptr<RglBrdf> b = RglBrdf::from_tensor_file(tf);
        const npf::ChannelQuery q = b->native_query();
        std::vector<float> out(q.size());
        const npf::Vec3 dirs[] = {{0.f, 0.f, 1.f}, {0.6f, 0.f, 0.8f}, {0.f, -0.6f, 0.8f}, {-0.28f, 0.96f, 0.f},
                                  {0.48f, 0.6f, 0.64f}};
        for (const npf::Vec3& wi : dirs) {
            for (const npf::Vec3& wo : dirs) {
                b->eval_cos(wi, wo, q, out.data());
                (void)b->pdf(wi, wo);
                npf::BrdfSample s;
                (void)b->sample(wi, {0.3f, 0.7f}, q, s, out.data());
            }
        }
    } catch (const npf::Error& e) {
        if (!contains(e.what(), source)) {
            why = std::string("error message does not name the source: ") + e.what();
            return false;
        }
    } catch (const std::exception& e) {
        why = std::string("non-npf exception: ") + e.what();
        return false;
    } catch (...) {
        why = "unknown exception";
        return false;
    }
    return true;
}

SyntheticRglSpec tiny_spec() {
    SyntheticRglSpec s;
    s.theta_count = 2;
    s.ndf_size = 3;
    s.vndf_size = 3;
    s.data_size = 2;
    return s;
}

TEST(RglBadInputFuzz, RandomSingleByteCorruptionsNeverCrash) {
    const Bytes base = npf::testing::make_synthetic_rgl(tiny_spec()).serialize();
    std::string why;
    ASSERT_TRUE(survives(base, "fuzz-base", why)) << why;
    std::mt19937_64 rng(0x5eed1234u);
    int loaded = 0;
    // Half the corruptions hit the header and descriptors, where the structure lives.
    const std::size_t head = std::size_t(descriptors(base).back().extents_pos + 40);
    for (int i = 0; i < 2000; ++i) {
        Bytes b = base;
        const std::size_t pos = (i % 2 == 0) ? std::size_t(rng() % head) : std::size_t(rng() % b.size());
        const std::uint8_t old = b[pos];
        std::uint8_t value = std::uint8_t(rng());
        if (value == old) value = std::uint8_t(~old);
        b[pos] = value;
        const std::string source = "fuzz#" + std::to_string(i);
        ASSERT_TRUE(survives(b, source, why))
            << "byte " << pos << ": " << int(old) << " -> " << int(value) << ": " << why;
        try {
            RglBrdf::from_tensor_file(npf::TensorFile::parse(b, source));
            ++loaded;
        } catch (const npf::Error&) {
        }
    }
    // Corrupting floats in payloads mostly leaves a loadable file; structure bytes mostly not.
    EXPECT_GT(loaded, 100);
    EXPECT_LT(loaded, 2000);
}

TEST(RglBadInputFuzz, RandomTruncationsNeverCrash) {
    const Bytes base = npf::testing::make_synthetic_rgl(tiny_spec()).serialize();
    std::mt19937_64 rng(0xc0ffeeu);
    std::string why;
    const Descriptor last = descriptors(base).back();
    const std::size_t complete = std::size_t(last.offset + last.payload_bytes);
    for (int i = 0; i < 200; ++i) {
        const std::size_t n = std::size_t(rng() % base.size());  // strictly shorter than the file
        const Bytes b(base.begin(), base.begin() + long(n));
        const std::string source = "trunc#" + std::to_string(n);
        ASSERT_TRUE(survives(b, source, why)) << "length " << n << ": " << why;
        // A prefix that ends before the last payload is complete is missing something.
        if (n < complete) {
            EXPECT_THROW(RglBrdf::from_tensor_file(npf::TensorFile::parse(b, source)), npf::Error) << "length " << n;
        }
    }
    // A few through the file system and open_material as well.
    for (int i = 0; i < 10; ++i) {
        const std::size_t n = std::size_t(rng() % base.size());
        const std::string path = write_bytes("trunc_" + std::to_string(n) + ".bsdf", Bytes(base.begin(), base.begin() + long(n)));
        EXPECT_THROW(npf::open_material(path), npf::Error);
    }
}

}  // namespace
