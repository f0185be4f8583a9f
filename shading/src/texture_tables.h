// NpfClosure's texture path: D and G looked up through OpenImageIO's TextureSystem, with the
// mapping of docs/format.md sec. 6 (s, t over the display window, which is D's grid; explicit
// wrap modes; no MIP levels; bilinear), and G's linear extrapolation beyond its last theta centre
// done by hand from two row lookups, as the model evaluates it. The detail layer's trilinear
// lookup is two bilinear ones, in the two theta_h slices of its part (docs/format.md sec. 6).
#pragma once

#include <npf/shading/npf_closure.h>
#include <npf/shading/npf_model.h>

#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/texture.h>

#include <string>

namespace npf {

class NpfClosure::TextureTables {
public:
    // Opens `path` in `host` (or in a private TextureSystem, destroyed with this object).
    TextureTables(const std::string& path, OIIO::TextureSystem* host);
    ~TextureTables();
    TextureTables(const TextureTables&) = delete;
    TextureTables& operator=(const TextureTables&) = delete;

    // The whole model, read through the TextureSystem (checked as read_npf_texture checks);
    // also resolves the parts and channels the lookups use. Throws npf::Error naming the file,
    // also for a rank above NpfModel::kInlineRank (the lookups' buffers).
    NpfModel read_model();

    // Fills at.d_basis, at.g_i_basis and at.g_o_basis from texture lookups at the positions
    // prepare() computed, and sets at.cached. false if the TextureSystem fails (the file vanished
    // from a cache that had evicted it, say): the caller then shades black.
    bool fill(NpfModel::Lookup& at) const;

private:
    bool lookup(OIIO::TextureOpt opt, double row, double col, int nchannels, float* out) const;
    bool lookup_g(double row, double col, int rank, double* out) const;

    std::string m_path;
    OIIO::TextureSystem* m_ts = nullptr;
    OIIO::ImageCache* m_cache = nullptr;  // ours, when the TextureSystem is
    bool m_owned = false;
    OIIO::ustring m_name;
    OIIO::TextureSystem::TextureHandle* m_handle = nullptr;
    bool fill_detail(NpfModel::Lookup& at) const;

    OIIO::TextureOpt m_d_opt, m_g_opt, m_r_opt;  // copied per lookup: texture() rewrites its options
    int m_d_theta = 0, m_d_phi = 0, m_g_theta = 0, m_g_phi = 0;
    int m_d_rank = 0, m_g_rank = 0;
    DetailGrid m_r_grid;  // empty: no detail layer
    int m_r_rank = 0;
};

}  // namespace npf
