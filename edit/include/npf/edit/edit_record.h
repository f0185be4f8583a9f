// What an edit did, for the tool's output and the file's history (docs/editing.md).
#pragma once

#include <string>
#include <vector>

namespace npf::edit {

struct EditRecord {
    // One line: the edit and what it measured ("ndf transform M = ...; D projected area ...").
    std::string summary;
    // Things the user should know (albedo above 1, colours clamped, a spectral range extended);
    // printed on stderr by `npf edit` and kept in the history.
    std::vector<std::string> warnings;
};

}  // namespace npf::edit
