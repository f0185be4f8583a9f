// What a batch's files record (private to npf_batch): an output's figures (errors, albedo, edit
// history) and a validation render's (PSNR, floor, SSIM, relMSE), read from their OpenEXR
// headers for files already there, or from the model about to be written.
#pragma once

#include <npf/batch/summary.h>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace npf::batch::detail {

// Attribute name -> string value.
using Header = std::map<std::string, std::string>;

// The first part's string attributes of an OpenEXR file; nothing when the file is missing or
// unreadable (headers only: cheap). `npf_texture`: the file must be an NPF texture by its first
// bytes (its header checks keep a damaged file at an output's name from OpenImageIO's assertions).
std::optional<Header> header_of(const std::string& path, bool npf_texture);

// The figures an output's metadata records, as its header carries them: the summary of a
// material converted now and of one skipped later read the same numbers.
void fill_recorded_figures(MaterialResult& r, const Header& output_header);
// The same from a model's metadata (keys without the header's "npf:meta:" prefix).
void fill_recorded_figures(MaterialResult& r, const std::vector<std::pair<std::string, std::string>>& metadata);

// A validation render's figures, as written into its header by render_figures_metadata (a
// figure that is not there: infinite PSNR and floor, as a pair that agrees exactly).
LightingCheck lighting_check_of(const std::string& label, const Header& render_header);
std::vector<std::pair<std::string, std::string>> render_figures_metadata(const LightingCheck& check);

}  // namespace npf::batch::detail
