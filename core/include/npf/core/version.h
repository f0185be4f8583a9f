// The npf version, defined once (the project's version in the top CMakeLists.txt): what
// `npf --version` prints and what the batch content hash of every output holds.
#pragma once

namespace npf {

const char* version();

}  // namespace npf
