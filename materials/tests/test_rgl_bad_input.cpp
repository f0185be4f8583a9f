// The RGL reader against malformed, truncated and hostile files: every such file must be
// rejected by both RglBrdf::load and open_material with an npf::Error naming the file and the
// problem, never a crash or an out-of-bounds read (support/rgl_bad_input.h). Here the
// container: magic, version, sizes, descriptors; the fields: test_rgl_bad_fields.cpp; the
// values: test_rgl_bad_values.cpp; valid files of every kind: test_rgl_valid_files.cpp;
// random corruptions: test_rgl_bad_input_fuzz.cpp.

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
using npf::RglBrdf, npf::testing::find_field, npf::testing::synthetic_rgl_fields;

// ---- Container: magic, version, sizes, descriptors ----------------------------------------

TEST(RglBadInputContainer, WrongMagic) {
    Bytes b = small_file_bytes();
    b[5] = 'X';  // "tensoX_file"
    expect_rejected_bytes("magic_letter.bsdf", b, "wrong magic", "unknown material format");
    b = small_file_bytes();
    b[11] = ' ';  // the NUL is part of the magic
    expect_rejected_bytes("magic_nul.bsdf", b, "wrong magic", "unknown material format");
    const std::string text = "this is not a material file at all\n";
    expect_rejected_bytes("text.bsdf", Bytes(text.begin(), text.end()), "wrong magic", "unknown material format");
    expect_rejected_bytes("short.bsdf", Bytes{'t', 'e', 'n'}, "wrong magic", "unknown material format");
}

TEST(RglBadInputContainer, WrongVersion) {
    for (auto [major, minor] : {std::pair<int, int>{2, 0}, {1, 1}, {0, 0}, {255, 255}}) {
        Bytes b = small_file_bytes();
        b[12] = std::uint8_t(major);
        b[13] = std::uint8_t(minor);
        const std::string v = std::to_string(major) + "." + std::to_string(minor);
        expect_rejected_bytes("version_" + v + ".bsdf", b, "unsupported tensor_file version " + v + " (expected 1.0)");
    }
}

TEST(RglBadInputContainer, EmptyFile) { expect_rejected_bytes("empty.bsdf", Bytes{}, "empty file"); }

TEST(RglBadInputContainer, TruncatedHeader) {
    const Bytes full = small_file_bytes();
    for (std::size_t n : {12, 13, 14, 17}) {
        expect_rejected_bytes("header_" + std::to_string(n) + ".bsdf", Bytes(full.begin(), full.begin() + long(n)),
                              "truncated header (" + std::to_string(n) + " bytes, need 18)");
    }
}

TEST(RglBadInputContainer, TruncatedMidDescriptor) {
    const Bytes full = small_file_bytes();
    const std::vector<Descriptor> ds = descriptors(full);
    const Descriptor& last = ds.back();
    // In the writers' layout every payload follows the descriptor block, so a cut inside the
    // block is reported at the first descriptor read: its payload lies past the end.
    for (std::size_t cut : {last.start + 1, last.start + 4, last.offset_pos + 3, last.extents_pos + 12}) {
        ASSERT_GE((cut - 18) / 13, ds.size());
        expect_rejected_bytes("descriptor_cut_" + std::to_string(cut) + ".bsdf",
                              Bytes(full.begin(), full.begin() + long(cut)),
                              "field '" + ds.front().name + "' payload (offset " + std::to_string(ds.front().offset) +
                                  ", " + std::to_string(ds.front().payload_bytes) +
                                  " bytes) extends past the end of the file (" + std::to_string(cut) + " bytes)");
    }
    // An early cut: the declared field count alone is more than the bytes can hold.
    expect_rejected_bytes("descriptor_cut_early.bsdf", Bytes(full.begin(), full.begin() + 40),
                          "declares " + std::to_string(ds.size()) + " fields, more than its size can hold");

    // Hand-made: field "a" (u8 [4]) reuses the first bytes of the file as its payload, so the
    // reader gets to the second descriptor, which the file cuts short.
    Bytes b(npf::TensorFile::kMagic, npf::TensorFile::kMagic + 12);
    b.push_back(1);  // version 1.0
    b.push_back(0);
    auto append = [&b](std::uint64_t v, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) b.push_back(std::uint8_t(v >> (8 * i)));
    };
    append(2, 4);                       // two fields
    append(1, 2);                       // "a"
    b.push_back('a');
    append(1, 2);                       // rank 1
    append(1, 1);                       // u8
    append(0, 8);                       // offset 0
    append(4, 8);                       // [4]
    ASSERT_EQ(b.size(), 40u);
    append(2, 2);                       // "bb"
    b.push_back('b');
    b.push_back('b');
    append(2, 2);                       // rank 2
    append(10, 1);                      // f32
    append(0, 8);                       // offset 0
    append(1, 8);                       // [1, 1]
    append(1, 8);
    ASSERT_EQ(b.size(), 71u);
    expect_rejected_bytes("handmade_complete.bsdf", b, "missing required field 'phi_i'");
    expect_rejected_bytes("handmade_cut_50.bsdf", Bytes(b.begin(), b.begin() + 50),
                          "truncated field descriptor #1 at byte 44");
    expect_rejected_bytes("handmade_cut_60.bsdf", Bytes(b.begin(), b.begin() + 60),
                          "truncated field descriptor #1 at byte 55");
    expect_rejected_bytes("handmade_cut_70.bsdf", Bytes(b.begin(), b.begin() + 70),
                          "truncated field descriptor #1 at byte 55");
}

