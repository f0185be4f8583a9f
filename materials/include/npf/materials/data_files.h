// Finding the data files npf ships (metal refractive indices, default materials):
// $NPF_DATA_DIR, then the installed share/npf folder, then the source tree's data/ folder.
#pragma once

#include <string>

namespace npf {

// The full path of `relative` (e.g. "ior/Cu.eta.spd"), or "" when no data folder has it.
std::string find_data_file(const std::string& relative);

}  // namespace npf
