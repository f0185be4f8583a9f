// The RGL reader against malformed, truncated and hostile files: every such file must be
// rejected by both RglBrdf::load and open_material with an npf::Error naming the file and the
// problem, never a crash or an out-of-bounds read. Valid synthetic files of every kind load
// and describe themselves correctly; a fuzz-lite pass corrupts a small valid file at random.

#include "synthetic_rgl.h"

#include <npf/materials/open_material.h>
#include <npf/materials/rgl_brdf.h>
#include <npf/materials/tensor_file.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <sys/stat.h>

namespace {

using npf::DType;
using npf::RglBrdf;
using npf::testing::find_field;
using npf::testing::remove_field;
using npf::testing::synthetic_rgl_fields;
using npf::testing::SyntheticField;
using npf::testing::SyntheticRglSpec;
using npf::testing::to_writer;
using Bytes = std::vector<std::uint8_t>;
using Fields = std::vector<SyntheticField>;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// ---- Helpers ------------------------------------------------------------------------------

// One folder per test process, removed at exit (kept if NPF_KEEP_TEST_FILES is set).
const std::string& folder() {
    static const std::string dir = npf::testing::temporary_folder("rgl-bad-input");
    return dir;
}

std::string write_bytes(const std::string& name, const Bytes& bytes) {
    const std::string path = folder() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    EXPECT_TRUE(out.good()) << "cannot write " << path;
    return path;
}

std::string write_fields(const std::string& name, const Fields& fields) {
    return write_bytes(name, to_writer(fields).serialize());
}

// Small files: a few kilobytes, so that the many variants below stay cheap.
SyntheticRglSpec small_spec(bool spectral = false) {
    SyntheticRglSpec s;
    s.theta_count = 3;
    s.ndf_size = 8;
    s.vndf_size = 6;
    s.data_size = 4;
    s.spectral = spectral;
    return s;
}

SyntheticRglSpec small_aniso_spec(int reduction, bool spectral = false) {
    SyntheticRglSpec s = small_spec(spectral);
    s.phi_count = 5;
    s.reduction = reduction;
    s.alpha_x = 0.2f;
    s.alpha_y = 0.5f;
    return s;
}

Bytes small_file_bytes(bool spectral = false) { return npf::testing::make_synthetic_rgl(small_spec(spectral)).serialize(); }

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

std::vector<Descriptor> descriptors(const Bytes& b) {
    std::vector<Descriptor> out;
    const std::uint32_t count = get_le<std::uint32_t>(b, 14);
    std::size_t pos = 18;
    for (std::uint32_t i = 0; i < count; ++i) {
        Descriptor d;
        d.start = pos;
        const std::uint16_t len = get_le<std::uint16_t>(b, pos);
        d.name.assign(reinterpret_cast<const char*>(b.data() + pos + 2), len);
        d.rank_pos = pos + 2 + len;
        d.rank = get_le<std::uint16_t>(b, d.rank_pos);
        d.dtype_pos = d.rank_pos + 2;
        d.offset_pos = d.dtype_pos + 1;
        d.offset = get_le<std::uint64_t>(b, d.offset_pos);
        d.extents_pos = d.offset_pos + 8;
        std::uint64_t n = 1;
        for (std::uint16_t k = 0; k < d.rank; ++k) n *= get_le<std::uint64_t>(b, d.extents_pos + 8 * k);
        d.payload_bytes = n * npf::dtype_size(DType(b[d.dtype_pos]));
        pos = d.extents_pos + 8 * std::size_t(d.rank);
        out.push_back(d);
    }
    return out;
}

const Descriptor& descriptor(const std::vector<Descriptor>& ds, const std::string& name) {
    for (const Descriptor& d : ds) {
        if (d.name == name) return d;
    }
    throw std::logic_error("no descriptor " + name);
}

// Runs `load` and returns what() of the npf::Error it throws; records a failure for no
// exception or any other exception type.
std::string error_of(const std::function<void()>& load) {
    try {
        load();
    } catch (const npf::Error& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "threw a non-npf exception: " << e.what();
        return "<wrong exception type>";
    } catch (...) {
        ADD_FAILURE() << "threw something that is not a std::exception";
        return "<unknown exception>";
    }
    ADD_FAILURE() << "loaded without an error";
    return "<no error>";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Both loaders reject `path` with a message naming it and containing `phrase`
// (`open_phrase` for open_material, when its format sniffing answers first).
void expect_rejected(const std::string& path, const std::string& phrase, const std::string& open_phrase = "") {
    const std::string a = error_of([&] { RglBrdf::load(path); });
    EXPECT_TRUE(contains(a, path)) << "RglBrdf::load message does not name the file: " << a;
    EXPECT_TRUE(contains(a, phrase)) << "RglBrdf::load message lacks '" << phrase << "': " << a;
    const std::string b = error_of([&] { npf::open_material(path); });
    const std::string& want = open_phrase.empty() ? phrase : open_phrase;
    EXPECT_TRUE(contains(b, path)) << "open_material message does not name the file: " << b;
    EXPECT_TRUE(contains(b, want)) << "open_material message lacks '" << want << "': " << b;
}

void expect_rejected_bytes(const std::string& name, const Bytes& bytes, const std::string& phrase,
                           const std::string& open_phrase = "") {
    SCOPED_TRACE(name);
    expect_rejected(write_bytes(name, bytes), phrase, open_phrase);
}

void expect_rejected_fields(const std::string& name, const Fields& fields, const std::string& phrase) {
    SCOPED_TRACE(name);
    expect_rejected(write_fields(name, fields), phrase);
}

std::uint64_t file_size(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    return std::uint64_t(in.tellg());
}

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

// ---- Required fields, dtypes and shapes ---------------------------------------------------

TEST(RglBadInputFields, MissingRequiredField) {
    for (const char* name : {"phi_i", "theta_i", "ndf", "sigma", "vndf", "luminance"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        ASSERT_TRUE(remove_field(f, name));
        expect_rejected_fields(std::string("missing_") + name + ".bsdf", f,
                               std::string("missing required field '") + name + "'");
    }
}

TEST(RglBadInputFields, MissingRgbAndSpectra) {
    Fields f = synthetic_rgl_fields(small_spec());
    ASSERT_TRUE(remove_field(f, "rgb"));
    expect_rejected_fields("missing_data.bsdf", f, "missing required field 'rgb' or 'spectra'");
    f = synthetic_rgl_fields(small_spec(true));
    ASSERT_TRUE(remove_field(f, "spectra"));
    expect_rejected_fields("missing_spectra.bsdf", f, "missing required field 'rgb' or 'spectra'");
}

TEST(RglBadInputFields, SpectraWithoutWavelengths) {
    Fields f = synthetic_rgl_fields(small_spec(true));
    ASSERT_TRUE(remove_field(f, "wavelengths"));
    expect_rejected_fields("no_wavelengths.bsdf", f, "missing required field 'wavelengths'");
}

TEST(RglBadInputFields, WrongDtype) {
    {  // f64 ndf with the right values and shape.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& ndf = *find_field(f, "ndf");
        std::vector<double> d;
        for (float v : ndf.floats()) d.push_back(v);
        ndf.dtype = DType::F64;
        ndf.bytes.resize(d.size() * 8);
        std::memcpy(ndf.bytes.data(), d.data(), ndf.bytes.size());
        expect_rejected_fields("ndf_f64.bsdf", f, "field 'ndf' has dtype f64, expected f32");
    }
    {  // f16 theta_i: two bytes per element.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& theta = *find_field(f, "theta_i");
        theta.dtype = DType::F16;
        theta.bytes.resize(theta.bytes.size() / 2);
        expect_rejected_fields("theta_f16.bsdf", f, "field 'theta_i' has dtype f16, expected f32");
    }
    {  // u8 luminance.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& lum = *find_field(f, "luminance");
        lum.dtype = DType::U8;
        lum.bytes.resize(lum.bytes.size() / 4, 1);
        expect_rejected_fields("luminance_u8.bsdf", f, "field 'luminance' has dtype u8, expected f32");
    }
    {  // f32 jacobian.
        Fields f = synthetic_rgl_fields(small_spec());
        find_field(f, "jacobian")->set_floats({1.f});
        expect_rejected_fields("jacobian_f32.bsdf", f, "field 'jacobian' has dtype f32, expected u8");
    }
    {  // f32 description.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& d = *find_field(f, "description");
        d.shape = {2};
        d.set_floats({1.f, 2.f});
        expect_rejected_fields("description_f32.bsdf", f, "field 'description' must be u8 text");
    }
}

TEST(RglBadInputFields, WrongRank) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticField& ndf = *find_field(f, "ndf");
    ndf.shape.insert(ndf.shape.begin(), 1);
    expect_rejected_fields("ndf_rank3.bsdf", f, "field 'ndf' has shape [1, 2, 8], expected 2 dimensions");
    f = synthetic_rgl_fields(small_spec());
    SyntheticField& vndf = *find_field(f, "vndf");
    vndf.shape = {vndf.shape[1], vndf.shape[2], vndf.shape[3]};
    expect_rejected_fields("vndf_rank3.bsdf", f, "field 'vndf' has shape [3, 6, 6], expected 4 dimensions");
    f = synthetic_rgl_fields(small_spec());
    SyntheticField& theta = *find_field(f, "theta_i");
    theta.shape = {1, theta.shape[0]};
    expect_rejected_fields("theta_rank2.bsdf", f, "field 'theta_i' has shape [1, 3], expected 1 dimensions");
}

TEST(RglBadInputFields, JacobianNotOneByte) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticField& j = *find_field(f, "jacobian");
    j.shape = {2};
    j.bytes = {1, 1};
    expect_rejected_fields("jacobian_2.bsdf", f, "field 'jacobian' must hold exactly one u8");
    j.shape = {0};
    j.bytes = {};
    expect_rejected_fields("jacobian_0.bsdf", f, "field 'jacobian' must hold exactly one u8");
}

// Drops the last theta_i slice of a [nP, nT, ...] field, so its leading dims disagree.
void drop_last_theta_slice(SyntheticField& f) {
    std::uint64_t per_slice = 4;
    for (std::size_t d = 2; d < f.shape.size(); ++d) per_slice *= f.shape[d];
    f.shape[1] -= 1;
    f.bytes.resize(std::size_t(f.bytes.size() - per_slice));
}

TEST(RglBadInputFields, LeadingDimensionsDisagree) {
    for (const char* name : {"vndf", "luminance", "rgb"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        drop_last_theta_slice(*find_field(f, name));
        expect_rejected_fields(std::string("leading_") + name + ".bsdf", f,
                               std::string("field '") + name + "' has shape [1, 2, ");
        expect_rejected_fields(std::string("leading2_") + name + ".bsdf", f,
                               "whose leading dimensions must be [phi_i, theta_i] = [1, 3]");
    }
    {  // The same bytes with the two leading dims swapped.
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& v = *find_field(f, "vndf");
        std::swap(v.shape[0], v.shape[1]);
        expect_rejected_fields("leading_swapped.bsdf", f, "field 'vndf' has shape [3, 1, 6, 6], whose leading");
    }
    {  // Spectral data.
        Fields f = synthetic_rgl_fields(small_spec(true));
        drop_last_theta_slice(*find_field(f, "spectra"));
        expect_rejected_fields("leading_spectra.bsdf", f, "field 'spectra' has shape [1, 2, 4, 4, 4], whose leading");
    }
}

TEST(RglBadInputFields, LuminanceGridDiffersFromData) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticRglSpec other = small_spec();
    other.data_size = 5;
    Fields g = synthetic_rgl_fields(other);
    *find_field(f, "luminance") = *find_field(g, "luminance");
    expect_rejected_fields("luminance_grid.bsdf", f,
                           "field 'luminance' has shape [1, 3, 5, 5], whose inner dimensions must equal the "
                           "data grid of 'rgb' [1, 3, 3, 4, 4]");
}

TEST(RglBadInputFields, RgbThirdDimensionNotThree) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticField& rgb = *find_field(f, "rgb");
    std::vector<float> v = rgb.floats(), four;
    const std::size_t plane = 16;
    for (std::size_t s = 0; s < 3; ++s) {  // per theta slice: R G B plus a copy of B
        four.insert(four.end(), v.begin() + long(s * 3 * plane), v.begin() + long((s + 1) * 3 * plane));
        four.insert(four.end(), v.begin() + long((s * 3 + 2) * plane), v.begin() + long((s * 3 + 3) * plane));
    }
    rgb.shape[2] = 4;
    rgb.set_floats(four);
    expect_rejected_fields("rgb_4.bsdf", f, "field 'rgb' has shape [1, 3, 4, 4, 4]; its third dimension must be 3");
}

