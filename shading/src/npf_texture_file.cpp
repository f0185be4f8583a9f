// The NPF factor texture reader. Every number taken from the file is checked before it sizes an
// allocation or indexes a table, so that a hostile or damaged file ends in an npf::Error naming
// it, never in a crash.
#include <npf/shading/npf_texture_file.h>
#include <npf/shading/npf_texture_layout.h>

#include "npf_texture_parts.h"

#include <npf/core/error.h>
#include <npf/core/float_environment.h>
#include <npf/core/input_file.h>
#include <npf/core/openexr_header.h>
#include <npf/core/text.h>

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace npf {

namespace {

namespace layout = npf_exr;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

// The most values one part may hold (512 MiB of floats), far above any real model, so that a
// hostile header cannot make us allocate without bound.
constexpr std::size_t kMaxPartValues = std::size_t(1) << 27;
// The largest part a factor texture has: the detail layer's 2^22 cells (NpfModel's caps), with
// room to spare; a header claiming more is refused before OpenEXR sizes anything by it.
constexpr std::uint64_t kMaxPartPixels = std::uint64_t(1) << 23;
constexpr int kMaxChannelCount = 1 << 16;

std::string quoted(const std::string& s) { return "'" + s + "'"; }

using Part = NpfTexturePart;
using PartSource = NpfTexturePartSource;

class Reader {
public:
    Reader(const std::string& path, std::unique_ptr<PartSource> source, std::uint64_t stored_bytes)
        : m_path(path), m_source(std::move(source)), m_stored_bytes(stored_bytes) {}

    NpfModel read() {
        m_parts = m_source->parts();
        check_expansion();
        const Part* d = find_part(layout::kPartD);
        if (!d) throw Error(m_path, "an OpenEXR file but not an NPF factor texture (it has no part \"D\")");
        read_attributes(d->spec);
        // What image tools leave of a factor texture when they keep the first part only (maketx
        // always; oiiotool with an operation but without -a): said as such, not as a missing G.
        if (m_parts.size() == 1) {
            throw Error(m_path, "holds only part \"D\" of an NPF factor texture (a single-part copy, as maketx makes): "
                                "shade the original or convert again (docs/farms.md)");
        }
        const std::size_t C = m_model.channel_count();

        // D and G: rank basis tables over their grids.
        auto read_basis = [&](const char* which, const char* prefix, int width, int height, SpectralBasis& s) {
            const Part& p = part(which);
            check_size(p, width, height);
            check_family(p, prefix, std::size_t(s.rank));
            s.cells = std::size_t(width) * std::size_t(height);
            s.basis.resize(std::size_t(s.rank) * s.cells);
            const std::vector<float> pixels = read_pixels(p);
            for (int k = 0; k < s.rank; ++k) {
                const std::string name = layout::indexed_channel(prefix, std::size_t(k), std::size_t(s.rank));
                extract(p, pixels, name, s.basis.data() + std::size_t(k) * s.cells, false);
            }
        };
        read_basis(layout::kPartD, layout::kDBasis, m_model.d_phi, m_model.d_theta, m_model.D);
        read_basis(layout::kPartG, layout::kGBasis, m_model.g_phi, m_model.g_theta, m_model.G);
        if (m_has_detail) {
            const DetailGrid& g = m_model.detail_grid;
            read_basis(layout::kPartDetail, layout::kRBasis, g.phi_d, g.theta_h * g.theta_d, m_model.detail);
        }

        // F: one row, one channel per stored channel.
        {
            const Part& p = part(layout::kPartF);
            check_size(p, m_model.f_theta, 1);
            check_family(p, layout::kFChannel, C);
            m_model.F.resize(C * std::size_t(m_model.f_theta));
            const std::vector<float> pixels = read_pixels(p);
            for (std::size_t c = 0; c < C; ++c) {
                extract(p, pixels, layout::indexed_channel(layout::kFChannel, c, C),
                        m_model.F.data() + c * std::size_t(m_model.f_theta), true);
            }
        }

        // The per-channel values: wavelengths, rho_d, rho_s and the weights of both bases.
        {
            const Part& p = part(layout::kPartSpectral);
            check_size(p, int(C), 1);
            check_family(p, layout::kDWeight, std::size_t(m_model.D.rank));
            check_family(p, layout::kGWeight, std::size_t(m_model.G.rank));
            const std::vector<float> pixels = read_pixels(p);
            std::vector<float> wavelengths(C);
            extract(p, pixels, layout::kWavelength, wavelengths.data(), false);
            m_model.rho_d.resize(C);
            m_model.rho_s.resize(C);
            extract(p, pixels, layout::kRhoD, m_model.rho_d.data(), true);
            extract(p, pixels, layout::kRhoS, m_model.rho_s.data(), true);
            read_weights(p, pixels, layout::kDWeight, m_model.D);
            read_weights(p, pixels, layout::kGWeight, m_model.G);
            if (m_has_detail) {
                check_family(p, layout::kRWeight, std::size_t(m_model.detail.rank));
                read_weights(p, pixels, layout::kRWeight, m_model.detail);
            }
            if (m_model.channels.is_rgb()) {
                for (std::size_t c = 0; c < C; ++c) {
                    if (wavelengths[c] != float(c)) {
                        throw Error(m_path, "an RGB file's wavelength channel must hold 0, 1, 2 (channel indices)");
                    }
                }
            } else {
                m_model.channels = Channels::spectral(wavelengths);
            }
        }
        m_model.validate(m_path);
        // Last, so that a value a tool made invalid is named as such first.
        check_tables_checksum(d->spec);
        return std::move(m_model);
    }

private:
    static std::string part_name(const Part& p) { return p.spec.get_string_attribute("oiio:subimagename"); }

    // What the parts will take in memory against what the file holds (npf_texture_parts.h).
    void check_expansion() const {
        if (m_stored_bytes == 0) return;
        std::uint64_t bytes = 0;
        for (const Part& p : m_parts) {
            bytes += std::uint64_t(std::max(p.spec.width, 0)) * std::uint64_t(std::max(p.spec.height, 0)) *
                     std::uint64_t(std::max(p.spec.depth, 1)) * std::uint64_t(std::max(p.spec.nchannels, 0)) * sizeof(float);
        }
        if (bytes > kMaxTableExpansion * m_stored_bytes + kTableExpansionAllowance) {
            char text[160];
            std::snprintf(text, sizeof text, "its tables would take %.1f MB in memory from a file of %.1f kB (%.0f times its size); "
                          "a factor texture may expand to %llu times its size plus %llu MiB: refused",
                          double(bytes) / 1e6, double(m_stored_bytes) / 1e3, double(bytes) / double(m_stored_bytes),
                          static_cast<unsigned long long>(kMaxTableExpansion), static_cast<unsigned long long>(kTableExpansionAllowance >> 20));
            throw Error(m_path, text);
        }
    }

    const Part* find_part(const char* name) const {
        for (const Part& p : m_parts) {
            if (part_name(p) == name) return &p;
        }
        return nullptr;
    }

    const Part& part(const char* name) const {
        const Part* p = find_part(name);
        if (!p) throw Error(m_path, "missing part " + quoted(name));
        return *p;
    }

    // ---- Attributes --------------------------------------------------------------------------

    const OIIO::ParamValue* attribute(const ImageSpec& spec, const char* name) const {
        const OIIO::ParamValue* p = spec.find_attribute(name, TypeDesc::UNKNOWN, /*casesensitive=*/true);
        if (!p) throw Error(m_path, std::string("missing attribute ") + name + " in part \"D\"");
        return p;
    }

    int int_attribute(const ImageSpec& spec, const char* name, int lo, int hi) const {
        const OIIO::ParamValue* p = attribute(spec, name);
        if (p->type() != OIIO::TypeInt) throw Error(m_path, std::string("attribute ") + name + " is not an int");
        const int v = p->get<int>();
        if (v < lo || v > hi) {
            throw Error(m_path, std::string("attribute ") + name + " = " + std::to_string(v) + " is outside " +
                                    std::to_string(lo) + ".." + std::to_string(hi));
        }
        return v;
    }

    double ratio_attribute(const ImageSpec& spec, const char* name) const {
        const OIIO::ParamValue* p = attribute(spec, name);
        double v;
        if (p->type() == OIIO::TypeDesc::DOUBLE) {
            v = p->get<double>();
        } else if (p->type() == OIIO::TypeFloat) {
            v = p->get<float>();
        } else {
            throw Error(m_path, std::string("attribute ") + name + " is not a number");
        }
        if (!(v >= 0.0 && v <= 1.0)) throw Error(m_path, std::string("attribute ") + name + " is outside [0, 1]");
        return v;
    }

    std::string string_attribute(const ImageSpec& spec, const std::string& name) const {
        const OIIO::ParamValue* p = spec.find_attribute(name, TypeDesc::UNKNOWN, /*casesensitive=*/true);
        if (!p) throw Error(m_path, "missing attribute " + name + " in part \"D\"");
        if (p->type() != OIIO::TypeString) throw Error(m_path, "attribute " + name + " is not a string");
        return p->get<OIIO::ustring>().string();
    }

    std::vector<double> numbers_attribute(const ImageSpec& spec, const char* name) const {
        const std::string text = string_attribute(spec, name);
        std::vector<double> v;
        const char* s = text.c_str();
        while (true) {
            while (*s == ' ') ++s;
            if (*s == '\0') break;
            char* end = nullptr;
            errno = 0;
            const double x = std::strtod(s, &end);
            if (end == s || (*end != ' ' && *end != '\0') || errno == ERANGE) {
                throw Error(m_path, std::string("attribute ") + name + " is not a list of numbers");
            }
            v.push_back(x);
            s = end;
        }
        return v;
    }

    void read_attributes(const ImageSpec& d) {
        const OIIO::ParamValue* version = d.find_attribute(layout::kAttrVersion, TypeDesc::UNKNOWN, true);
        if (!version || version->type() != OIIO::TypeInt) {
            throw Error(m_path, "an OpenEXR file but not an NPF factor texture (its part \"D\" has no integer "
                                "npf:format_version attribute)");
        }
        const int format_version = version->get<int>();
        if (format_version != layout::kFormatVersion && format_version != layout::kFormatVersionWithoutDetail) {
            throw Error(m_path, "unsupported npf:format_version " + std::to_string(format_version) +
                                    " (this build reads versions " + std::to_string(layout::kFormatVersionWithoutDetail) +
                                    " and " + std::to_string(layout::kFormatVersion) + ")");
        }
        m_has_detail = format_version >= 2;
        const std::string kind = string_attribute(d, layout::kAttrChannelKind);
        if (kind != "rgb" && kind != "spectral") {
            throw Error(m_path, "attribute npf:channel_kind is " + quoted(kind) + ", expected 'rgb' or 'spectral'");
        }
        const int C = int_attribute(d, layout::kAttrChannelCount, 1, kMaxChannelCount);
        if (kind == "rgb" && C != 3) {
            throw Error(m_path, "an RGB file must have 3 channels, npf:channel_count is " + std::to_string(C));
        }
        constexpr int kMaxGrid = 1 << 16;
        NpfModel& m = m_model;
        // Placeholder wavelengths until the spectral part is read; their count is what matters here.
        m.channels = kind == "rgb" ? Channels::rgb() : Channels::spectral(std::vector<float>(std::size_t(C), 1.f));
        m.rho_d.assign(std::size_t(C), 0.f);
        m.d_theta = int_attribute(d, layout::kAttrDTheta, 1, kMaxGrid);
        m.d_phi = int_attribute(d, layout::kAttrDPhi, 1, kMaxGrid);
        m.f_theta = int_attribute(d, layout::kAttrFTheta, 1, kMaxGrid);
        m.g_theta = int_attribute(d, layout::kAttrGTheta, 1, kMaxGrid);
        m.g_phi = int_attribute(d, layout::kAttrGPhi, 1, kMaxGrid);
        for (const auto& [name, cells] :
             {std::pair<const char*, std::size_t>{"D", std::size_t(m.d_theta) * std::size_t(m.d_phi)},
              {"G", std::size_t(m.g_theta) * std::size_t(m.g_phi)}}) {
            if (cells > NpfModel::kMaxTableCells) {
                throw Error(m_path, std::string("the ") + name + " table has " + std::to_string(cells) +
                                        " cells, more than the format's " + std::to_string(NpfModel::kMaxTableCells));
            }
        }
        const int isotropic = int_attribute(d, layout::kAttrIsotropic, 0, 1);
        if ((isotropic == 1) != m.isotropic()) {
            throw Error(m_path, "attribute npf:isotropic disagrees with the grid sizes (phi sizes " +
                                    std::to_string(m.d_phi) + " and " + std::to_string(m.g_phi) + ")");
        }
        auto read_basis_facts = [&](SpectralBasis& s, int theta, int phi, const char* rank_name, const char* ratio_name,
                                    const char* sigma_name) {
            s.cells = std::size_t(theta) * std::size_t(phi);
            const std::size_t max_rank = std::min(s.cells, std::size_t(C));
            s.rank = int_attribute(d, rank_name, 1, int(max_rank));
            // The format's caps (docs/format.md sec. 8), before anything is sized by the header.
            if (std::size_t(s.rank) * s.cells > NpfModel::kMaxBasisValues) {
                throw Error(m_path, std::string(rank_name) + " " + std::to_string(s.rank) + " over " +
                                        std::to_string(s.cells) + " cells is more than the format's " +
                                        std::to_string(NpfModel::kMaxBasisValues) + " basis values");
            }
            s.kept_ratio = ratio_attribute(d, ratio_name);
            s.singular_values = numbers_attribute(d, sigma_name);
            if (s.singular_values.size() != max_rank) {
                throw Error(m_path, std::string("attribute ") + sigma_name + " holds " +
                                        std::to_string(s.singular_values.size()) + " values, expected " +
                                        std::to_string(max_rank));
            }
        };
        read_basis_facts(m.D, m.d_theta, m.d_phi, layout::kAttrDRank, layout::kAttrDKeptRatio,
                         layout::kAttrDSingularValues);
        read_basis_facts(m.G, m.g_theta, m.g_phi, layout::kAttrGRank, layout::kAttrGKeptRatio,
                         layout::kAttrGSingularValues);
        if (m_has_detail) {
            DetailGrid& g = m.detail_grid;
            g.theta_h = int_attribute(d, layout::kAttrDetailThetaH, 1, kMaxGrid);
            g.theta_d = int_attribute(d, layout::kAttrDetailThetaD, 1, kMaxGrid);
            g.phi_d = int_attribute(d, layout::kAttrDetailPhiD, 1, kMaxGrid);
            // Checked before anything is sized by it.
            if (g.cells() > NpfModel::kMaxDetailCells) {
                throw Error(m_path, "the detail grid " + std::to_string(g.theta_h) + " x " + std::to_string(g.theta_d) +
                                        " x " + std::to_string(g.phi_d) + " has more than " +
                                        std::to_string(NpfModel::kMaxDetailCells) + " cells");
            }
            read_basis_facts(m.detail, g.theta_h * g.theta_d, g.phi_d, layout::kAttrDetailRank,
                             layout::kAttrDetailKeptRatio, layout::kAttrDetailSingularValues);
        }

        // Metadata: the key list gives the order; each key has its own string attribute.
        const OIIO::ParamValue* keys = d.find_attribute(layout::kAttrMetadataKeys, TypeDesc::UNKNOWN, true);
        if (keys) {
            const std::string list = string_attribute(d, layout::kAttrMetadataKeys);
            std::size_t begin = 0;
            while (begin <= list.size() && !list.empty()) {
                std::size_t end = list.find('\n', begin);
                if (end == std::string::npos) end = list.size();
                const std::string key = list.substr(begin, end - begin);
                const std::string name = std::string(layout::kMetadataPrefix) + key;
                if (!d.find_attribute(name, TypeDesc::UNKNOWN, true)) {
                    throw Error(m_path, "metadata key " + quoted(key) + " is listed in npf:metadata_keys but has no " +
                                            name + " attribute");
                }
                m.metadata.emplace_back(key, string_attribute(d, name));
                begin = end + 1;
            }
        }
    }

    // A file with a checksum must hold exactly the tables npf wrote: image tools keep the
    // attributes of what they copy but may change its pixels (oiiotool -d half or --compression
    // pxr24 round them, --colorconvert -a transforms them), and such a copy still passes every
    // other check. Files written before the checksum have none and are read as they are.
    void check_tables_checksum(const ImageSpec& d) const {
        if (!d.find_attribute(layout::kAttrTablesChecksum, TypeDesc::UNKNOWN, true)) return;
        if (string_attribute(d, layout::kAttrTablesChecksum) != tables_checksum(m_model)) {
            throw Error(m_path, "its tables do not match its npf:tables_checksum (an image tool changed its pixels: "
                                "oiiotool -d half, a lossy compression, --colorconvert, ...): shade the original or "
                                "convert again (docs/farms.md)");
        }
    }

    // ---- Pixels ------------------------------------------------------------------------------

    void check_size(const Part& p, int width, int height) const {
        const ImageSpec& s = p.spec;
        if (s.width != width || s.height != height || s.depth != 1) {
            throw Error(m_path, "part " + quoted(part_name(p)) + " is " + std::to_string(s.width) + " x " +
                                    std::to_string(s.height) + (s.depth != 1 ? " x " + std::to_string(s.depth) : "") +
                                    " pixels, the attributes call for " + std::to_string(width) + " x " +
                                    std::to_string(height));
        }
        if (std::size_t(s.width) * std::size_t(s.height) * std::size_t(std::max(s.nchannels, 1)) > kMaxPartValues) {
            throw Error(m_path, "part " + quoted(part_name(p)) + " is too large");
        }
    }

    // The part holds exactly `count` channels named prefix + index (the rank or channel count in
    // the attributes), each stored as float or half.
    void check_family(const Part& p, const char* prefix, std::size_t count) const {
        const ImageSpec& s = p.spec;
        std::size_t found = 0;
        const std::size_t prefix_length = std::strlen(prefix);
        for (const std::string& name : s.channelnames) {
            if (name.compare(0, prefix_length, prefix) == 0) ++found;
        }
        for (std::size_t k = 0; k < count; ++k) {
            const std::string name = layout::indexed_channel(prefix, k, count);
            if (s.channelindex(name) < 0) {
                throw Error(m_path, "part " + quoted(part_name(p)) + " lacks channel " + quoted(name));
            }
        }
        if (found != count) {
            throw Error(m_path, "part " + quoted(part_name(p)) + " has " + std::to_string(found) + " channels " + prefix +
                                    "*, the attributes call for " + std::to_string(count));
        }
    }

    std::vector<float> read_pixels(const Part& p) const {
        const ImageSpec& s = p.spec;
        // The writer stores the detail part as half when that is exact, every other part as float:
        // half elsewhere is an image tool's rounding (oiiotool -d half), caught here also in files
        // written before npf:tables_checksum.
        const bool half_written = part_name(p) == layout::kPartDetail;
        for (int c = 0; c < s.nchannels; ++c) {
            const TypeDesc t = s.channelformat(c);
            const std::string channel =
                "part " + quoted(part_name(p)) + " channel " + quoted(s.channelnames[std::size_t(c)]);
            if (t == OIIO::TypeHalf && !half_written) {
                throw Error(m_path, channel + " stores half pixels, npf writes it as float (an image tool rounded it: "
                                              "oiiotool -d half, ...): shade the original or convert again "
                                              "(docs/farms.md)");
            }
            if (t != OIIO::TypeFloat && t != OIIO::TypeHalf) {
                throw Error(m_path, channel + " stores " + t.c_str() + " pixels; NPF tables are float");
            }
        }
        std::vector<float> pixels(std::size_t(s.width) * std::size_t(s.height) * std::size_t(s.nchannels));
        bool ok = false;
        std::string why;
        try {
            ok = m_source->read(p, pixels.data(), why);
        } catch (const std::exception& e) {
            why = e.what();
        }
        if (!ok) {
            throw Error(m_path, "cannot read the pixels of part " + quoted(part_name(p)) +
                                    " (truncated or corrupt file): " + why);
        }
        return pixels;
    }

    // Copies one channel out of the interleaved pixels, checking its values.
    void extract(const Part& p, const std::vector<float>& pixels, const std::string& name, float* out,
                 bool non_negative) const {
        const ImageSpec& s = p.spec;
        const int index = s.channelindex(name);
        if (index < 0) throw Error(m_path, "part " + quoted(part_name(p)) + " lacks channel " + quoted(name));
        const std::size_t n = std::size_t(s.width) * std::size_t(s.height), stride = std::size_t(s.nchannels);
        for (std::size_t i = 0; i < n; ++i) {
            const float v = pixels[i * stride + std::size_t(index)];
            if (!std::isfinite(v) || (non_negative && v < 0.f)) {
                throw Error(m_path, std::string(std::isfinite(v) ? "negative" : "non-finite") + " value in part " +
                                        quoted(part_name(p)) + " channel " + quoted(name) + " at x " +
                                        std::to_string(i % std::size_t(s.width)) + ", y " +
                                        std::to_string(i / std::size_t(s.width)));
            }
            out[i] = v;
        }
    }

    void read_weights(const Part& p, const std::vector<float>& pixels, const char* prefix, SpectralBasis& s) const {
        const std::size_t C = m_model.channel_count(), rank = std::size_t(s.rank);
        s.weights.resize(C * rank);
        std::vector<float> column(C);
        for (std::size_t k = 0; k < rank; ++k) {
            extract(p, pixels, layout::indexed_channel(prefix, k, rank), column.data(), false);
            for (std::size_t c = 0; c < C; ++c) s.weights[c * rank + k] = column[c];
        }
    }

    std::string m_path;
    std::unique_ptr<PartSource> m_source;
    std::uint64_t m_stored_bytes = 0;
    std::vector<Part> m_parts;
    NpfModel m_model;
    bool m_has_detail = false;  // format version 2
};

}  // namespace

bool has_exr_magic(const unsigned char* head, std::size_t size) {
    return head && size >= 4 && head[0] == 0x76 && head[1] == 0x2f && head[2] == 0x31 && head[3] == 0x01;
}

bool has_tiff_magic(const unsigned char* head, std::size_t size) {
    if (!head || size < 4) return false;
    // "II" little-endian or "MM" big-endian, then 42 (TIFF) or 43 (BigTIFF) in that byte order.
    const bool little = head[0] == 'I' && head[1] == 'I' && (head[2] == 42 || head[2] == 43) && head[3] == 0;
    const bool big = head[0] == 'M' && head[1] == 'M' && head[2] == 0 && (head[3] == 42 || head[3] == 43);
    return little || big;
}

namespace {

// Checks the OpenEXR headers before OpenEXR and OpenImageIO see them, for two problems fuzzing
// found in the system libraries: OpenEXR 3.1 sizes an attribute's value from the header's own
// length field before reading it, so a header that claims a value of up to 2 GB makes it
// allocate and clear that much (2 GB and seconds per file); and OpenImageIO 2.4 aborts on a
// channel of an unknown pixel type. Refuses an attribute longer than what is left of the file
// and such a channel. "" when the headers are plausible.
NpfModel read_with(const std::string& path, std::unique_ptr<PartSource> source) {
    const ExactFloatScope exact;  // half-denormal texels must not read as 0 (float_environment.h)
    const std::uint64_t size = require_regular_file(path, "an NPF texture (.exr)");
    if (size == 0) throw Error(path, "empty file");
    {
        std::ifstream in(path, std::ios::binary);
        if (!in) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
        unsigned char head[4] = {};
        in.read(reinterpret_cast<char*>(head), sizeof head);
        if (has_tiff_magic(head, std::size_t(in.gcount()))) {
            throw Error(path, "not an OpenEXR file but a TIFF (maketx's .tx copies of a factor texture are TIFF "
                              "and keep only its first part): shade the original .exr (docs/farms.md)");
        }
        if (!has_exr_magic(head, std::size_t(in.gcount()))) {
            throw Error(path, "not an OpenEXR file (NPF factor textures are OpenEXR images)");
        }
    }
    check_openexr_header(path, kMaxPartPixels);
    return read_npf_texture_parts(path, std::move(source), size);
}

}  // namespace

NpfModel read_npf_texture_parts(const std::string& path, std::unique_ptr<NpfTexturePartSource> source, std::uint64_t stored_bytes) {
    try {
        return Reader(path, std::move(source), stored_bytes).read();
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {  // OpenEXR or allocation failures OIIO did not catch
        throw Error(path, std::string("cannot read: ") + e.what());
    }
}

NpfModel read_npf_texture(const std::string& path) { return read_with(path, file_part_source(path)); }

NpfModel read_npf_texture(const std::string& path, OIIO::TextureSystem& ts) {
    return read_with(path, texture_system_part_source(path, ts));
}

bool is_npf_texture_or_copy(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char head[4] = {};
    if (!in.read(reinterpret_cast<char*>(head), sizeof head)) return false;
    return has_exr_magic(head, sizeof head) || has_tiff_magic(head, sizeof head);
}

bool is_npf_texture(const std::string& path) {
    try {
        std::ifstream in(path, std::ios::binary);
        unsigned char head[4] = {};
        if (!in.read(reinterpret_cast<char*>(head), sizeof head) || !has_exr_magic(head, sizeof head)) return false;
        in.close();
        if (!openexr_header_problem(path, kMaxPartPixels).empty()) return false;
        std::unique_ptr<OIIO::ImageInput> input = OIIO::ImageInput::create("openexr");
        ImageSpec spec;
        if (!input || !input->open(path, spec)) {
            if (input) input->geterror();
            return false;
        }
        for (int i = 0; input->seek_subimage(i, 0); ++i) {
            const ImageSpec& s = input->spec();
            if (s.get_string_attribute("oiio:subimagename") == layout::kPartD) {
                return s.find_attribute(layout::kAttrVersion, OIIO::TypeInt, true) != nullptr;
            }
        }
        input->geterror();
        return false;
    } catch (const std::exception&) {
        return false;
    }
}

}  // namespace npf
