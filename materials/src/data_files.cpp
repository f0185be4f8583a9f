#include <npf/materials/data_files.h>

#include <cstdlib>
#include <sys/stat.h>

namespace npf {

std::string find_data_file(const std::string& relative) {
    const char* env = std::getenv("NPF_DATA_DIR");
    const std::string candidates[] = {env && *env ? std::string(env) : std::string(), NPF_INSTALLED_DATA_DIR,
                                      NPF_SOURCE_DATA_DIR};
    for (const std::string& dir : candidates) {
        if (dir.empty()) continue;
        const std::string path = dir + "/" + relative;
        struct stat st;
        if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) return path;
    }
    return "";
}

}  // namespace npf
