#include "rgl_bad_input.h"

#include "run_tool.h"

#include <npf/core/error.h>
#include <npf/materials/open_material.h>
#include <npf/materials/rgl_brdf.h>

#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>

namespace npf::testing::rgl_bad_input {

const std::string& folder() {
    static const std::string dir = temporary_folder("rgl-bad-input");
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

SyntheticRglSpec small_spec(bool spectral) {
    SyntheticRglSpec s;
    s.theta_count = 3;
    s.ndf_size = 8;
    s.vndf_size = 6;
    s.data_size = 4;
    s.spectral = spectral;
    return s;
}

SyntheticRglSpec small_aniso_spec(int reduction, bool spectral) {
    SyntheticRglSpec s = small_spec(spectral);
    s.phi_count = 5;
    s.reduction = reduction;
    s.alpha_x = 0.2f;
    s.alpha_y = 0.5f;
    return s;
}

Bytes small_file_bytes(bool spectral) { return make_synthetic_rgl(small_spec(spectral)).serialize(); }

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
        d.payload_bytes = n * npf::dtype_size(npf::DType(b[d.dtype_pos]));
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

// Both loaders reject `path` with a message naming it and containing `phrase`
// (`open_phrase` for open_material, when its format sniffing answers first).
void expect_rejected(const std::string& path, const std::string& phrase, const std::string& open_phrase) {
    const std::string a = error_of([&] { npf::RglBrdf::load(path); });
    EXPECT_TRUE(contains(a, path)) << "npf::RglBrdf::load message does not name the file: " << a;
    EXPECT_TRUE(contains(a, phrase)) << "npf::RglBrdf::load message lacks '" << phrase << "': " << a;
    const std::string b = error_of([&] { npf::open_material(path); });
    const std::string& want = open_phrase.empty() ? phrase : open_phrase;
    EXPECT_TRUE(contains(b, path)) << "open_material message does not name the file: " << b;
    EXPECT_TRUE(contains(b, want)) << "open_material message lacks '" << want << "': " << b;
}

void expect_rejected_bytes(const std::string& name, const Bytes& bytes, const std::string& phrase,
                           const std::string& open_phrase) {
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

}  // namespace npf::testing::rgl_bad_input
