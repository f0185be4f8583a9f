#include <npf/core/owned_folder.h>

#include <npf/core/error.h>
#include <npf/core/file_kind.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace npf {

namespace {

std::string system_message(int e) { return std::strerror(e); }

// One name inside a folder: no slash, not "." or "..".
void check_entry_name(const std::string& folder, const std::string& name) {
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos || name.find('\0') != std::string::npos)
        throw Error(folder, "'" + name + "' is not a name inside the folder");
}

bool write_all(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        data += n;
        size -= std::size_t(n);
    }
    return true;
}

// Deep enough for anything a tool leaves in its own folder; a deeper tree was planted.
constexpr int kMaxClearDepth = 64;

// Empties the folder open at `fd` (named `shown` in messages); the entries are listed first, then
// removed: unlinkat for files and links (a link goes, its target stays), and folders opened with
// O_NOFOLLOW, emptied and removed.
void clear_entries(int fd, const std::string& shown, const std::string& owner, int depth) {
    if (depth > kMaxClearDepth) throw Error(shown, "is nested too deep to be emptied by " + owner + ": remove it");
    const int listing = ::fcntl(fd, F_DUPFD_CLOEXEC, 0);
    DIR* dir = listing >= 0 ? ::fdopendir(listing) : nullptr;
    if (!dir) {
        const int e = errno;
        if (listing >= 0) ::close(listing);
        throw Error(shown, "cannot list the folder to empty it: " + system_message(e));
    }
    ::rewinddir(dir);  // the duplicate shares its position with `fd`
    std::vector<std::string> names;
    while (const dirent* e = ::readdir(dir)) {
        const std::string name = e->d_name;
        if (name != "." && name != "..") names.push_back(name);
    }
    ::closedir(dir);
    for (const std::string& name : names) {
        const std::string entry = shown + "/" + name;
        if (::unlinkat(fd, name.c_str(), 0) == 0 || errno == ENOENT) continue;
        if (errno != EISDIR && errno != EPERM) throw Error(entry, "cannot remove it to empty a folder " + owner + " owns: " + system_message(errno));
        const int child = ::openat(fd, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        if (child < 0) throw Error(entry, "cannot remove it to empty a folder " + owner + " owns: " + system_message(errno));
        try {
            clear_entries(child, entry, owner, depth + 1);
        } catch (...) {
            ::close(child);
            throw;
        }
        ::close(child);
        if (::unlinkat(fd, name.c_str(), AT_REMOVEDIR) != 0 && errno != ENOENT)
            throw Error(entry, "cannot remove it to empty a folder " + owner + " owns: " + system_message(errno));
    }
}

}  // namespace

OwnedFolder::OwnedFolder(int fd, std::string path, std::string owner) : m_fd(fd), m_path(std::move(path)), m_owner(std::move(owner)) {
    struct stat st {};
    if (::fstat(m_fd, &st) != 0) {
        const int e = errno;
        ::close(m_fd);
        m_fd = -1;
        throw Error(m_path, "cannot examine the folder: " + system_message(e));
    }
    m_device = std::uint64_t(st.st_dev);
    m_inode = std::uint64_t(st.st_ino);
    struct stat via {};
    const std::string proc = "/proc/self/fd/" + std::to_string(m_fd);
    m_proc = ::stat(proc.c_str(), &via) == 0 && via.st_dev == st.st_dev && via.st_ino == st.st_ino;
    while (m_path.size() > 1 && m_path.back() == '/') m_path.pop_back();
}

OwnedFolder::OwnedFolder(OwnedFolder&& other) noexcept
    : m_fd(std::exchange(other.m_fd, -1)), m_path(std::move(other.m_path)), m_owner(std::move(other.m_owner)),
      m_device(other.m_device), m_inode(other.m_inode), m_proc(other.m_proc) {}

OwnedFolder& OwnedFolder::operator=(OwnedFolder&& other) noexcept {
    if (this != &other) {
        if (m_fd >= 0) ::close(m_fd);
        m_fd = std::exchange(other.m_fd, -1);
        m_path = std::move(other.m_path);
        m_owner = std::move(other.m_owner);
        m_device = other.m_device;
        m_inode = other.m_inode;
        m_proc = other.m_proc;
    }
    return *this;
}

OwnedFolder::~OwnedFolder() {
    if (m_fd >= 0) ::close(m_fd);
}

OwnedFolder OwnedFolder::user_folder(const std::string& path, const std::string& owner, bool create) {
    if (create) {
        // The user's choice of place: links on the way are followed, as for -o.
        std::error_code ec;
        std::filesystem::create_directories(path, ec);
        if (ec) throw Error(path, "cannot create the folder: " + ec.message());
    }
    const int fd = ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw Error(path, "cannot open the folder: " + system_message(errno));
    return OwnedFolder(fd, path, owner);
}

OwnedFolder OwnedFolder::reopen(const std::string& path, std::uint64_t device, std::uint64_t inode, const std::string& owner) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0) throw Error(path, "cannot open the folder " + owner + " made: " + system_message(errno));
    OwnedFolder folder(fd, path, owner);
    if (folder.m_device != device || folder.m_inode != inode)
        throw Error(path, "is not the folder " + owner + " made (another was put in its place): not used");
    return folder;
}

