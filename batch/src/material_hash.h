// What decides whether a material's output and its validation renders are up to date: the
// content hashes they carry (private to npf_batch; material_hash in runner.h is the public one).
#pragma once

#include <npf/batch/config.h>

#include <string>

namespace npf::batch::detail {

// material_hash for an input whose SHA-256 is known (the parent checks an output against both
// isotropies without opening the input as a material).
std::string material_hash_of(const MaterialJob& job, bool source_isotropic, const std::string& input_sha);

// The hash every validation render of a material is stamped with: the material's, the render
// settings and each lighting (a map by its bytes; a built-in one by its name: its geometry is
// this build's, and the material hash names the build).
std::string render_hash_of(const std::string& material_hash, const RenderCheck& check);

}  // namespace npf::batch::detail
