// Opens any supported material file by looking at its contents, not its name.
#pragma once

#include <npf/core/brdf.h>

#include <memory>
#include <string>

namespace npf {

// RGL `.bsdf` (tensor_file magic), MERL `.binary` (its header and exact size) or NPF factor
// texture (OpenEXR magic, then the npf:format_version attribute; docs/format.md). Throws
// npf::Error naming the file when it is missing, a directory, empty, of an unknown format or
// malformed.
std::unique_ptr<Brdf> open_brdf(const std::string& path);

// A material file as open_brdf opens it, or an analytic recipe (a name ending in .yaml or
// .yml; docs/synth.md) evaluated exactly: what `npf convert` and the benchmarks accept.
std::unique_ptr<Brdf> open_material(const std::string& path);

}  // namespace npf
