// What one edit run does, from a recipe and flags: the steps in order (the recipe's, then the
// flags' in the order given) and the options, checked before any work. `npf edit` and the Python
// package (`npf.edit`) both build their runs here, so that the same flags mean the same edit.
#pragma once

#include <npf/edit/edit_step.h>
#include <npf/edit/recipe.h>

#include <string>
#include <utility>
#include <vector>

namespace npf::edit {

// The flags an edit run takes besides the commands' own (-o, --recipe, --dry-run, --help):
// every edit kind's flags, then the run's options. `takes_value` false: a switch.
struct EditRunFlag {
    std::string name;
    bool takes_value = true;
    std::string help;
};
const std::vector<EditRunFlag>& edit_run_flags();

struct EditRequest {
    std::vector<EditStep> steps;
    EditOptions options;
};

// `recipe_path` empty: none. `flags` in the order given, each with its text ("" for a switch);
// every one must be in edit_run_flags(). Throws npf::Error naming the flag, the recipe line or
// "edit" (no steps at all), as npf edit reports them.
EditRequest edit_request(const std::string& recipe_path, const std::vector<std::pair<std::string, std::string>>& flags);

// Edits work on fitted materials only: any other material file (a measurement, a recipe) is
// refused by name, with the way to convert it; errors of a step's own file name the step's
// origin (`origin`, empty for the input). A file that is missing, not regular, too short or an
// OpenEXR file is left to the factor texture reader, whose messages say more.
void require_npf_texture(const std::string& path, const std::string& origin);
// The input and every file the steps read (the diffuse and specular colour sources).
void require_npf_textures(const std::string& input, const EditRequest& request);

}  // namespace npf::edit
