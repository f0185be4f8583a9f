// Shared by the RGL bad-input tests (test_rgl_bad_*.cpp, test_rgl_valid_files.cpp): small
// synthetic files written to a per-process folder, the byte layout of a serialized file's
// descriptors (to damage one part of it), and the expectation that both loaders reject a file
// with an npf::Error that names it and the problem.
#pragma once

#include "synthetic_rgl.h"

#include <npf/materials/tensor_file.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace npf::testing::rgl_bad_input {

using Bytes = std::vector<std::uint8_t>;
using Fields = std::vector<SyntheticField>;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// One folder per test process, removed at exit (kept if NPF_KEEP_TEST_FILES is set).
const std::string& folder();
// Writes the bytes (the fields, serialized) to `name` in folder(); returns the path.
std::string write_bytes(const std::string& name, const Bytes& bytes);
std::string write_fields(const std::string& name, const Fields& fields);

// Small files: a few kilobytes, so that the many variants stay cheap.
SyntheticRglSpec small_spec(bool spectral = false);
SyntheticRglSpec small_aniso_spec(int reduction, bool spectral = false);
Bytes small_file_bytes(bool spectral = false);

template <typename T>
T get_le(const Bytes& b, std::size_t pos) {
    T v = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) v = T(v | (T(b.at(pos + i)) << (8 * i)));
    return v;
}

template <typename T>
void put_le(Bytes& b, std::size_t pos, T v) {
    for (std::size_t i = 0; i < sizeof(T); ++i) b.at(pos + i) = std::uint8_t(std::uint64_t(v) >> (8 * i));
}

// Where each part of a descriptor sits in a (valid) serialized file.
struct Descriptor {
    std::string name;
    std::size_t start = 0;        // the uint16 name length
    std::size_t rank_pos = 0;     // uint16 rank
    std::size_t dtype_pos = 0;    // uint8 dtype
    std::size_t offset_pos = 0;   // uint64 payload offset
    std::size_t extents_pos = 0;  // rank x uint64
    std::uint16_t rank = 0;
    std::uint64_t offset = 0;
    std::uint64_t payload_bytes = 0;
};

std::vector<Descriptor> descriptors(const Bytes& b);
const Descriptor& descriptor(const std::vector<Descriptor>& ds, const std::string& name);

// Runs `load` and returns what() of the npf::Error it throws; records a failure for no
// exception or any other exception type.
std::string error_of(const std::function<void()>& load);

// Both loaders reject `path` with a message naming it and containing `phrase`
// (`open_phrase` for open_material, when its format sniffing answers first).
void expect_rejected(const std::string& path, const std::string& phrase, const std::string& open_phrase = "");
void expect_rejected_bytes(const std::string& name, const Bytes& bytes, const std::string& phrase,
                           const std::string& open_phrase = "");
void expect_rejected_fields(const std::string& name, const Fields& fields, const std::string& phrase);

std::uint64_t file_size(const std::string& path);

}  // namespace npf::testing::rgl_bad_input
