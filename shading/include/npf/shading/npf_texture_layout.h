// Names in an NPF factor texture (docs/format.md): the one place the writer (converter) and the
// reader (shading) take part, channel and attribute names from.
#pragma once

#include <cstddef>
#include <string>

namespace npf::npf_exr {

// Version 2 added the optional detail layer (part "detail"); a file without one is written as
// version 1, exactly as before, so older readers still read it. Readers take both.
constexpr int kFormatVersion = 2;
constexpr int kFormatVersionWithoutDetail = 1;

// Parts, in the order they are written.
constexpr const char* kPartD = "D";
constexpr const char* kPartG = "G";
constexpr const char* kPartF = "F";
constexpr const char* kPartSpectral = "spectral";
constexpr const char* kPartDetail = "detail";  // version 2, optional, written last

// Channels of the "spectral" part besides the weights.
constexpr const char* kWavelength = "wavelength";
constexpr const char* kRhoD = "rho_d";
constexpr const char* kRhoS = "rho_s";

// File-wide attributes, in the header of part "D".
constexpr const char* kAttrVersion = "npf:format_version";     // int
constexpr const char* kAttrChannelKind = "npf:channel_kind";    // string "rgb" | "spectral"
constexpr const char* kAttrChannelCount = "npf:channel_count";  // int
constexpr const char* kAttrIsotropic = "npf:isotropic";         // int 0 | 1
constexpr const char* kAttrDTheta = "npf:d_theta";              // ints: grid sizes
constexpr const char* kAttrDPhi = "npf:d_phi";
constexpr const char* kAttrFTheta = "npf:f_theta";
constexpr const char* kAttrGTheta = "npf:g_theta";
constexpr const char* kAttrGPhi = "npf:g_phi";
constexpr const char* kAttrDRank = "npf:d_rank";                // ints
constexpr const char* kAttrGRank = "npf:g_rank";
constexpr const char* kAttrDKeptRatio = "npf:d_kept_ratio";     // doubles
constexpr const char* kAttrGKeptRatio = "npf:g_kept_ratio";
constexpr const char* kAttrDSingularValues = "npf:d_singular_values";  // string of %.17g numbers
constexpr const char* kAttrGSingularValues = "npf:g_singular_values";
// The detail layer (version 2; all present when part "detail" is, absent otherwise).
constexpr const char* kAttrDetailThetaH = "npf:detail_theta_h";  // ints: grid sizes
constexpr const char* kAttrDetailThetaD = "npf:detail_theta_d";
constexpr const char* kAttrDetailPhiD = "npf:detail_phi_d";
constexpr const char* kAttrDetailRank = "npf:detail_rank";                      // int
constexpr const char* kAttrDetailKeptRatio = "npf:detail_kept_ratio";           // double
constexpr const char* kAttrDetailSingularValues = "npf:detail_singular_values";  // string
// A seal over every table value ("fnv1a64:" and 16 hex digits; docs/format.md sec. 4): a copy
// whose pixels a tool changed (oiiotool -d half, say) is refused rather than shaded. Optional:
// files written before it have none.
constexpr const char* kAttrTablesChecksum = "npf:tables_checksum";  // string
constexpr const char* kAttrMetadataKeys = "npf:metadata_keys";  // string, keys joined by '\n'
constexpr const char* kMetadataPrefix = "npf:meta:";            // + key: string value
// Metadata keys that npf reads back (the others are written for people: docs/format.md sec. 5).
constexpr const char* kMetaAlbedoMax = "albedo_max";                        // edit --limit-albedo
constexpr const char* kMetaAlbedoMaxViewTheta = "albedo_max_view_theta";
constexpr const char* kMetaBatchName = "batch_name";                        // npf batch
constexpr const char* kMetaBatchSettings = "batch_settings";
constexpr const char* kMetaBatchHash = "batch_hash";                        // up to date?
// npf convert's BRDF-space errors (mean over channels, worst channel) of the file and of the
// fitted factors before compression, read back by npf batch for its summary.
constexpr const char* kMetaErrorMean = "error_rel_rms_mean";
constexpr const char* kMetaErrorMax = "error_rel_rms_max";
constexpr const char* kMetaFittedErrorMean = "error_fitted_rel_rms_mean";
constexpr const char* kMetaFittedErrorMax = "error_fitted_rel_rms_max";
// The edit history: "edit_001", "edit_002", ... (npf edit writes them, npf batch reads them).
constexpr const char* kMetaEditPrefix = "edit_";
// Per part (informative; readers rely on the grid sizes above): what x and y index.
constexpr const char* kAttrXAxis = "npf:x_axis";
constexpr const char* kAttrYAxis = "npf:y_axis";

// Indexed channel names, zero-padded to at least three digits so that OpenEXR's name-sorted
// channel lists keep numeric order: indexed_channel("D.u", 3, 20) = "D.u003".
inline std::string indexed_channel(const char* prefix, std::size_t index, std::size_t count) {
    std::size_t digits = 3;
    for (std::size_t n = count > 0 ? count - 1 : 0; n >= 1000; n /= 10) ++digits;
    std::string number = std::to_string(index);
    if (number.size() < digits) number.insert(0, digits - number.size(), '0');
    return prefix + number;
}

// Channel families.
constexpr const char* kDBasis = "D.u";    // part D: basis tables
constexpr const char* kGBasis = "G.u";    // part G: basis tables
constexpr const char* kFChannel = "F.c";  // part F: one channel per stored channel
constexpr const char* kDWeight = "D.v";   // part spectral: weights of the D basis
constexpr const char* kGWeight = "G.v";   // part spectral: weights of the G basis
constexpr const char* kRBasis = "R.u";    // part detail: basis tables of the residual
constexpr const char* kRWeight = "R.v";   // part spectral: weights of the residual's basis

}  // namespace npf::npf_exr
