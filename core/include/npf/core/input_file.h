// The one check every reader makes before opening a file, so that all of them word the
// common problems alike: "<path>: cannot open: file not found", "<path>: is a directory, not
// <what>", "<path>: cannot open: <system message>".
#pragma once

#include <cstdint>
#include <string>

namespace npf {

// Checks that `path` is an existing regular file and returns its size in bytes; `what` names
// the expected kind in messages ("a file", "a MERL file", "a recipe"). Throws npf::Error.
std::uint64_t require_regular_file(const std::string& path, const std::string& what = "a file");

// Throws npf::Error when `path` holds a NUL byte: the system would take the name up to it, another
// file (a name from Python or a configuration can hold one).
void check_file_name(const std::string& path);

}  // namespace npf
