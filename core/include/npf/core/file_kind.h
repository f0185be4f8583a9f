// What a file system entry is, for messages: "a regular file", "a folder", "a FIFO", ...
#pragma once

#include <sys/types.h>

#include <string>

namespace npf {

// From a stat's st_mode; "a special file" for a type without a name here.
std::string file_kind(mode_t mode);

}  // namespace npf