TEST(RglBadInputFields, NonSquareData) {
    Fields f = synthetic_rgl_fields(small_spec());
    SyntheticField& rgb = *find_field(f, "rgb");
    rgb.shape[3] = 8;
    rgb.shape[4] = 2;
    expect_rejected_fields("nonsquare.bsdf", f, "field 'rgb' data grid [1, 3, 3, 8, 2] is not square");
    f = synthetic_rgl_fields(small_spec(true));
    SyntheticField& sp = *find_field(f, "spectra");
    sp.shape[3] = 2;
    sp.shape[4] = 8;
    expect_rejected_fields("nonsquare_spectra.bsdf", f, "field 'spectra' data grid [1, 3, 4, 2, 8] is not square");
}

TEST(RglBadInputFields, SpectraDisagreeWithWavelengths) {
    Fields f = synthetic_rgl_fields(small_spec(true));
    SyntheticField& wl = *find_field(f, "wavelengths");
    wl.shape = {3};
    wl.set_floats({400.f, 550.f, 700.f});
    expect_rejected_fields("wavelengths_3.bsdf", f,
                           "field 'spectra' has shape [1, 3, 4, 4, 4] but there are 3 wavelengths");
    wl.shape = {5};
    wl.set_floats({400.f, 450.f, 550.f, 600.f, 700.f});
    expect_rejected_fields("wavelengths_5.bsdf", f, "but there are 5 wavelengths");
}

