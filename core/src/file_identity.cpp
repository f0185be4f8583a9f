#include <npf/core/file_identity.h>

#include <npf/core/error.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <optional>
#include <utility>

#include <sys/stat.h>
#include <unistd.h>

namespace npf {

namespace {

struct Identity {
    dev_t device = 0;
    ino_t inode = 0;
    std::string entry;  // for a file not there yet: its name in that folder
    bool shared = false;  // a device or FIFO: may be used more than once
};

bool operator==(const Identity& a, const Identity& b) {
    return a.device == b.device && a.inode == b.inode && a.entry == b.entry;
}

std::pair<std::string, std::string> split(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return {".", path};
    return {slash == 0 ? "/" : path.substr(0, slash), path.substr(slash + 1)};
}

// The identity of `path`, following links; nothing when neither it nor its folder can be
// examined (the command's own checks then report the path).
std::optional<Identity> identity_of(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) == 0) {
        Identity id{st.st_dev, st.st_ino, "", S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)};
        return id;
    }
    // Not there yet (or a dangling link: publishing refuses it; compare the link's own place).
    std::string target = path;
    char resolved[PATH_MAX];
    struct stat lst;
    if (::lstat(path.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode)) {
        const ssize_t n = ::readlink(path.c_str(), resolved, sizeof resolved - 1);
        if (n > 0) {
            resolved[n] = '\0';
            target = resolved[0] == '/' ? std::string(resolved) : split(path).first + "/" + resolved;
        }
    }
    const auto [folder, name] = split(target);
    if (name.empty() || name == "." || name == "..") return std::nullopt;
    if (::stat(folder.c_str(), &st) != 0) return std::nullopt;
    return Identity{st.st_dev, st.st_ino, name, false};
}

}  // namespace

void check_distinct_files(const std::vector<FileUse>& uses) {
    std::vector<std::pair<const FileUse*, Identity>> seen;
    for (const FileUse& use : uses) {
        if (use.path.empty() || use.path == "-") continue;
        const std::optional<Identity> id = identity_of(use.path);
        if (!id || id->shared) continue;
        for (const auto& [earlier, other] : seen) {
            if (!(other == *id) || (!use.output && !earlier->output)) continue;  // two inputs may be one file
            const std::string same = earlier->path == use.path ? "is named twice" : "is the same file as " + earlier->path;
            const std::string as = " (" + earlier->role + " and " + use.role + ")";
            const std::string why = earlier->output && use.output ? ": one output would replace the other"
                                                                  : ": the output would replace an input";
            throw Error(use.path, same + as + why);
        }
        seen.emplace_back(&use, *id);
    }
}

}  // namespace npf
