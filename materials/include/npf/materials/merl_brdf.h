// Measured isotropic RGB materials of the MERL database (`*.binary`, Matusik et al. 2003).
//
// Layout (as the reference reader BRDFRead.cpp expects): three little-endian int32 dimensions
// (theta_h bins, theta_d bins, phi_d bins), normally 90 x 90 x 180, then all red, all green
// and all blue values as little-endian float64, index = phi_d + n_pd * (theta_d + n_td *
// theta_h). Stored numbers are f_r divided by the channel scale (R 1/1500, G 1.15/1500,
// B 1.66/1500); negative numbers mark bins without a valid measurement.
//
// The table is indexed by Rusinkiewicz half/difference angles: theta_h on a square-root grid
// (dense near the specular peak), theta_d and phi_d on uniform grids, phi_d folded to [0, pi)
// because the data are reciprocal.
#pragma once

#include <npf/materials/isotropic_rgb_brdf.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace npf {

enum class MerlLookup {
    Nearest,  // the reference reader's bin lookup, bit for bit (in double, then rounded)
    Linear,   // trilinear between bin centres (theta_h in its square-root coordinate)
};

struct MerlOptions {
    MerlLookup lookup = MerlLookup::Nearest;
};

// The reference reader's per-channel factors from stored numbers to f_r.
constexpr double kMerlScaleRed = 1.0 / 1500.0;
constexpr double kMerlScaleGreen = 1.15 / 1500.0;
constexpr double kMerlScaleBlue = 1.66 / 1500.0;

class MerlBrdf final : public IsotropicRgbBrdf {
public:
    // Throws npf::Error naming the file and the problem (missing, directory, empty, truncated,
    // bad dimensions, non-finite values).
    static std::unique_ptr<MerlBrdf> load(const std::string& path, MerlOptions opts = {});

    // Format sniffing: true when the first bytes hold three positive dimensions whose table
    // makes the file exactly `file_size` bytes long (12 + n_th * n_td * n_pd * 3 * 8).
    static bool looks_like_merl(const std::uint8_t* head, std::size_t head_size,
                                std::uint64_t file_size);
    // True when the first bytes hold MERL's standard 90 x 90 x 180 dimensions, or three positive
    // dimensions whose table is within a factor of two of `file_size`: a MERL file cut short or
    // padded, which the loader then names as such.
    static bool has_plausible_header(const std::uint8_t* head, std::size_t head_size, std::uint64_t file_size);

    // pdf and sample: cosine-weighted (MERL files carry no sampling tables).
    void eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const override;

    MerlLookup lookup() const { return m_lookup; }
    int theta_h_bins() const { return m_n_th; }
    int theta_d_bins() const { return m_n_td; }
    int phi_d_bins() const { return m_n_pd; }
    // f_r of one bin and channel (0 R, 1 G, 2 B), scale applied, negative if invalid.
    // Indices must be in range.
    double bin_value(int channel, int ith, int itd, int ipd) const;

private:
    MerlBrdf() = default;

    std::size_t bin_index(int ith, int itd, int ipd) const {
        return static_cast<std::size_t>(ipd) +
               static_cast<std::size_t>(m_n_pd) *
                   (static_cast<std::size_t>(itd) +
                    static_cast<std::size_t>(m_n_td) * static_cast<std::size_t>(ith));
    }
    // f_r of the three stored channels for one direction pair (both above the horizon).
    void lookup_nearest(const double in[3], const double out[3], double rgb[3]) const;
    void lookup_linear(const double in[3], const double out[3], double rgb[3]) const;

    MerlLookup m_lookup = MerlLookup::Nearest;
    int m_n_th = 0, m_n_td = 0, m_n_pd = 0;
    std::size_t m_bins = 0;
    // f_r (stored number times channel scale), [channel][bin]; doubles so that Nearest matches
    // the reference reader exactly.
    std::vector<double> m_fr;
};

}  // namespace npf
