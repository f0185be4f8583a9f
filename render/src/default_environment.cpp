#include <npf/render/default_environment.h>

#include <npf/core/error.h>

#include <filesystem>

// Set by render/CMakeLists.txt: the shipped map in the source tree, in the configured install
// prefix, and relative to the installed executables' folder.
#if !defined(NPF_ENVMAP_SOURCE) || !defined(NPF_ENVMAP_INSTALLED) || !defined(NPF_ENVMAP_FROM_BINDIR)
#error "render/CMakeLists.txt defines the shipped environment map's locations"
#endif

namespace npf::render {

namespace fs = std::filesystem;

std::vector<std::string> shipped_environment_map_candidates() {
    std::vector<std::string> out;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec && !exe.empty()) out.push_back((exe.parent_path() / NPF_ENVMAP_FROM_BINDIR).lexically_normal().string());
    out.emplace_back(NPF_ENVMAP_SOURCE);
    out.emplace_back(NPF_ENVMAP_INSTALLED);
    return out;
}

std::string default_environment_map_path() {
    const std::vector<std::string> candidates = shipped_environment_map_candidates();
    std::string looked;
    for (const std::string& c : candidates) {
        std::error_code ec;
        if (fs::is_regular_file(c, ec)) return c;
        looked += (looked.empty() ? "'" : ", '") + c + "'";
    }
    throw Error("environment map", "none given (--env) and the shipped map is not in " + looked);
}

}  // namespace npf::render
