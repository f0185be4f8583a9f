#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

namespace npf {

namespace {

std::string system_message(int e) { return std::strerror(e); }

// Everything up to and including the last '/' ("" for a bare name): where a temporary goes.
std::string folder_prefix(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string folder_for_messages(const std::string& prefix) {
    if (prefix.empty()) return ".";
    return prefix.size() == 1 ? prefix : prefix.substr(0, prefix.size() - 1);
}

// 16 hex digits from the kernel's random source: a name nobody can plant a link at beforehand.
std::string random_hex(const std::string& path) {
    unsigned char bytes[8];
    std::size_t got = 0;
    while (got < sizeof bytes) {
        const ssize_t n = ::getrandom(bytes + got, sizeof bytes - got, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        got += std::size_t(n);
    }
    if (got < sizeof bytes) {  // a kernel without getrandom(2)
        const int fd = ::open("/dev/urandom", O_RDONLY | O_CLOEXEC);
        while (fd >= 0 && got < sizeof bytes) {
            const ssize_t n = ::read(fd, bytes + got, sizeof bytes - got);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) break;
            got += std::size_t(n);
        }
        if (fd >= 0) ::close(fd);
    }
    if (got < sizeof bytes) throw Error(path, "cannot create output: no random bytes for a temporary name");
    static const char digits[] = "0123456789abcdef";
    std::string hex;
    for (unsigned char b : bytes) hex += {digits[b >> 4], digits[b & 15]};
    return hex;
}

// Best effort: makes a rename durable. Some file systems refuse fsync on a folder; the output
// is in place by then, so a failure here is not reported.
void sync_folder(const std::string& prefix) {
    const std::string folder = prefix.empty() ? "." : prefix;
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

std::string temporary_folder_prefix() {
    const char* t = std::getenv("TMPDIR");
    std::string dir = (t && t[0] == '/') ? t : "/tmp";
    if (dir.back() != '/') dir += '/';
    return dir;
}

// Where the link `path` points, as written in it ("?" when it cannot be read).
std::string link_target(const std::string& path) {
    std::vector<char> to(4096);
    const ssize_t n = ::readlink(path.c_str(), to.data(), to.size() - 1);
    return n > 0 ? std::string(to.data(), std::size_t(n)) : "?";
}

// A temporary's name before its random part: the output's own name capped below NAME_MAX.
std::string temporary_stem(const std::string& name) { return name.substr(0, 200) + kTemporarySuffix; }

// Writes all of `size` bytes to `fd` (a device or FIFO); returns 0 or the errno.
int write_all(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return errno;
        if (n == 0) return EIO;
        data += n;
        size -= std::size_t(n);
    }
    return 0;
}

}  // namespace

void write_file_atomically(const std::string& path, const void* data, std::size_t size, const OutputOptions& options) {
    AtomicOutput out(path, options);
    if (out.write_at(0, data, size) != size) out.fail("cannot write", "short write");
    out.commit();
}

void check_output_path(const std::string& path, const OutputOptions& options) {
    // Examining the destination and creating (then removing) the temporary is the check.
    AtomicOutput probe(path, options);
}

AtomicOutput::AtomicOutput(std::string path, const OutputOptions& options)
    : m_final(std::move(path)), m_shown(options.shown_as.empty() ? m_final : options.shown_as) {
    if (m_final.empty()) throw Error("", "the output file name is empty");
    if (m_final.back() == '/') throw Error(m_shown, "ends in '/': names a folder, not a file");
    check_file_name(m_final);

    // What is there decides how it is published.
    struct stat st {};
    bool link = false;
    if (::lstat(m_final.c_str(), &st) != 0) {
        if (errno != ENOENT) throw Error(m_shown, "cannot create output: " + system_message(errno));
        st.st_mode = S_IFREG;  // nothing there yet: created like a regular file
    } else if (!options.owned_by.empty() && !S_ISREG(st.st_mode)) {
        // A tool's own file: nothing the user put there is followed or written through.
        if (!S_ISLNK(st.st_mode))
            throw Error(m_shown, "is not a regular file where " + options.owned_by + " keeps a file of its own: not used; remove it");
        throw Error(m_shown, "is a symbolic link (to " + link_target(m_final) + "): a file " + options.owned_by +
                                 " owns is never followed; remove it");
    } else if (S_ISLNK(st.st_mode)) {
        // A link is followed, as cp and the shell's '>' do: the link stays, its target is the
        // output. A dangling one is refused (cp does too): its target may be anywhere.
        link = true;
        if (::stat(m_final.c_str(), &st) != 0) {
            const int e = errno;
            if (e != ENOENT) throw Error(m_shown, "cannot follow the symbolic link: " + system_message(e));
            throw Error(m_shown, "is a symbolic link to " + link_target(m_final) +
                                     ", which does not exist: not followed (remove the link or create its target)");
        }
    }
    std::string prefix;
    if (S_ISREG(st.st_mode)) {
        m_target = m_final;
        if (link) {
            char* resolved = ::realpath(m_final.c_str(), nullptr);
            if (!resolved) throw Error(m_shown, "cannot follow the symbolic link: " + system_message(errno));
            m_target = resolved;
            std::free(resolved);
        }
        prefix = folder_prefix(m_target);
    } else if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
        // /dev/null, /dev/stdout on a terminal, a named pipe: never replaced, the finished bytes
        // are written through. The temporary goes to the system's temporary folder.
        if (::access(m_final.c_str(), W_OK) != 0) throw Error(m_shown, "cannot write: " + system_message(errno));
        m_write_through = true;
        prefix = temporary_folder_prefix();
    } else {
        const std::string is = link ? "is a symbolic link to " : "is ";
        if (S_ISDIR(st.st_mode)) throw Error(m_shown, is + "a directory, not a file: cannot move an output over it");
        const char* kind = S_ISBLK(st.st_mode) ? "a block device" : S_ISSOCK(st.st_mode) ? "a socket" : "a special file";
        throw Error(m_shown, is + kind + ": not written (npf writes regular files, and writes through to character "
                                          "devices such as /dev/null and to FIFOs)");
    }

