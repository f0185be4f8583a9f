#include "texture_tables.h"

#include <npf/core/error.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/shading/npf_texture_layout.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <utility>

namespace npf {

namespace {

namespace layout = npf_exr;

OIIO::TextureOpt lookup_options(int subimage, int first_channel) {
    OIIO::TextureOpt opt;
    opt.subimage = subimage;
    opt.firstchannel = first_channel;
    opt.mipmode = OIIO::TextureOpt::MipModeNoMIP;
    opt.interpmode = OIIO::TextureOpt::InterpBilinear;
    opt.swrap = OIIO::TextureOpt::WrapPeriodic;  // phi
    opt.twrap = OIIO::TextureOpt::WrapClamp;     // theta (clamped at the outer centres)
    return opt;
}

}  // namespace

NpfClosure::TextureTables::TextureTables(const std::string& path, OIIO::TextureSystem* host)
    : m_path(path), m_ts(host), m_name(path) {
    if (!m_ts) {
        m_ts = OIIO::TextureSystem::create(/*shared=*/false);
        if (!m_ts) throw Error(path, "cannot create a TextureSystem");
        m_owned = true;
        // Every basis of a part in one tile (docs/format.md sec. 6).
        m_ts->attribute("max_tile_channels", 1 << 16);
    }
}

NpfClosure::TextureTables::~TextureTables() {
    if (m_owned) OIIO::TextureSystem::destroy(m_ts);
}

NpfModel NpfClosure::TextureTables::read_model() {
    NpfModel m = read_npf_texture(m_path, *m_ts);
    // Checked before anything is built on the model: the lookups fetch into buffers of this size.
    for (const auto& [name, rank] : {std::pair<const char*, int>{"D", m.D.rank}, {"G", m.G.rank}}) {
        if (rank > NpfModel::kInlineRank) {
            throw Error(m_path, std::string("the texture path shades ranks up to ") +
                                    std::to_string(NpfModel::kInlineRank) + "; this file's " + name + " has rank " +
                                    std::to_string(rank));
        }
    }
    m_handle = m_ts->get_texture_handle(m_name);
    if (!m_handle) throw Error(m_path, "the TextureSystem gives no handle: " + m_ts->geterror());
    int count = 0;
    m_ts->get_texture_info(m_name, 0, OIIO::ustring("subimages"), OIIO::TypeInt, &count);
    int d_part = -1, g_part = -1, d_first = -1, g_first = -1;
    for (int i = 0; i < count; ++i) {
        OIIO::ImageSpec spec;
        if (!m_ts->get_imagespec(m_name, i, spec)) continue;
        const std::string name = spec.get_string_attribute("oiio:subimagename");
        // The bases must be consecutive channels (OpenEXR sorts names; the zero-padded indices
        // keep them in order), so that one lookup fetches them all.
        auto first_of = [&](const char* prefix, int rank) {
            const int first = spec.channelindex(layout::indexed_channel(prefix, 0, std::size_t(rank)));
            for (int k = 0; k < rank; ++k) {
                if (first < 0 ||
                    spec.channelindex(layout::indexed_channel(prefix, std::size_t(k), std::size_t(rank))) != first + k) {
                    throw Error(m_path, std::string("the ") + prefix + "* channels of part '" + name +
                                            "' are not consecutive, so they cannot be fetched in one lookup");
                }
            }
            return first;
        };
        if (name == layout::kPartD) {
            d_part = i;
            d_first = first_of(layout::kDBasis, m.D.rank);
        } else if (name == layout::kPartG) {
            g_part = i;
            g_first = first_of(layout::kGBasis, m.G.rank);
        }
    }
    if (d_part < 0 || g_part < 0) throw Error(m_path, "the TextureSystem does not show parts D and G");
    m_d_opt = lookup_options(d_part, d_first);
    m_g_opt = lookup_options(g_part, g_first);
    m_d_theta = m.d_theta;
    m_d_phi = m.d_phi;
    m_g_theta = m.g_theta;
    m_g_phi = m.g_phi;
    m_d_rank = m.D.rank;
    m_g_rank = m.G.rank;
    return m;
}

bool NpfClosure::TextureTables::lookup(OIIO::TextureOpt opt, double row, double col, int nchannels, float* out) const {
    // Every part is mapped over the display window, D's grid (docs/format.md sec. 6), so a
    // position in a part's own cells becomes s = (col + 1/2) / d_phi, t = (row + 1/2) / d_theta.
    const float s = float((col + 0.5) / m_d_phi), t = float((row + 0.5) / m_d_theta);
    return m_ts->texture(m_handle, m_ts->get_perthread_info(), opt, s, t, 0.f, 0.f, 0.f, 0.f, nchannels, out);
}

bool NpfClosure::TextureTables::lookup_g(double row, double col, int rank, double* out) const {
    float a[NpfModel::kInlineRank], b[NpfModel::kInlineRank];
    const double last = m_g_theta - 1;
    if (m_g_theta > 1 && row > last) {
        // Beyond the last centre: the line through the last two rows.
        if (!lookup(m_g_opt, last, col, rank, a) || !lookup(m_g_opt, last - 1.0, col, rank, b)) return false;
        const double x = row - last;
        for (int k = 0; k < rank; ++k) out[k] = a[k] + x * (double(a[k]) - double(b[k]));
        return true;
    }
    if (!lookup(m_g_opt, row, col, rank, a)) return false;
    std::copy(a, a + rank, out);
    return true;
}

bool NpfClosure::TextureTables::fill(NpfModel::Lookup& at) const {
    float d[NpfModel::kInlineRank];
    if (!lookup(m_d_opt, at.d_row, at.d_col, m_d_rank, d)) return false;
    std::copy(d, d + m_d_rank, at.d_basis);
    if (!lookup_g(at.g_i_row, at.g_i_col, m_g_rank, at.g_i_basis) ||
        !lookup_g(at.g_o_row, at.g_o_col, m_g_rank, at.g_o_basis)) {
        return false;
    }
    at.cached = true;
    return true;
}

}  // namespace npf
