#include "texture_tables.h"

#include <npf/core/error.h>
#include <npf/shading/npf_equation.h>
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

// The OpenEXR reader, whatever the file's name says (ImageCache::add_file's creator).
OIIO::ImageInput* openexr_input() { return OIIO::ImageInput::create("openexr").release(); }

}  // namespace

NpfClosure::TextureTables::TextureTables(const std::string& path, OIIO::TextureSystem* host)
    : m_path(path), m_ts(host), m_name(path) {
    if (!m_ts) {
        // Our own cache, told that this file is OpenEXR: by default OpenImageIO picks a reader by
        // the name's extension, and some readers take parameters from the name itself (a factor
        // texture named x.null?RES=20000x20000 was read as a 20000 x 20000 procedural image).
        m_cache = OIIO::ImageCache::create(/*shared=*/false);
        if (!m_cache) throw Error(path, "cannot create an ImageCache");
        m_cache->add_file(m_name, &openexr_input);
        m_ts = OIIO::TextureSystem::create(/*shared=*/false, m_cache);
        if (!m_ts) {
            OIIO::ImageCache::destroy(m_cache);
            throw Error(path, "cannot create a TextureSystem");
        }
        m_owned = true;
        // Every basis of a part in one tile (docs/format.md sec. 6).
        m_ts->attribute("max_tile_channels", 1 << 16);
    }
}

NpfClosure::TextureTables::~TextureTables() {
    if (m_owned) OIIO::TextureSystem::destroy(m_ts);
    if (m_cache) OIIO::ImageCache::destroy(m_cache);
}

NpfModel NpfClosure::TextureTables::read_model() {
    NpfModel m = read_npf_texture(m_path, *m_ts);
    // Checked before anything is built on the model: the lookups fetch into buffers of this size.
    for (const auto& [name, rank] :
         {std::pair<const char*, int>{"D", m.D.rank}, {"G", m.G.rank}, {"detail", m.detail.rank}}) {
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
    int d_part = -1, g_part = -1, d_first = -1, g_first = -1, r_part = -1, r_first = -1;
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
        } else if (name == layout::kPartDetail && m.has_detail()) {
            r_part = i;
            r_first = first_of(layout::kRBasis, m.detail.rank);
        }
    }
    if (d_part < 0 || g_part < 0) throw Error(m_path, "the TextureSystem does not show parts D and G");
    if (m.has_detail() && r_part < 0) throw Error(m_path, "the TextureSystem does not show part 'detail'");
    m_d_opt = lookup_options(d_part, d_first);
    m_g_opt = lookup_options(g_part, g_first);
    if (m.has_detail()) {
        m_r_opt = lookup_options(r_part, r_first);  // periodic in phi_d, clamped rows
        m_r_grid = m.detail_grid;
        m_r_rank = m.detail.rank;
    }
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
        // Beyond the last centre: G's horizon rule (npf_equation.h) on every basis table, which
        // is linear, so it commutes with the recombination.
        if (!lookup(m_g_opt, last, col, rank, a) || !lookup(m_g_opt, last - 1.0, col, rank, b)) return false;
        const double x = row - last;
        for (int k = 0; k < rank; ++k) out[k] = equation::g_beyond_last_row(a[k], b[k], x);
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
    if (!m_r_grid.empty() && !fill_detail(at)) return false;
    at.cached = true;
    return true;
}

bool NpfClosure::TextureTables::fill_detail(NpfModel::Lookup& at) const {
    // Rows of the part are theta_h slices of theta_d rows each; theta_d is clamped to the slice's
    // outer centres (at.r_at), so each bilinear lookup stays inside its slice, and the two slices
    // are blended here.
    const DetailPosition& p = at.r_at;
    const double d = p.d.i0 + p.d.t, col = p.p.i0 + p.p.t;
    float a[NpfModel::kInlineRank], b[NpfModel::kInlineRank];
    if (!lookup(m_r_opt, double(p.h.i0) * m_r_grid.theta_d + d, col, m_r_rank, a)) return false;
    if (p.h.t == 0.0) {
        std::copy(a, a + m_r_rank, at.r_basis);
        return true;
    }
    if (!lookup(m_r_opt, double(p.h.i1) * m_r_grid.theta_d + d, col, m_r_rank, b)) return false;
    for (int k = 0; k < m_r_rank; ++k) at.r_basis[k] = (1.0 - p.h.t) * a[k] + p.h.t * b[k];
    return true;
}

}  // namespace npf
