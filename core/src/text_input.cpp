#include <npf/core/text_input.h>

#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace npf {

namespace {

std::string bytes_text(std::uint64_t n) {
    if (n >= (std::uint64_t(1) << 30) && n % (std::uint64_t(1) << 30) == 0) return std::to_string(n >> 30) + " GiB";
    if (n >= (std::uint64_t(1) << 20) && n % (std::uint64_t(1) << 20) == 0) return std::to_string(n >> 20) + " MiB";
    if (n >= (std::uint64_t(1) << 10) && n % (std::uint64_t(1) << 10) == 0) return std::to_string(n >> 10) + " KiB";
    return std::to_string(n) + " bytes";
}

[[noreturn]] void too_large(const std::string& name, const std::string& what, std::uint64_t cap) {
    throw Error(name, "larger than the " + bytes_text(cap) + " " + what + " may hold: not read");
}

[[noreturn]] void line_too_long(const std::string& name, std::size_t line, std::size_t cap) {
    throw Error(name + ":" + std::to_string(line), "a line longer than " + bytes_text(cap) + ": not a text file of this kind");
}

[[noreturn]] void nul_byte(const std::string& name, std::size_t line) {
    throw Error(name + ":" + std::to_string(line), "holds a NUL byte: not a text file");
}

}  // namespace

LineReader::LineReader(int fd, std::string name, const TextBounds& bounds)
    : m_fd(fd), m_name(std::move(name)), m_bounds(bounds) {}

LineReader::LineReader(const std::string& path, const std::string& what, const TextBounds& bounds)
    : m_name(path), m_bounds(bounds) {
    if (require_regular_file(path, what) > bounds.max_bytes) too_large(path, what, bounds.max_bytes);
    m_fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (m_fd < 0) throw Error(path, std::string("cannot open: ") + std::strerror(errno));
    m_owned = true;
}

LineReader::~LineReader() {
    if (m_owned && m_fd >= 0) ::close(m_fd);
}

// Appends one block to the buffer; false at the end of the input.
bool LineReader::fill() {
    if (m_eof) return false;
    if (m_start > 0) {
        m_buffer.erase(0, m_start);
        m_start = 0;
    }
    constexpr std::size_t kBlock = std::size_t(1) << 16;
    const std::size_t old = m_buffer.size();
    m_buffer.resize(old + kBlock);
    ssize_t n;
    do {
        n = ::read(m_fd, &m_buffer[old], kBlock);
    } while (n < 0 && errno == EINTR);
    if (n < 0) {
        const int e = errno;
        m_buffer.resize(old);
        throw Error(m_name, std::string("read error after line ") + std::to_string(m_line) + ": " + std::strerror(e));
    }
    m_buffer.resize(old + std::size_t(n));
    if (n == 0) {
        m_eof = true;
        return false;
    }
    m_total += std::uint64_t(n);
    if (m_total > m_bounds.max_bytes)
        throw Error(m_name, "more than " + bytes_text(m_bounds.max_bytes) + " of text: the rest is not read");
    return true;
}

bool LineReader::next(std::string& line) {
    std::size_t scanned = m_start;
    for (;;) {
        const std::size_t nl = m_buffer.find('\n', scanned);
        const std::size_t end = nl == std::string::npos ? m_buffer.size() : nl;
        if (std::memchr(m_buffer.data() + scanned, '\0', end - scanned)) nul_byte(m_name, m_line + 1);
        if (end - m_start > m_bounds.max_line_bytes) line_too_long(m_name, m_line + 1, m_bounds.max_line_bytes);
        if (nl != std::string::npos) {
            line.assign(m_buffer, m_start, nl - m_start);
            m_start = nl + 1;
            m_last_newline = true;
            ++m_line;
            return true;
        }
        const std::size_t unread = m_buffer.size() - m_start;
        if (!fill()) {
            if (m_start >= m_buffer.size()) return false;
            line.assign(m_buffer, m_start, std::string::npos);  // a last line without newline
            m_start = m_buffer.size();
            m_last_newline = false;
            ++m_line;
            return true;
        }
        scanned = m_start + unread;  // fill() moved the unread part to the front
    }
}

namespace {

// The lines through LineReader (its checks), the bytes as they are (a last line without a
// newline stays so).
std::string whole_text(LineReader& reader) {
    std::string text, line;
    bool first = true;
    while (reader.next(line)) {
        if (!first) text += '\n';
        text += line;
        first = false;
    }
    if (reader.ended_with_newline()) text += '\n';
    return text;
}

}  // namespace

std::string read_text_file(const std::string& path, const std::string& what, const TextBounds& bounds) {
    LineReader reader(path, what, bounds);
    return whole_text(reader);
}

std::string read_text_file(int fd, const std::string& name, const std::string& what, const TextBounds& bounds) {
    struct stat st {};
    if (::fstat(fd, &st) != 0) throw Error(name, std::string("cannot examine: ") + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw Error(name, "is not a regular file (expected " + what + ")");
    if (std::uint64_t(st.st_size) > bounds.max_bytes) too_large(name, what, bounds.max_bytes);
    if (::lseek(fd, 0, SEEK_SET) < 0) throw Error(name, std::string("cannot read: ") + std::strerror(errno));
    LineReader reader(fd, name, bounds);
    return whole_text(reader);
}

}  // namespace npf