TEST(RglBadInputContainer, TruncatedMidPayload) {
    const Bytes full = small_file_bytes();
    const std::vector<Descriptor> ds = descriptors(full);
    const Descriptor& last = ds.back();
    ASSERT_EQ(last.name, "rgb");
    std::size_t cut = std::size_t(last.offset + last.payload_bytes / 2);
    expect_rejected_bytes("payload_cut_last.bsdf", Bytes(full.begin(), full.begin() + long(cut)),
                          "field 'rgb' payload (offset " + std::to_string(last.offset));
    expect_rejected_bytes("payload_cut_last2.bsdf", Bytes(full.begin(), full.begin() + long(cut)),
                          "extends past the end of the file (" + std::to_string(cut) + " bytes)");
    // One byte short of the complete file.
    cut = std::size_t(last.offset + last.payload_bytes - 1);
    expect_rejected_bytes("payload_cut_one.bsdf", Bytes(full.begin(), full.begin() + long(cut)),
                          "field 'rgb' payload");
    // Cut right after the descriptor block: the first field's payload is missing.
    const Descriptor& vndf = descriptor(ds, "vndf");
    cut = std::size_t(vndf.offset + 8);
    expect_rejected_bytes("payload_cut_vndf.bsdf", Bytes(full.begin(), full.begin() + long(cut)),
                          "field 'vndf' payload");
    cut = std::size_t(ds.front().offset);
    expect_rejected_bytes("payload_cut_all.bsdf", Bytes(full.begin(), full.begin() + long(cut)),
                          "field '" + ds.front().name + "' payload");
}

TEST(RglBadInputContainer, OffsetPastEndOfFile) {
    const Bytes full = small_file_bytes();
    const Descriptor ndf = descriptor(descriptors(full), "ndf");
    for (std::uint64_t offset : {std::uint64_t(full.size()), std::uint64_t(full.size()) + 100,
                                 std::uint64_t(full.size()) - 4, std::numeric_limits<std::uint64_t>::max(),
                                 std::numeric_limits<std::uint64_t>::max() - 3}) {
        Bytes b = full;
        put_le<std::uint64_t>(b, ndf.offset_pos, offset);
        expect_rejected_bytes("offset_" + std::to_string(offset) + ".bsdf", b,
                              "field 'ndf' payload (offset " + std::to_string(offset) + ", " +
                                  std::to_string(ndf.payload_bytes) + " bytes) extends past the end of the file");
    }
}

TEST(RglBadInputContainer, ExtentPastEndOfFile) {
    const Bytes full = small_file_bytes();
    const Descriptor vndf = descriptor(descriptors(full), "vndf");
    Bytes b = full;
    put_le<std::uint64_t>(b, vndf.extents_pos, 1000);  // [1000, nT, V, V]
    expect_rejected_bytes("extent_vndf.bsdf", b, "field 'vndf' payload");
    expect_rejected_bytes("extent_vndf2.bsdf", b, "extends past the end of the file");
    b = full;
    const Descriptor desc = descriptor(descriptors(full), "description");
    put_le<std::uint64_t>(b, desc.extents_pos, full.size());  // u8 text as long as the file
    expect_rejected_bytes("extent_description.bsdf", b, "field 'description' payload");
}

