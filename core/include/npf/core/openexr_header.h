// A bounded look at an OpenEXR file's headers before any library opens it. OpenEXR allocates
// what a header claims (an attribute of 1.8 GB in a 40 KB file, found by fuzzing; a data window
// of 2^31 lines gives an offset table of as many entries) before anything npf could check, so
// every npf reader of OpenEXR files (factor textures, scene images) first walks the headers
// here: each attribute must fit in the file and have its type's size, channel lists must end
// where their size says and hold known pixel types, each part's data window must be non-empty
// and at most `max_pixels` pixels, and the chunk offset tables must fit in the file.
#pragma once

#include <cstdint>
#include <string>

namespace npf {

// The problem with the headers, or "" when there is none. A file without the OpenEXR magic
// number is "not an OpenEXR file". Never throws.
std::string openexr_header_problem(const std::string& path, std::uint64_t max_pixels);
// The same for the first `head_size` bytes of a file of `file_size` bytes (the headers must end
// within the head; the offset tables are checked against the file size), e.g. a file in memory.
std::string openexr_header_problem(const std::uint8_t* head, std::size_t head_size, std::uint64_t file_size,
                                   std::uint64_t max_pixels);
// The same, as an npf::Error naming `path`.
void check_openexr_header(const std::string& path, std::uint64_t max_pixels);

}  // namespace npf