TEST(RglBadInputFields, TableDimensionOfOne) {
    SyntheticRglSpec s = small_spec();
    s.ndf_size = 1;
    expect_rejected_fields("ndf_1.bsdf", synthetic_rgl_fields(s),
                           "field 'ndf': table is 2 x 1; every table dimension must be at least 2");
    {  // one ndf row
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& ndf = *find_field(f, "ndf");
        ndf.shape[0] = 1;
        ndf.bytes.resize(ndf.bytes.size() / 2);
        expect_rejected_fields("ndf_row.bsdf", f, "field 'ndf': table is 1 x 8; every table dimension");
        SyntheticField& sigma = *find_field(f, "sigma");
        sigma.shape[0] = 1;
        sigma.bytes.resize(sigma.bytes.size() / 2);
        expect_rejected_fields("ndf_sigma_row.bsdf", f, "field 'ndf': table is 1 x 8");
        Fields fresh = synthetic_rgl_fields(small_spec());
        *find_field(f, "ndf") = *find_field(fresh, "ndf");
        expect_rejected_fields("sigma_row.bsdf", f, "field 'sigma': table is 1 x 8");
    }
    s = small_spec();
    s.vndf_size = 1;
    expect_rejected_fields("vndf_1.bsdf", synthetic_rgl_fields(s), "field 'vndf': table is 1 x 1");
    s = small_spec();
    s.data_size = 1;
    // The luminance table shares the data grid and is checked first.
    expect_rejected_fields("data_1.bsdf", synthetic_rgl_fields(s), "field 'luminance': table is 1 x 1");
    s.spectral = true;
    expect_rejected_fields("data_1_spectral.bsdf", synthetic_rgl_fields(s), "table is 1 x 1");
}

