// The environment map npf ships for renders without --env: data/envmaps/studio.exr (CC0, HDRI
// Haven / Greg Zaal; data/envmaps/README.md), installed as share/npf/envmaps/studio.exr.
#pragma once

#include <string>
#include <vector>

namespace npf::render {

// Where the shipped map is looked for, in order: beside the running executable
// (<bin>/../share/npf/envmaps/studio.exr, an installed or relocated npf), the source tree this
// library was built from (a build tree), the install prefix it was configured with.
std::vector<std::string> shipped_environment_map_candidates();

// The first candidate that exists. Throws npf::Error listing the places looked at when none
// does.
std::string default_environment_map_path();

}  // namespace npf::render
