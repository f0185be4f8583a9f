#include <npf/core/version.h>

namespace npf {

// NPF_VERSION_STRING is set by core/CMakeLists.txt, the one place it is defined.
const char* version() { return NPF_VERSION_STRING; }

}  // namespace npf
