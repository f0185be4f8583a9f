// Writing NPF factor textures: the multi-part OpenEXR files of docs/format.md (read back by
// npf/shading/npf_texture_file.h and opened by open_brdf).
#pragma once

#include <npf/shading/npf_model.h>

#include <string>

namespace npf {

// Writes `model` to `path` atomically (a temporary beside it, renamed into place): float pixels,
// lossless ZIP compression, every array bit for bit. Throws npf::Error naming `path` when the
// model is inconsistent (NpfModel::validate), a metadata key is empty, repeated or holds a
// control character, or writing fails; no file appears under `path` then.
void write_npf_texture(const NpfModel& model, const std::string& path);

}  // namespace npf
