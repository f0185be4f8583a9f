// Outputs checked against each other and the inputs before any work (docs/reliability.md, sec. 1):
// two names are the same file when they reach the same inode, whether through a symbolic link, a
// hard link, "./", ".." or another spelling, so that `npf render m.exr -o m.exr` cannot replace
// the material with its render and `-o x --png x` cannot lose the EXR.
#pragma once

#include <string>
#include <vector>

namespace npf {

struct FileUse {
    std::string path;
    std::string role;     // for messages: "the input", "--png", "-o"
    bool output = false;
};

// Throws npf::Error naming the later of two uses when an output is the same file as another
// output or as an input ("out.exr: is the same file as the input m.exr: it would be replaced").
// An output that does not exist yet is the same as another use when both name the same entry of
// the same folder (the folder compared by identity, a link at the name followed as publishing
// follows it). Character devices and FIFOs (/dev/null, a pipe) may appear more than once: they
// are written through, never replaced. Empty paths and "-" (standard streams) are skipped.
void check_distinct_files(const std::vector<FileUse>& uses);

}  // namespace npf
