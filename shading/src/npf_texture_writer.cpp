// The NPF factor texture writer (layout: docs/format.md, names: npf/shading/npf_texture_layout.h).
#include <npf/shading/npf_texture_file.h>

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/text.h>
#include <npf/shading/npf_texture_layout.h>

#include "npf_texture_parts.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <Imath/half.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <sys/stat.h>

namespace npf {

namespace {

namespace layout = npf_exr;
using OIIO::ImageSpec;

// One part: its header and its pixels, interleaved [y][x][channel].
struct PartData {
    ImageSpec spec;
    std::vector<float> pixels;
};

// A part of `width` x `height` pixels. Every part of a multi-part file must have the same
// display window (OpenEXR): D's grid, `display_width` x `display_height` (docs/format.md sec. 6).
PartData make_part(const char* name, int width, int height, const std::vector<std::string>& channels,
                   int display_width, int display_height) {
    PartData p;
    p.spec = ImageSpec(width, height, int(channels.size()), OIIO::TypeFloat);
    p.spec.channelnames = channels;
    p.spec.alpha_channel = -1;  // none of our channels is alpha or depth
    p.spec.z_channel = -1;
    p.spec.full_x = 0;
    p.spec.full_y = 0;
    p.spec.full_width = display_width;
    p.spec.full_height = display_height;
    p.spec.attribute("oiio:subimagename", name);
    p.spec.attribute("compression", "zip");
    // No time stamp: the same model gives the same bytes (batches skip by content, golden tests
    // compare bytes). OpenImageIO 2.4 stamps the time of writing as capDate unless given a
    // DateTime; an empty one is written as an empty capDate: "no date".
    p.spec.attribute("DateTime", "");
    p.pixels.assign(std::size_t(width) * std::size_t(height) * channels.size(), 0.f);
    return p;
}

// Writes the values of channel `channel` (one per pixel, in scanline order).
void put_channel(PartData& p, std::size_t channel, const float* values) {
    const std::size_t n = std::size_t(p.spec.width) * std::size_t(p.spec.height), stride = p.spec.channelnames.size();
    for (std::size_t i = 0; i < n; ++i) p.pixels[i * stride + channel] = values[i];
}

std::vector<std::string> family(const char* prefix, std::size_t count) {
    std::vector<std::string> names;
    for (std::size_t k = 0; k < count; ++k) names.push_back(layout::indexed_channel(prefix, k, count));
    return names;
}

std::string numbers_text(const std::vector<double>& v) {
    std::string text;
    char buf[32];
    for (std::size_t k = 0; k < v.size(); ++k) {
        std::snprintf(buf, sizeof buf, k ? " %.17g" : "%.17g", v[k]);
        text += buf;
    }
    return text;
}

void check_metadata(const NpfModel& m, const std::string& path) {
    std::set<std::string> seen;
    for (const auto& [key, value] : m.metadata) {
        if (key.empty()) throw Error(path, "a metadata key is empty");
        if (key.size() > 200) throw Error(path, "metadata key '" + key.substr(0, 40) + "...' is longer than 200 bytes");
        for (unsigned char ch : key) {
            if (ch < 0x20 || ch == 0x7f) throw Error(path, "metadata key '" + key + "' holds a control character");
        }
        if (!seen.insert(key).second) throw Error(path, "metadata key '" + key + "' appears twice");
        if (value.find('\0') != std::string::npos) throw Error(path, "metadata value of '" + key + "' holds a NUL byte");
    }
}

void put_file_attributes(const NpfModel& m, ImageSpec& spec) {
    spec.attribute(layout::kAttrVersion,
                   m.has_detail() ? layout::kFormatVersion : layout::kFormatVersionWithoutDetail);
    spec.attribute(layout::kAttrChannelKind, m.channels.is_rgb() ? "rgb" : "spectral");
    spec.attribute(layout::kAttrChannelCount, int(m.channel_count()));
    spec.attribute(layout::kAttrIsotropic, m.isotropic() ? 1 : 0);
    spec.attribute(layout::kAttrDTheta, m.d_theta);
    spec.attribute(layout::kAttrDPhi, m.d_phi);
    spec.attribute(layout::kAttrFTheta, m.f_theta);
    spec.attribute(layout::kAttrGTheta, m.g_theta);
    spec.attribute(layout::kAttrGPhi, m.g_phi);
    spec.attribute(layout::kAttrDRank, m.D.rank);
    spec.attribute(layout::kAttrGRank, m.G.rank);
    spec.attribute(layout::kAttrDKeptRatio, OIIO::TypeDesc::DOUBLE, &m.D.kept_ratio);
    spec.attribute(layout::kAttrGKeptRatio, OIIO::TypeDesc::DOUBLE, &m.G.kept_ratio);
    spec.attribute(layout::kAttrDSingularValues, numbers_text(m.D.singular_values));
    spec.attribute(layout::kAttrGSingularValues, numbers_text(m.G.singular_values));
    spec.attribute(layout::kAttrTablesChecksum, tables_checksum(m));
    if (m.has_detail()) {
        spec.attribute(layout::kAttrDetailThetaH, m.detail_grid.theta_h);
        spec.attribute(layout::kAttrDetailThetaD, m.detail_grid.theta_d);
        spec.attribute(layout::kAttrDetailPhiD, m.detail_grid.phi_d);
        spec.attribute(layout::kAttrDetailRank, m.detail.rank);
        spec.attribute(layout::kAttrDetailKeptRatio, OIIO::TypeDesc::DOUBLE, &m.detail.kept_ratio);
        spec.attribute(layout::kAttrDetailSingularValues, numbers_text(m.detail.singular_values));
    }
    if (!m.metadata.empty()) {
        std::string keys;
        for (const auto& [key, value] : m.metadata) {
            if (!keys.empty()) keys += '\n';
            keys += key;
            spec.attribute(std::string(layout::kMetadataPrefix) + key, value);
        }
        spec.attribute(layout::kAttrMetadataKeys, keys);
    }
}

void put_axes(PartData& p, const char* x, const char* y) {
    p.spec.attribute(layout::kAttrXAxis, x);
    p.spec.attribute(layout::kAttrYAxis, y);
}

// Whether every value survives a round trip through half precision (then half is lossless and
// halves the part's size; the fitter rounds the detail basis to half for that reason).
bool exact_in_half(const std::vector<float>& values) {
    for (float v : values) {
        if (float(Imath::half(v)) != v) return false;
    }
    return true;
}

std::vector<PartData> make_parts(const NpfModel& m) {
    const std::size_t C = m.channel_count();
    const int dw = m.d_phi, dh = m.d_theta;  // the shared display window
    std::vector<PartData> parts;

    PartData d = make_part(layout::kPartD, m.d_phi, m.d_theta, family(layout::kDBasis, std::size_t(m.D.rank)), dw, dh);
    for (int k = 0; k < m.D.rank; ++k) put_channel(d, std::size_t(k), m.D.basis.data() + std::size_t(k) * m.D.cells);
    d.spec.attribute("wrapmodes", "periodic,clamp");
    put_axes(d, "phi_h = 2 pi (x + 1/2) / width", "theta_h = (pi/2) ((y + 1/2) / height)^2");
    put_file_attributes(m, d.spec);
    parts.push_back(std::move(d));

    PartData g = make_part(layout::kPartG, m.g_phi, m.g_theta, family(layout::kGBasis, std::size_t(m.G.rank)), dw, dh);
    for (int k = 0; k < m.G.rank; ++k) put_channel(g, std::size_t(k), m.G.basis.data() + std::size_t(k) * m.G.cells);
    g.spec.attribute("wrapmodes", "periodic,clamp");
    put_axes(g, "phi = 2 pi (x + 1/2) / width", "theta = (pi/2) (y + 1/2) / height");
    parts.push_back(std::move(g));

    PartData f = make_part(layout::kPartF, m.f_theta, 1, family(layout::kFChannel, C), dw, dh);
    for (std::size_t c = 0; c < C; ++c) put_channel(f, c, m.F.data() + c * std::size_t(m.f_theta));
    f.spec.attribute("wrapmodes", "clamp,clamp");
    put_axes(f, "theta_d = (pi/2) (x + 1/2) / width", "none (one row)");
    parts.push_back(std::move(f));

    std::vector<std::string> names = {layout::kWavelength, layout::kRhoD, layout::kRhoS};
    for (const std::string& n : family(layout::kDWeight, std::size_t(m.D.rank))) names.push_back(n);
    for (const std::string& n : family(layout::kGWeight, std::size_t(m.G.rank))) names.push_back(n);
    for (const std::string& n : family(layout::kRWeight, std::size_t(m.detail.rank))) names.push_back(n);
    PartData s = make_part(layout::kPartSpectral, int(C), 1, names, dw, dh);
    std::vector<float> column(C);
    for (std::size_t c = 0; c < C; ++c) column[c] = m.channels.is_rgb() ? float(c) : m.channels.wavelengths()[c];
    put_channel(s, 0, column.data());
    put_channel(s, 1, m.rho_d.data());
    put_channel(s, 2, m.rho_s.data());
    std::size_t channel = 3;
    for (const SpectralBasis* b : {&m.D, &m.G, &m.detail}) {
        for (std::size_t k = 0; k < std::size_t(b->rank); ++k, ++channel) {
            for (std::size_t c = 0; c < C; ++c) column[c] = b->weights[c * std::size_t(b->rank) + k];
            put_channel(s, channel, column.data());
        }
    }
    s.spec.attribute("wrapmodes", "clamp,clamp");
    put_axes(s, m.channels.is_rgb() ? "stored channel: R, G, B" : "stored wavelength, ascending", "none (one row)");
    parts.push_back(std::move(s));

    if (m.has_detail()) {
        const DetailGrid& grid = m.detail_grid;
        PartData r = make_part(layout::kPartDetail, grid.phi_d, grid.theta_h * grid.theta_d,
                               family(layout::kRBasis, std::size_t(m.detail.rank)), dw, dh);
        for (int k = 0; k < m.detail.rank; ++k) {
            put_channel(r, std::size_t(k), m.detail.basis.data() + std::size_t(k) * m.detail.cells);
        }
        if (exact_in_half(m.detail.basis)) r.spec.set_format(OIIO::TypeHalf);
        r.spec.attribute("wrapmodes", "periodic,clamp");
        put_axes(r, "phi_d = 2 pi (x + 1/2) / width",
                 "y = i theta_d + j: u_h = (i + 1/2) / detail_theta_h, theta_d = (pi/2) (j + 1/2) / detail_theta_d");
        parts.push_back(std::move(r));
    }
    return parts;
}

// Reads the written file back and compares every part's pixels with what was meant, bit for
// bit (what was stored as half is exactly representable, so it reads back equal). OpenEXR keeps
// channels sorted by name, so they are matched by name.
void check_written(const AtomicOutput& atomic, const std::string& name, const std::vector<PartData>& parts) {
    std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::create("openexr");
    if (!in) atomic.fail("cannot read the output back", first_line(OIIO::geterror()));
    ImageSpec first;
    if (!in->open(name, first)) atomic.fail("cannot write (the file does not read back)", first_line(in->geterror()));
    std::vector<float> back;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const ImageSpec& want = parts[i].spec;
        const std::string part = "part " + std::string(want.get_string_attribute("oiio:subimagename"));
        if (!in->seek_subimage(int(i), 0)) atomic.fail("cannot write (" + part + " does not read back)", first_line(in->geterror()));
        const ImageSpec& got = in->spec();
        std::vector<std::size_t> where;  // want's channel k is got's channel where[k]
        for (const std::string& channel : want.channelnames) {
            const auto found = std::find(got.channelnames.begin(), got.channelnames.end(), channel);
            if (found == got.channelnames.end()) break;
            where.push_back(std::size_t(found - got.channelnames.begin()));
        }
        if (got.width != want.width || got.height != want.height || got.nchannels != want.nchannels ||
            where.size() != want.channelnames.size())
            atomic.fail("cannot write (" + part + " reads back with another shape)", "");
        back.assign(parts[i].pixels.size(), 0.f);
        if (!in->read_image(int(i), 0, 0, got.nchannels, OIIO::TypeFloat, back.data()))
            atomic.fail("cannot write (" + part + " does not read back)", first_line(in->geterror()));
        const std::size_t n = std::size_t(want.nchannels), pixels = back.size() / n;
        for (std::size_t p = 0; p < pixels; ++p)
            for (std::size_t k = 0; k < n; ++k)
                if (std::memcmp(&back[p * n + where[k]], &parts[i].pixels[p * n + k], sizeof(float)) != 0)
                    atomic.fail("cannot write (" + part + " reads back different)", "the file on disk is not what was written");
    }
}

}  // namespace

