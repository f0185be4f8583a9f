// Opens any material source: the one way every tool reads a material (core/brdf.h).
#pragma once

#include <npf/core/brdf.h>

#include <memory>
#include <string>

namespace npf {

// An analytic recipe (a name ending in .yaml or .yml; docs/synth.md), evaluated exactly; any
// other file by its contents, not its name: RGL `.bsdf` (tensor_file magic), MERL `.binary`
// (its header and exact size), NPF factor texture (OpenEXR magic, then the npf:format_version
// attribute; docs/format.md) or Neural BRDF `.h5` (HDF5 signature). Throws npf::Error naming
// the file when it is missing, a directory, empty, of an unknown format or malformed.
std::unique_ptr<Brdf> open_material(const std::string& path);

}  // namespace npf
