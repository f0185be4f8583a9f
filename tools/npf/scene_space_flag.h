// --from linear|xyz, read the same by every command that takes a scene-referred image (display,
// compare): what its values are.
#pragma once

#include "command_line.h"

#include <npf/color/display.h>

namespace npf::cli {

inline color::SceneSpace scene_space_flag(const CommandLine& cl) {
    return cl.choice<color::SceneSpace>("--from",
                                        {{"linear", color::SceneSpace::LinearRec709}, {"xyz", color::SceneSpace::CieXyzD65}},
                                        color::SceneSpace::LinearRec709, "is neither linear nor xyz");
}

}  // namespace npf::cli