void OwnedFolder::refuse(const std::string& name, const char* kind) const {
    const std::string entry = path_of(name);
    struct stat st {};
    if (::fstatat(m_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0)
        throw Error(entry, "cannot examine it: " + system_message(errno));
    if (S_ISLNK(st.st_mode)) {
        std::vector<char> to(4096);
        const ssize_t n = ::readlinkat(m_fd, name.c_str(), to.data(), to.size() - 1);
        const std::string target = n > 0 ? std::string(to.data(), std::size_t(n)) : "?";
        throw Error(entry, "is a symbolic link (to " + target + "): a " + kind + " " + m_owner + " owns is never followed; remove it");
    }
    throw Error(entry, "is " + file_kind(st.st_mode) + " where " + m_owner + " keeps a " + kind + " of its own: not used; remove it");
}

OwnedFolder OwnedFolder::owned_child(const std::string& name, mode_t mode) const {
    check_entry_name(m_path, name);
    const int made = ::mkdirat(m_fd, name.c_str(), mode) == 0 ? 0 : errno;
    const int fd = ::openat(m_fd, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd >= 0) return OwnedFolder(fd, path_of(name), m_owner);
    const int e = errno;
    if (e == ELOOP || e == ENOTDIR) refuse(name, "folder");
    if (made != 0 && made != EEXIST) throw Error(path_of(name), "cannot create the folder: " + system_message(made));
    throw Error(path_of(name), "cannot open the folder: " + system_message(e));
}

bool OwnedFolder::check_owned_child(const std::string& name) const {
    check_entry_name(m_path, name);
    struct stat st {};
    if (::fstatat(m_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) {
        if (errno == ENOENT) return false;
        throw Error(path_of(name), "cannot examine it: " + system_message(errno));
    }
    if (!S_ISDIR(st.st_mode)) refuse(name, "folder");
    return true;
}

std::string OwnedFolder::through(const std::string& name) const {
    return m_proc ? "/proc/self/fd/" + std::to_string(m_fd) + "/" + name : path_of(name);
}

std::string OwnedFolder::shown(const std::string& text) const {
    if (!m_proc) return text;
    const std::string prefix = "/proc/self/fd/" + std::to_string(m_fd);
    std::string out;
    std::size_t from = 0;
    for (std::size_t at; (at = text.find(prefix, from)) != std::string::npos;) {
        const std::size_t end = at + prefix.size();
        const bool whole = end == text.size() || !std::isdigit(static_cast<unsigned char>(text[end]));
        out.append(text, from, at - from).append(whole ? m_path : prefix);
        from = end;
    }
    return out.append(text, from, std::string::npos);
}

void OwnedFolder::clear() const { clear_entries(m_fd, m_path, m_owner, 0); }

int OwnedFolder::create_file(const std::string& name, mode_t mode) const {
    check_entry_name(m_path, name);
    const int fd = ::openat(m_fd, name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, mode);
    if (fd >= 0) return fd;
    const int e = errno;
    struct stat st {};
    if (e == EEXIST && ::fstatat(m_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISLNK(st.st_mode)) refuse(name, "file");
    if (e == EEXIST) throw Error(path_of(name), "is already there, though " + m_owner + " emptied the folder: something else writes into it");
    throw Error(path_of(name), "cannot create: " + system_message(e));
}

void OwnedFolder::write_new_file(const std::string& name, const std::string& text) const {
    const int fd = create_file(name, 0644);
    const bool written = write_all(fd, text.data(), text.size());
    const int e = errno;
    if (::close(fd) != 0 || !written) throw Error(path_of(name), "cannot write: " + system_message(written ? errno : e));
}

int OwnedFolder::open_file(const std::string& name, bool create) const {
    check_entry_name(m_path, name);
    const int flags = O_RDWR | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC | (create ? O_CREAT : 0);
    const int fd = ::openat(m_fd, name.c_str(), flags, 0644);
    if (fd < 0) {
        const int e = errno;
        if (e == ELOOP) refuse(name, "file");
        throw Error(path_of(name), (create ? "cannot create: " : "cannot open: ") + system_message(e));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        refuse(name, "file");
    }
    return fd;
}

std::string OwnedFolder::read_text(const std::string& name, const std::string& what, const TextBounds& bounds) const {
    check_entry_name(m_path, name);
    const int fd = ::openat(m_fd, name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        const int e = errno;
        if (e == ELOOP) refuse(name, "file");
        throw Error(path_of(name), e == ENOENT ? std::string("cannot open: file not found") : "cannot open: " + system_message(e));
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        refuse(name, "file");
    }
    try {
        std::string text = read_text_file(fd, path_of(name), what, bounds);
        ::close(fd);
        return text;
    } catch (...) {
        ::close(fd);
        throw;
    }
}

bool OwnedFolder::has_regular_file(const std::string& name) const {
    struct stat st {};
    return ::fstatat(m_fd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(st.st_mode);
}

}  // namespace npf