std::uint64_t write_npf_texture(const NpfModel& model, const std::string& path) {
    model.validate(path);
    check_metadata(model, path);
    const std::vector<PartData> parts = make_parts(model);
    std::vector<ImageSpec> specs;
    for (const PartData& p : parts) specs.push_back(p.spec);

    AtomicOutput atomic(path);
    // OpenImageIO writes through the proxy into the temporary where it can (declared before
    // `out`, so that it outlives the writes `out` makes when destroyed unclosed). Its multi-part
    // OpenEXR writer (2.4) ignores proxies and opens a name: it gets one that reaches the
    // temporary without going through the folder, and the file is read back before publishing,
    // since that writer reports no write error (a full disk).
    AtomicOutputProxy<OIIO::Filesystem::IOProxy> proxy(atomic);
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("openexr");
    if (!out) throw Error(path, "this build of OpenImageIO cannot write OpenEXR: " + first_line(OIIO::geterror()));
    if (!out->set_ioproxy(&proxy)) throw Error(path, "this build of OpenImageIO cannot write OpenEXR through a proxy");
    const std::string name = atomic.descriptor_path();
    try {
        if (!out->open(name, int(specs.size()), specs.data())) atomic.fail("cannot create output", first_line(out->geterror()));
        for (std::size_t i = 0; i < parts.size(); ++i) {
            const std::string part(parts[i].spec.get_string_attribute("oiio:subimagename"));
            if (i > 0 && !out->open(name, specs[i], OIIO::ImageOutput::AppendSubimage)) {
                atomic.fail("cannot start part '" + part + "'", first_line(out->geterror()));
            }
            if (!out->write_image(OIIO::TypeFloat, parts[i].pixels.data())) {
                atomic.fail("cannot write part '" + part + "'", first_line(out->geterror()));
            }
        }
        if (!out->close()) atomic.fail("cannot finish output", first_line(out->geterror()));
        out.reset();
        check_written(atomic, name, parts);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        atomic.fail("cannot write", e.what());
    }
    // The size as written: after a write-through (-o /dev/null) the destination cannot say it.
    struct stat st {};
    const std::uint64_t bytes = ::stat(atomic.descriptor_path().c_str(), &st) == 0 ? std::uint64_t(st.st_size) : 0;
    atomic.commit();
    return bytes;
}

}  // namespace npf