    // The temporary: created here, never there before (O_EXCL), never through a link
    // (O_NOFOLLOW), under a name nobody could guess. Same folder as the target, so that rename
    // is atomic; the name starts with the output's own (capped below NAME_MAX) so that a
    // leftover after kill -9 is recognisable.
    const std::size_t slash = m_target.find_last_of('/');
    const std::string name = m_write_through ? std::string("npf") : m_target.substr(slash == std::string::npos ? 0 : slash + 1);
    const std::string stem = prefix + temporary_stem(name);
    const mode_t mode = m_write_through ? 0600 : 0666;  // a copy in /tmp is nobody else's business
    for (int attempt = 0; attempt < 16 && m_fd < 0; ++attempt) {
        std::string candidate = stem + random_hex(m_shown);
        m_fd = ::open(candidate.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, mode);
        if (m_fd >= 0) {
            m_temporary = std::move(candidate);
        } else if (errno != EEXIST) {
            throw Error(m_shown, "cannot create output in " + folder_for_messages(prefix) + ": " + system_message(errno));
        }
    }
    if (m_fd < 0) throw Error(m_shown, "cannot create output in " + folder_for_messages(prefix) + ": no free temporary name");
}

AtomicOutput::~AtomicOutput() {
    if (m_fd >= 0) ::close(m_fd);
    // Written through: the copy in the temporary folder has served; renamed: nothing to remove.
    if (!m_committed || m_write_through) ::unlink(m_temporary.c_str());
}

std::size_t AtomicOutput::write_at(std::uint64_t offset, const void* data, std::size_t size) noexcept {
    if (m_write_errno.load() != 0) return 0;  // the file is already bad: fail fast
    if (m_fd < 0 || m_finished) {
        int none = 0;
        m_write_errno.compare_exchange_strong(none, EBADF);
        return 0;
    }
    const char* p = static_cast<const char*>(data);
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::pwrite(m_fd, p + done, size - done, off_t(offset + done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            int none = 0;
            m_write_errno.compare_exchange_strong(none, n < 0 ? errno : EIO);
            break;
        }
        done += std::size_t(n);
    }
    const std::uint64_t end = offset + done;
    std::uint64_t seen = m_size.load();
    while (end > seen && !m_size.compare_exchange_weak(seen, end)) {
    }
    return done;
}

std::string AtomicOutput::descriptor_path() const {
    const std::string path = "/proc/self/fd/" + std::to_string(m_fd);
    struct stat via {}, mine {};
    if (m_fd >= 0 && ::stat(path.c_str(), &via) == 0 && ::fstat(m_fd, &mine) == 0 && via.st_ino == mine.st_ino &&
        via.st_dev == mine.st_dev)
        return path;
    return m_temporary;
}

int AtomicOutput::growth_error() const {
    // Writes by name (not through write_at) leave no errno behind; growing the temporary again
    // shows whether the disk is full or a file size limit reached. It is discarded anyway.
    struct stat st {};
    if (m_fd < 0 || ::fstat(m_fd, &st) != 0) return 0;
    static const char zeros[1 << 16] = {};
    std::size_t done = 0;
    while (done < sizeof zeros) {
        const ssize_t n = ::pwrite(m_fd, zeros + done, sizeof zeros - done, off_t(st.st_size) + off_t(done));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return errno;
        if (n == 0) return EIO;
        done += std::size_t(n);
    }
    return 0;
}

void AtomicOutput::fail(const std::string& step, const std::string& detail) const {
    int e = m_write_errno.load();
    if (e == 0) e = growth_error();
    throw Error(m_shown, step + ": " + (e != 0 ? system_message(e) : detail.empty() ? std::string("failed") : detail));
}

void AtomicOutput::finish() {
    if (m_finished) return;
    if (m_write_errno.load() != 0) fail("cannot write", "");
    if (m_fd < 0) throw Error(m_shown, "cannot write: the output is not open");
    if (!m_write_through) {
        // On the disk before it has the final name: a crash after the rename finds it whole.
        if (::fsync(m_fd) != 0) throw Error(m_shown, "cannot write (sync to disk): " + system_message(errno));
        // The name must still be this file: something that swapped it for a link or another
        // file in the meantime does not get it published.
        struct stat mine {}, named {};
        if (::fstat(m_fd, &mine) != 0 || ::lstat(m_temporary.c_str(), &named) != 0 || !S_ISREG(named.st_mode) ||
            mine.st_dev != named.st_dev || mine.st_ino != named.st_ino)
            throw Error(m_shown, "the temporary file " + m_temporary + " was replaced while it was written: not published");
        const int fd = m_fd;
        m_fd = -1;
        if (::close(fd) != 0) throw Error(m_shown, "cannot write (close): " + system_message(errno));
    }
    m_finished = true;
}

void AtomicOutput::commit() {
    if (m_committed) return;
    finish();
    if (!m_write_through) {
        if (::rename(m_temporary.c_str(), m_target.c_str()) != 0)
            throw Error(m_shown, "cannot move the finished output into place: " + system_message(errno));
        m_committed = true;
        sync_folder(folder_prefix(m_target));
        return;
    }
    // Through to the device or FIFO as the user named it (a link such as /dev/stdout included);
    // no O_CREAT and no O_TRUNC: this never makes or empties a file.
    const int out = ::open(m_final.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
    if (out < 0) throw Error(m_shown, "cannot open for writing: " + system_message(errno));
    struct stat st {};
    if (::fstat(out, &st) != 0 || !(S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode))) {
        ::close(out);
        throw Error(m_shown, "is no longer a device or FIFO: not written");
    }
    // To the temporary's end, not size(): a library may have written it by name.
    std::vector<char> buffer(1 << 16);
    int error = 0;
    for (std::uint64_t offset = 0; error == 0;) {
        const ssize_t n = ::pread(m_fd, buffer.data(), buffer.size(), off_t(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) error = errno;
        if (n <= 0) break;
        error = write_all(out, buffer.data(), std::size_t(n));
        offset += std::uint64_t(n);
    }
    if (::close(out) != 0 && error == 0) error = errno;
    if (error != 0) throw Error(m_shown, "cannot write: " + system_message(error));
    m_committed = true;
}

void publish_staged_file(const std::string& staged, const std::string& path, const OutputOptions& options) {
    // First what may throw: nothing between open() and close() below does, so `in` never leaks.
    AtomicOutput out(path, options);
    std::vector<char> buffer(1 << 20);
    // O_NONBLOCK: a FIFO put there cannot hold the open; it is refused below.
    const int in = ::open(staged.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (in < 0) {
        const int e = errno;
        if (e == ELOOP) throw Error(staged, "is a symbolic link, not the finished file: never read through; not published");
        throw Error(staged, "cannot read the finished file: " + system_message(e));
    }
    struct stat st {};
    if (::fstat(in, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(in);
        throw Error(staged, "is not a regular file, not the finished file: not published");
    }
    int error = 0;
    for (std::uint64_t offset = 0;;) {
        const ssize_t n = ::read(in, buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) error = errno;
        if (n <= 0) break;
        if (out.write_at(offset, buffer.data(), std::size_t(n)) != std::size_t(n)) break;  // kept for commit()
        offset += std::uint64_t(n);
    }
    ::close(in);
    if (error != 0) throw Error(staged, "cannot read the finished file: " + system_message(error));
    out.commit();
    ::unlink(staged.c_str());
}

bool is_temporary_of(const std::string& file, const std::string& output) {
    const std::string stem = temporary_stem(output);
    if (file.size() != stem.size() + 16 || file.compare(0, stem.size(), stem) != 0) return false;
    return std::all_of(file.begin() + std::ptrdiff_t(stem.size()), file.end(),
                       [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

void commit_together(std::initializer_list<AtomicOutput*> outputs) {
    // The steps that fail in practice (full disk, a device refusing bytes) before any rename.
    for (AtomicOutput* o : outputs)
        if (o) o->finish();
    for (AtomicOutput* o : outputs)
        if (o && o->writes_through()) o->commit();
    for (AtomicOutput* o : outputs)
        if (o) o->commit();
}

}  // namespace npf
