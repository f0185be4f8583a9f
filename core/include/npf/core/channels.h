// What an evaluation returns, and how to read it from what a source stores.
//
// A material stores either RGB (linear sRGB, three channels) or a list of wavelengths (nm).
// A caller asks for `Channels`: RGB, or any list of wavelengths. `ChannelQuery` is the request
// resolved against one source's stored channels once, so that the per-direction evaluation
// only blends two stored channels per requested one and never searches.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace npf {

enum class ChannelKind { Rgb, Spectral };

class Channels {
public:
    static Channels rgb();
    // Wavelengths in nanometres; any order, duplicates allowed (each gets its own value).
    static Channels spectral(std::vector<float> wavelengths_nm);

    ChannelKind kind() const { return m_kind; }
    bool is_rgb() const { return m_kind == ChannelKind::Rgb; }
    std::size_t size() const { return m_kind == ChannelKind::Rgb ? 3 : m_wavelengths.size(); }
    const std::vector<float>& wavelengths() const { return m_wavelengths; }  // empty for RGB

    // "R G B" or the wavelengths, for headers and messages.
    std::string describe() const;
    // Channel c as a column header or a message names it: "R", "G", "B" or "550nm".
    std::string name(std::size_t c) const;

private:
    ChannelKind m_kind = ChannelKind::Rgb;
    std::vector<float> m_wavelengths;
};

// Requested channel k = (1 - weight1[k]) * stored[index0[k]] + weight1[k] * stored[index1[k]].
// Spectral requests interpolate linearly between the neighbouring stored wavelengths and are
// constant outside the stored range (the RGL readers' rule); RGB maps channel to channel.
struct ChannelQuery {
    Channels requested;
    std::vector<std::uint32_t> index0, index1;
    std::vector<float> weight1;
    // Negative values (out-of-gamut RGB, noisy measurements) are clamped to zero unless false:
    // the reference readers clamp RGB; `npf eval --raw` turns it off.
    bool clamp_negative = true;

    std::size_t size() const { return index0.size(); }
};

// Where wavelength `lambda` falls on an ascending list of `n` stored wavelengths: stored
// channels i0 and i1 and the weight t of i1. Linear between neighbours, constant outside (the
// parameter-blend rule of the RGL readers, docs/rgl-format.md sec. 3.1, applied to wavelength).
// No allocation, so shaders call it per sample; make_channel_query uses it too.
void locate_wavelength(const float* grid, std::size_t n, float lambda, std::uint32_t& i0, std::uint32_t& i1,
                       float& t);

// Channels i0 = i and i1 = i + 1 around `lambda` and the weight of i1, once i is known: the last
// step of locate_wavelength and WavelengthLocator::locate.
inline void blend_wavelengths_at(const float* grid, std::size_t i, float lambda, std::uint32_t& i0, std::uint32_t& i1,
                                 float& t) {
    i0 = std::uint32_t(i);
    i1 = i0 + 1;
    const float span = grid[i1] - grid[i0];
    t = span > 0.f ? std::clamp((lambda - grid[i0]) / span, 0.f, 1.f) : 0.f;
}

// locate_wavelength in constant time on one fixed grid, with the same results to the bit: a
// renderer locates every hero wavelength of every evaluation, and a binary search over a
// 195-wavelength grid (eight unpredictable branches) cost more than the table lookups.
// Buckets of equal width over the grid give a starting index; a short scan settles it.
class WavelengthLocator {
public:
    WavelengthLocator() = default;
    explicit WavelengthLocator(std::vector<float> ascending_grid);
    // Inline: the batched closure locates four wavelengths per pair.
    void locate(float lambda, std::uint32_t& i0, std::uint32_t& i1, float& t) const {
        const std::size_t n = m_grid.size();
        // Outside the grid, NaN, or a grid without buckets: the search gives the same answer.
        if (m_start.empty() || !(lambda >= m_lo && lambda <= m_hi)) {
            locate_wavelength(m_grid.data(), n, lambda, i0, i1, t);
            return;
        }
        std::size_t i = m_start[std::min(std::size_t((lambda - m_lo) * m_buckets_per_nm), m_start.size() - 1)];
        // The last index at or below lambda (what upper_bound - 1 finds), whatever rounding did to
        // the bucket's edge.
        while (i + 1 < n && m_grid[i + 1] <= lambda) ++i;
        while (i > 0 && m_grid[i] > lambda) --i;
        blend_wavelengths_at(m_grid.data(), std::min(i, n - 2), lambda, i0, i1, t);
    }

    // The tables locate() reads, for vector code that locates several wavelengths at once with the
    // same steps (the batched closure's float lanes). start is null where locate() searches.
    struct Tables {
        const float* grid = nullptr;
        std::size_t n = 0;
        const std::uint32_t* start = nullptr;
        std::size_t buckets = 0;
        float lo = 0.f, hi = 0.f, buckets_per_nm = 0.f;
    };
    Tables tables() const {
        return {m_grid.data(), m_grid.size(), m_start.empty() ? nullptr : m_start.data(), m_start.size(), m_lo, m_hi,
                m_buckets_per_nm};
    }

private:
    std::vector<float> m_grid;
    std::vector<std::uint32_t> m_start;  // per bucket: the last grid index at or below its start
    float m_lo = 0.f, m_hi = 0.f, m_buckets_per_nm = 0.f;
};

// Resolves `requested` against `stored`. Throws npf::Error naming `source` when they cannot
// be matched (spectral wavelengths from an RGB source, RGB from a spectral one, empty lists,
// non-finite or non-positive wavelengths).
ChannelQuery make_channel_query(const Channels& stored, const Channels& requested,
                                const std::string& source);

// Parses a wavelength list as given on a command line: "450,550,650" or "start:end:count"
// (count evenly spaced values, both ends included). Throws npf::Error naming `what`.
std::vector<float> parse_wavelength_list(const std::string& text, const std::string& what);

// Parses a channel list as a flag or setting gives it: "rgb", or a wavelength list as
// parse_wavelength_list reads it. The one parser of every --wavelengths flag and wavelengths
// key that takes either, so that all accept the same forms and fail alike: npf::Error naming
// `what` (the flag or key), the problem, then the forms a channel list takes.
Channels parse_channel_list(const std::string& text, const std::string& what);

}  // namespace npf