TEST(RglBadInputContainer, ShapeProductOverflows) {
    const Bytes full = small_file_bytes();
    const std::vector<Descriptor> ds = descriptors(full);
    Bytes b = full;
    const Descriptor& ndf = descriptor(ds, "ndf");
    ASSERT_EQ(ndf.rank, 2);
    put_le<std::uint64_t>(b, ndf.extents_pos, std::uint64_t(1) << 33);
    put_le<std::uint64_t>(b, ndf.extents_pos + 8, std::uint64_t(1) << 33);
    expect_rejected_bytes("overflow_extents.bsdf", b,
                          "field 'ndf' has a shape [8589934592, 8589934592] whose size overflows");
    // The element count fits but the byte count (4 per f32) does not.
    b = full;
    const Descriptor& phi = descriptor(ds, "phi_i");
    put_le<std::uint64_t>(b, phi.extents_pos, std::uint64_t(1) << 62);
    expect_rejected_bytes("overflow_bytes.bsdf", b, "field 'phi_i' has a shape [4611686018427387904] whose size overflows");
    // 2^32 * 2^32 * 6 * 6 wraps to 0 mod 2^64 if multiplied carelessly.
    b = full;
    const Descriptor& vndf = descriptor(ds, "vndf");
    put_le<std::uint64_t>(b, vndf.extents_pos, std::uint64_t(1) << 32);
    put_le<std::uint64_t>(b, vndf.extents_pos + 8, std::uint64_t(1) << 32);
    expect_rejected_bytes("overflow_wrap.bsdf", b, "field 'vndf' has a shape [4294967296, 4294967296, ");
}

TEST(RglBadInputContainer, InvalidDtypeCode) {
    const Bytes full = small_file_bytes();
    const Descriptor sigma = descriptor(descriptors(full), "sigma");
    for (int code : {0, 12, 200, 255}) {
        Bytes b = full;
        b[sigma.dtype_pos] = std::uint8_t(code);
        expect_rejected_bytes("dtype_" + std::to_string(code) + ".bsdf", b,
                              "field 'sigma' has invalid dtype code " + std::to_string(code));
    }
}

TEST(RglBadInputContainer, DuplicateFieldNames) {
    Fields f = synthetic_rgl_fields(small_spec());
    f.push_back(*find_field(f, "ndf"));
    expect_rejected_fields("duplicate_ndf.bsdf", f, "duplicate field 'ndf'");
    // A byte-level rename: "sigma" becomes "phi_i" (same length), so 'phi_i' appears twice.
    Bytes b = small_file_bytes();
    const Descriptor sig = descriptor(descriptors(b), "sigma");
    std::memcpy(b.data() + sig.start + 2, "phi_i", 5);
    expect_rejected_bytes("duplicate_phi.bsdf", b, "duplicate field 'phi_i'");
}

TEST(RglBadInputContainer, HugeFieldCount) {
    for (std::uint32_t count : {0xffffffffu, 0x80000000u, 100000u, 1000u}) {
        Bytes b = small_file_bytes();
        put_le<std::uint32_t>(b, 14, count);
        expect_rejected_bytes("count_" + std::to_string(count) + ".bsdf", b,
                              "declares " + std::to_string(count) + " fields, more than its size can hold");
    }
}

TEST(RglBadInputContainer, ZeroFields) {
    Bytes b = small_file_bytes();
    put_le<std::uint32_t>(b, 14, 0);
    expect_rejected_bytes("count_0.bsdf", b, "missing required field 'phi_i'");
}

TEST(RglBadInputContainer, DirectoryInsteadOfFile) {
    const std::string dir = folder() + "/a_directory.bsdf";
    ASSERT_TRUE(::mkdir(dir.c_str(), 0755) == 0 || errno == EEXIST) << std::strerror(errno);
    expect_rejected(dir, "is a directory, not a file");
}

TEST(RglBadInputContainer, NonExistentPath) {
    expect_rejected(folder() + "/does_not_exist.bsdf", "cannot open: file not found");
    expect_rejected(folder() + "/no_such_folder/x.bsdf", "cannot open");
}

}  // namespace