TEST(RglBadInputFields, EmptyGrids) {
    for (const char* name : {"phi_i", "theta_i"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& g = *find_field(f, name);
        g.shape = {0};
        g.bytes.clear();
        expect_rejected_fields(std::string("empty_") + name + ".bsdf", f, std::string("field '") + name + "' is empty");
    }
    Fields f = synthetic_rgl_fields(small_spec(true));
    SyntheticField& wl = *find_field(f, "wavelengths");
    wl.shape = {0};
    wl.bytes.clear();
    expect_rejected_fields("empty_wavelengths.bsdf", f, "field 'wavelengths' is empty");
}

// ---- Values -------------------------------------------------------------------------------

TEST(RglBadInputValues, NonFiniteValues) {
    struct Case {
        const char* field;
        bool spectral;
    };
    const Case cases[] = {{"ndf", false},       {"sigma", false},   {"vndf", false},        {"luminance", false},
                          {"rgb", false},       {"theta_i", false}, {"phi_i", false},       {"spectra", true},
                          {"wavelengths", true}, {"luminance", true}, {"vndf", true}};
    const float bad_values[] = {kNaN, kInf, -kInf};
    for (const Case& c : cases) {
        for (int which = 0; which < 3; ++which) {
            for (int where = 0; where < 2; ++where) {  // first element, then a middle one
                Fields f = synthetic_rgl_fields(small_spec(c.spectral));
                SyntheticField& field = *find_field(f, c.field);
                std::vector<float> v = field.floats();
                const std::size_t index = where == 0 ? 0 : v.size() / 2 + 1;
                if (index >= v.size()) continue;
                v[index] = bad_values[which];
                field.set_floats(v);
                const std::string name = std::string("nonfinite_") + c.field + (c.spectral ? "_spec_" : "_") +
                                         std::to_string(which) + "_" + std::to_string(index) + ".bsdf";
                const std::string path = write_fields(name, f);
                SCOPED_TRACE(name);
                expect_rejected(path, std::string("field '") + c.field + "'");
                expect_rejected(path, "non-finite value");
            }
        }
    }
}

TEST(RglBadInputValues, NegativeDensity) {
    for (const char* name : {"vndf", "luminance"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& field = *find_field(f, name);
        std::vector<float> v = field.floats();
        v[v.size() / 2] = -1e-3f;
        field.set_floats(v);
        expect_rejected_fields(std::string("negative_") + name + ".bsdf", f,
                               std::string("field '") + name + "': negative density");
    }
}

TEST(RglBadInputValues, NegativeNdfOrSigma) {
    // Unchecked by the reference readers, but a negative D or sigma would make eval_cos
    // negative after the channel clamp.
    for (const char* name : {"ndf", "sigma"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& field = *find_field(f, name);
        std::vector<float> v = field.floats();
        v[3] = -0.25f;
        field.set_floats(v);
        expect_rejected_fields(std::string("negative_") + name + ".bsdf", f,
                               std::string("field '") + name + "' holds a negative value");
    }
}

TEST(RglBadInputValues, AnisotropicGridMissesTheFoldedInterval) {
    // Right span, wrong place: folded queries have phi_i in [-pi, -pi + 2 pi / k].
    struct Case {
        int reduction;
        float shift;
    };
    for (const Case c : {Case{1, npf::kPi}, Case{2, npf::kPi}, Case{4, npf::kPi / 2}, Case{4, 0.3f}}) {
        Fields f = synthetic_rgl_fields(small_aniso_spec(c.reduction));
        SyntheticField& phi = *find_field(f, "phi_i");
        std::vector<float> v = phi.floats();
        for (float& x : v) x += c.shift;
        phi.set_floats(v);
        expect_rejected_fields("phi_shifted_k" + std::to_string(c.reduction) + ".bsdf", f,
                               "needs it to cover [-pi, ");
    }
}

TEST(RglBadInputValues, AllZeroSlice) {
    for (const char* name : {"luminance", "vndf"}) {
        Fields f = synthetic_rgl_fields(small_spec());
        SyntheticField& field = *find_field(f, name);
        std::vector<float> v = field.floats();
        const std::size_t plane = v.size() / 3;  // three theta slices
        std::fill(v.begin() + long(plane), v.begin() + long(2 * plane), 0.f);
        field.set_floats(v);
        expect_rejected_fields(std::string("zero_slice_") + name + ".bsdf", f,
                               std::string("field '") + name + "': slice 1 has zero total density");
    }
}

TEST(RglBadInputValues, PhiNotAscending) {
    {  // anisotropic: two entries swapped
        Fields f = synthetic_rgl_fields(small_aniso_spec(1));
        SyntheticField& phi = *find_field(f, "phi_i");
        std::vector<float> v = phi.floats();
        std::swap(v[1], v[2]);
        phi.set_floats(v);
        expect_rejected_fields("phi_swapped.bsdf", f, "field 'phi_i' is not strictly ascending at index 2");
        Fields fresh = synthetic_rgl_fields(small_aniso_spec(1));
        v = find_field(fresh, "phi_i")->floats();
        v[3] = v[2];
        phi.set_floats(v);
        expect_rejected_fields("phi_repeated.bsdf", f, "field 'phi_i' is not strictly ascending at index 3");
    }
    {  // two entries (isotropic by count), descending
        SyntheticRglSpec s = small_spec();
        s.phi_count = 2;
        Fields f = synthetic_rgl_fields(s);
        find_field(f, "phi_i")->set_floats({1.f, -1.f});
        expect_rejected_fields("phi_descending.bsdf", f, "field 'phi_i' is not strictly ascending at index 1");
    }
}

TEST(RglBadInputValues, ThetaNotAscending) {
    Fields f = synthetic_rgl_fields(small_spec());
    find_field(f, "theta_i")->set_floats({0.f, 1.f, 0.5f});
    expect_rejected_fields("theta_descending.bsdf", f, "field 'theta_i' is not strictly ascending at index 2");
}

TEST(RglBadInputValues, ThetaOutsideQuarterCircle) {
    Fields f = synthetic_rgl_fields(small_spec());
    find_field(f, "theta_i")->set_floats({0.f, 0.8f, 1.6f});
    expect_rejected_fields("theta_beyond.bsdf", f, "field 'theta_i' leaves [0, pi/2]");
    find_field(f, "theta_i")->set_floats({-0.1f, 0.8f, 1.5f});
    expect_rejected_fields("theta_negative.bsdf", f, "field 'theta_i' leaves [0, pi/2]");
    find_field(f, "theta_i")->set_floats({0.f, 2.f, 3.f});
    expect_rejected_fields("theta_far.bsdf", f, "field 'theta_i' leaves [0, pi/2]");
}

TEST(RglBadInputValues, AnisotropicSpanNotAFractionOfTheCircle) {
    for (int reduction : {3, 5, 8}) {
        expect_rejected_fields("span_k" + std::to_string(reduction) + ".bsdf",
                               synthetic_rgl_fields(small_aniso_spec(reduction)),
                               "only the full circle, a half or a quarter (reductions 1, 2, 4) are supported");
    }
    for (double factor : {0.9, 1.05, 2.0, 0.55}) {  // spans of 0.9, 1.05, 2 and 0.55 full circles
        Fields f = synthetic_rgl_fields(small_aniso_spec(1));
        SyntheticField& phi = *find_field(f, "phi_i");
        std::vector<float> v = phi.floats();
        for (float& x : v) x = float(double(x) * factor);
        phi.set_floats(v);
        expect_rejected_fields("span_factor_" + std::to_string(factor) + ".bsdf", f,
                               "field 'phi_i' spans ");
    }
}

TEST(RglBadInputValues, WavelengthsNotPositiveOrNotAscending) {
    Fields f = synthetic_rgl_fields(small_spec(true));
    find_field(f, "wavelengths")->set_floats({-100.f, 500.f, 600.f, 700.f});
    expect_rejected_fields("wavelengths_negative.bsdf", f, "field 'wavelengths' must be positive (nm)");
    find_field(f, "wavelengths")->set_floats({0.f, 500.f, 600.f, 700.f});
    expect_rejected_fields("wavelengths_zero.bsdf", f, "field 'wavelengths' must be positive (nm)");
    find_field(f, "wavelengths")->set_floats({400.f, 600.f, 500.f, 700.f});
    expect_rejected_fields("wavelengths_order.bsdf", f, "field 'wavelengths' is not strictly ascending at index 2");
}

// ---- Valid files of every kind ------------------------------------------------------------

struct ValidKind {
    const char* name;
    int phi_count;
    int reduction;
    bool spectral;
    bool jacobian;
};

const ValidKind kValidKinds[] = {
    {"iso_rgb", 1, 1, false, true},          {"iso2_rgb", 2, 1, false, true},
    {"iso_spectral", 1, 1, true, true},      {"aniso1_rgb", 5, 1, false, true},
    {"aniso2_rgb", 5, 2, false, true},       {"aniso4_rgb", 4, 4, false, true},
    {"aniso1_spectral", 5, 1, true, true},   {"aniso2_spectral", 3, 2, true, true},
    {"aniso4_spectral", 5, 4, true, true},   {"iso_rgb_jacobian0", 1, 1, false, false},
    {"aniso2_spectral_jacobian0", 5, 2, true, false},
};

TEST(RglBadInputValidFiles, EveryKindLoadsAndDescribesItself) {
    for (const ValidKind& k : kValidKinds) {
        SCOPED_TRACE(k.name);
        SyntheticRglSpec s = small_spec(k.spectral);
        s.phi_count = k.phi_count;
        s.reduction = k.reduction;
        s.jacobian = k.jacobian;
        s.alpha_x = 0.2f;
        s.alpha_y = 0.45f;
        s.wavelengths = {380.f, 455.5f, 600.f, 780.f, 830.f};
        s.description = std::string("valid ") + k.name;
        const std::string path = npf::testing::write_synthetic_rgl(s, folder() + "/valid_" + k.name + ".bsdf");
        const bool isotropic = k.phi_count <= 2;

        std::unique_ptr<RglBrdf> rgl;
        ASSERT_NO_THROW(rgl = RglBrdf::load(path));
        std::unique_ptr<npf::Brdf> any;
        ASSERT_NO_THROW(any = npf::open_material(path));
        EXPECT_EQ(rgl->reduction(), isotropic ? 1 : k.reduction);
        EXPECT_EQ(rgl->jacobian(), k.jacobian);
        EXPECT_EQ(rgl->phi_i().size(), std::size_t(k.phi_count));
        EXPECT_EQ(rgl->theta_i().size(), std::size_t(s.theta_count));
        for (const npf::BrdfInfo* info : {&rgl->info(), &any->info()}) {
            EXPECT_EQ(info->format, "rgl");
            EXPECT_EQ(info->path, path);
            EXPECT_EQ(info->description, s.description);
            EXPECT_EQ(info->isotropic, isotropic);
            EXPECT_EQ(info->file_bytes, file_size(path));
            EXPECT_EQ(info->channels.is_rgb(), !k.spectral);
            if (k.spectral) {
                EXPECT_EQ(info->channels.wavelengths(), s.wavelengths);
            } else {
                EXPECT_EQ(info->channels.size(), 3u);
            }
            bool found = false;
            for (const auto& [key, value] : info->details) {
                if (key != "phi_i reduction") continue;
                found = true;
                EXPECT_EQ(value, std::to_string(k.reduction) + " (phi_i covers 2 pi / " + std::to_string(k.reduction) + ")");
            }
            EXPECT_EQ(found, !isotropic) << "'phi_i reduction' detail is for anisotropic files only";
        }

        // Evaluation, pdf and sampling give finite, non-negative results over the hemisphere.
        const npf::ChannelQuery q = rgl->native_query();
        std::vector<float> out(q.size()), weight(q.size());
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> uni(0.f, 1.f);
        int positive = 0;
        for (int i = 0; i < 200; ++i) {
            const npf::Vec3 wi = npf::spherical_direction(0.5f * npf::kPi * uni(rng), 2.f * npf::kPi * uni(rng));
            const npf::Vec3 wo = npf::spherical_direction(0.5f * npf::kPi * uni(rng), 2.f * npf::kPi * uni(rng));
            rgl->eval_cos(wi, wo, q, out.data());
            for (float v : out) {
                ASSERT_TRUE(std::isfinite(v) && v >= 0.f) << v;
                positive += v > 0.f;
            }
            const float p = rgl->pdf(wi, wo);
            ASSERT_TRUE(std::isfinite(p) && p >= 0.f) << p;
            npf::BrdfSample smp;
            if (rgl->sample(wi, {uni(rng), uni(rng)}, q, smp, weight.data())) {
                ASSERT_GT(smp.wo.z, 0.f);
                ASSERT_TRUE(std::isfinite(smp.pdf) && smp.pdf > 0.f);
                for (float w : weight) ASSERT_TRUE(std::isfinite(w) && w >= 0.f);
            }
        }
        EXPECT_GT(positive, 100);
    }
}

TEST(RglBadInputValidFiles, OptionalFieldsAndUnknownFields) {
    Fields f = synthetic_rgl_fields(small_spec());
    ASSERT_TRUE(remove_field(f, "jacobian"));
    ASSERT_TRUE(remove_field(f, "description"));
    SyntheticField valid;
    valid.name = "valid";
    valid.dtype = DType::U8;
    valid.shape = {6};  // 1 * 3 * 4 * 4 nodes = 48 bits
    valid.bytes = {0xff, 0xff, 0x0f, 0xff, 0x00, 0x01};
    f.push_back(valid);
    SyntheticField unknown;
    unknown.name = "some_future_field";
    unknown.dtype = DType::I64;
    unknown.shape = {2, 1};
    unknown.bytes.assign(16, 0xab);
    f.insert(f.begin(), unknown);
    const std::string path = write_fields("optional.bsdf", f);
    std::unique_ptr<RglBrdf> b;
    ASSERT_NO_THROW(b = RglBrdf::load(path));
    EXPECT_TRUE(b->jacobian());
    EXPECT_EQ(b->info().description, "");
    bool saw_valid = false, saw_jacobian = false;
    for (const auto& [key, value] : b->info().details) {
        if (key == "valid mask") {
            saw_valid = true;
            EXPECT_EQ(value, "29 of 48 bits set (not used by evaluation)");
        }
        if (key == "jacobian") {
            saw_jacobian = true;
            EXPECT_TRUE(contains(value, "absent")) << value;
        }
    }
    EXPECT_TRUE(saw_valid);
    EXPECT_TRUE(saw_jacobian);
    EXPECT_NO_THROW(npf::open_material(path));
}

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
