#include "own_files.h"

#include <npf/core/atomic_file.h>
#include <npf/core/text.h>

#include <algorithm>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace npf::batch {

namespace fs = std::filesystem;

namespace detail {

namespace {

bool starts_with(const std::string& s, const std::string& p) { return s.size() >= p.size() && s.compare(0, p.size(), p) == 0; }

// A path with its symbolic links resolved as far as it exists, so that a folder reached two ways
// is recognised (the lexical path when that fails).
fs::path resolved(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::path(path), ec);
    return ec ? fs::path(path).lexically_normal() : p;
}

bool is_under(const fs::path& p, const fs::path& dir) {
    auto d = dir.begin(), q = p.begin();
    for (; d != dir.end(); ++d, ++q) {
        if (q == p.end() || *q != *d) return false;
    }
    return q != p.end();
}

// Whether `file` is `naming` with one name put in for every {name}.
bool fits_naming(const std::string& file, const std::string& naming) {
    std::size_t fixed = naming.size(), count = 0;
    for (std::size_t at = naming.find("{name}"); at != std::string::npos; at = naming.find("{name}", at + 6)) fixed -= 6, ++count;
    if (count == 0 || file.size() <= fixed || (file.size() - fixed) % count != 0) return false;
    const std::size_t first = naming.find("{name}");
    const std::string name = file.substr(first, (file.size() - fixed) / count);
    return apply_naming(naming, name) == file;
}

// A summary by its first bytes (summary_json and summary_markdown begin so), wherever it was
// written: --summary, shard summaries, merged ones.
bool is_summary_file(const fs::path& p) {
    const std::string ext = p.extension().string();
    if (ext != ".json" && ext != ".md") return false;
    // A regular file only, opened without waiting: a FIFO named x.json would hold the open.
    const int fd = ::open(p.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return false;
    struct stat st {};
    char head[64] = {};
    ssize_t got = -1;
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) got = ::read(fd, head, sizeof head);
    ::close(fd);
    std::string text(head, got > 0 ? std::size_t(got) : 0);
    text.erase(std::remove_if(text.begin(), text.end(), [](char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }),
               text.end());
    return starts_with(text, "{\"npf_batch_summary\"") || starts_with(text, "#npfbatchsummary");
}

}  // namespace

std::string apply_naming(const std::string& naming, const std::string& name) {
    std::string out;
    std::size_t from = 0;
    for (std::size_t at; (at = naming.find("{name}", from)) != std::string::npos; from = at + 6) {
        out.append(naming, from, at - from).append(name);
    }
    return out.append(naming, from, std::string::npos);
}

OwnFiles::OwnFiles(const BatchConfig& c)
    : m_out(resolved(c.output_dir)), m_naming(c.naming),
      m_summary(resolved(c.summary.empty() ? (fs::path(c.output_dir) / "batch-summary").string() : c.summary)),
      m_config(c.path.empty() ? fs::path() : resolved(c.path)) {}

std::string OwnFiles::kind(const std::string& path) const {
    // The folder resolved, the name kept: a link at an output's name is still an output.
    const fs::path given = fs::path(path).lexically_normal();
    const fs::path p = resolved(given.parent_path().string()) / given.filename();
    if (is_under(p, m_out / ".npf-batch")) return "in the batch's work folder (.npf-batch)";
    if (is_under(p, m_out / "renders")) return "a validation render of the batch";
    const std::string file = p.filename().string();
    if (p.parent_path() == m_out && fits_naming(file, m_naming)) return "an output of the batch (naming '" + m_naming + "')";
    const std::size_t tmp = file.rfind(kTemporarySuffix);
    if (p.parent_path() == m_out && tmp != std::string::npos && is_temporary_of(file, file.substr(0, tmp)) &&
        fits_naming(file.substr(0, tmp), m_naming))
        return "an unfinished output of the batch (a temporary file left by a killed run)";
    const std::string base = m_summary.filename().string();
    if (p.parent_path() == m_summary.parent_path() &&
        (file == base + ".json" || file == base + ".md" ||
         (starts_with(file, base + ".shard-") && (ends_with(file, ".json") || ends_with(file, ".md")))))
        return "the batch's summary";
    if (!m_config.empty() && (p == m_config || resolved(path) == m_config)) return "the batch's configuration";
    if (is_summary_file(p)) return "an npf batch summary";
    return "";
}

}  // namespace detail

std::string batch_file_kind(const BatchConfig& config, const std::string& path) { return detail::OwnFiles(config).kind(path); }

}  // namespace npf::batch
