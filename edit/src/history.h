// The edit history in a model's metadata: one "edit_NNN" entry per step applied (recipe.h).
#pragma once

#include <npf/shading/npf_model.h>

#include <string>

namespace npf::edit::detail {

// The number that the model's next history entry takes: one past the highest there (1 if none),
// so that a file edited twice keeps both histories.
int next_history_number(const NpfModel& model);

// "edit_007" for 7.
std::string history_key(int number);

}  // namespace npf::edit::detail
