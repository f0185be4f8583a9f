// Publishing outputs: the one way everything npf writes reaches its destination (docs/reliability.md,
// "1. Publishing outputs").
//
// A regular file (or a name not yet taken) is replaced atomically: the bytes go to a temporary
// file created exclusively beside it (O_EXCL | O_NOFOLLOW, a random name `<name>.tmp-<16 hex>`),
// every write is checked, the file is synced, and only then renamed over the destination; the
// folder is synced after. A crash, a full disk or any error leaves the earlier output untouched and
// removes the temporary. A symbolic link is followed (the link stays, its target is replaced); a
// character device or FIFO (/dev/null, a pipe) is written through, never replaced; a directory,
// block device, socket or dangling link is refused before anything is written. A file a tool owns
// (OutputOptions::owned_by) is stricter: a link at its name is refused, never followed.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>

namespace npf {

// What a writer knows about its destination beyond its path.
struct OutputOptions {
    // Non-empty: the destination is a file that the tool so named ("npf batch") owns, in a folder
    // it owns (a batch's renders, its default summary): a symbolic link at its name is refused,
    // never followed ("PATH: is a symbolic link (to T): a file npf batch owns is never followed;
    // remove it"), and so is anything there but a regular file.
    std::string owned_by;
    // Non-empty: the name messages give the destination, when `path` reaches it another way
    // (through a folder's descriptor, /proc/self/fd/N/NAME: OwnedFolder::through).
    std::string shown_as;
};

// Writes `size` bytes to `path` as above. Throws npf::Error naming `path`.
void write_file_atomically(const std::string& path, const void* data, std::size_t size, const OutputOptions& options = {});

// Throws the npf::Error that publishing to `path` would throw before writing anything: a
// directory or other special file, a dangling link, a folder that is missing or not writable.
// Commands call it first so that a bad -o fails before minutes of work.
void check_output_path(const std::string& path, const OutputOptions& options = {});

// An output being written. The constructor examines the destination and creates the temporary
// (throwing npf::Error naming `path` if either fails); write_at() fills it; commit() publishes it;
// the destructor removes the temporary if commit() never succeeded.
class AtomicOutput {
public:
    explicit AtomicOutput(std::string path, const OutputOptions& options = {});
    ~AtomicOutput();
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;

    // The destination as messages name it (OutputOptions::shown_as, else the path given).
    const std::string& final_path() const { return m_shown; }
    // The temporary's name. Write through write_at() (or AtomicOutputProxy), not by opening this
    // name: the name could be swapped for a link between its creation and a later open (commit()
    // refuses a swapped temporary, but cannot undo a write through the link).
    const std::string& temporary_path() const { return m_temporary; }
    // The temporary under a name that reaches it without going through its folder:
    // /proc/self/fd/N (the temporary's own name where /proc is missing). For libraries that insist
    // on opening a file by name (OpenImageIO's multi-part OpenEXR writer): nothing planted in the
    // folder can redirect it. Such a library's write errors are not seen by write_at(): read the
    // file back before commit().
    std::string descriptor_path() const;
    // True when the destination is a character device or FIFO that commit() writes through.
    bool writes_through() const { return m_write_through; }

    // Writes `size` bytes at `offset` of the temporary. Returns the bytes written: `size`, or
    // fewer after a failure, whose reason is kept (the first one) for commit() and fail(). Never
    // throws: C libraries (libpng, OpenEXR through OpenImageIO) call it. Thread-safe.
    std::size_t write_at(std::uint64_t offset, const void* data, std::size_t size) noexcept;
    std::uint64_t size() const { return m_size.load(); }  // the end of what write_at() wrote

    // Checks that every write succeeded, syncs and closes the temporary (throws npf::Error naming
    // the destination). commit() runs it if it has not run.
    void finish();
    // Publishes: renames the temporary over the destination (then syncs the folder), or writes it
    // through to a device or FIFO. Throws npf::Error naming the destination; the earlier output is
    // untouched unless this succeeds.
    void commit();
    // Throws npf::Error(final_path(), step + ": " + reason): the reason of a failed write_at() if
    // there was one (the system's, e.g. "No space left on device"); else, if the temporary cannot
    // grow by 64 KiB now, why not (a library that wrote by name hit a full disk); else `detail`
    // (the library's own message).
    [[noreturn]] void fail(const std::string& step, const std::string& detail) const;

private:
    int growth_error() const;  // the errno of growing the temporary by 64 KiB, or 0

    std::string m_final;      // as given, for the system calls and writing through
    std::string m_shown;      // for messages
    std::string m_target;     // what the rename replaces: m_final, or a link's resolved target
    std::string m_temporary;
    int m_fd = -1;
    bool m_write_through = false;
    bool m_finished = false;
    bool m_committed = false;
    std::atomic<std::uint64_t> m_size{0};
    std::atomic<int> m_write_errno{0};
};

// Commits several outputs as one: finishes them all, then writes through to devices and FIFOs,
// then renames; the first failure stops it (outputs already published stay so). Null entries are
// skipped. For commands with two outputs (npf render -o X --png Y): a failure in either leaves
// both earlier outputs in place, short of a rename failing after another succeeded.
void commit_together(std::initializer_list<AtomicOutput*> outputs);

// Publishes a finished file written elsewhere (a batch worker's staging folder) to `path` by the
// rules above (and `options`): its bytes are copied into an AtomicOutput for `path` and committed,
// then `staged` is removed. A rename of the staged file would skip them (it replaces a link or a
// FIFO at `path` instead of following or writing through it, and syncs nothing). The staged file
// is the tool's own: a link at its name is refused, never read through. Throws npf::Error naming
// `path` (or `staged` when it cannot be read); the earlier output is then untouched.
void publish_staged_file(const std::string& staged, const std::string& path, const OutputOptions& options = {});

// The name of a temporary AtomicOutput makes for `path` is `path` + this + 16 hex digits: a
// leftover after kill -9 can be told from other files.
inline constexpr const char* kTemporarySuffix = ".tmp-";
// Whether `file` (a file name) is such a temporary of an output named `output` (a file name).
bool is_temporary_of(const std::string& file, const std::string& output);

// An OpenImageIO IOProxy writing into an AtomicOutput, so that OpenImageIO never opens a file by
// name: instantiate as AtomicOutputProxy<OIIO::Filesystem::IOProxy> and pass it to
// ImageOutput::set_ioproxy() before open(). A template so that npf_core does not depend on
// OpenImageIO; only the writers that use it do. The proxy must outlive the ImageOutput.
template <class IOProxy>
class AtomicOutputProxy final : public IOProxy {
public:
    explicit AtomicOutputProxy(AtomicOutput& out) : IOProxy(out.temporary_path(), IOProxy::Write), m_out(out) {}
    const char* proxytype() const override { return "npf-atomic-output"; }
    using IOProxy::write;
    std::size_t write(const void* buf, std::size_t size) override {
        const std::size_t n = m_out.write_at(std::uint64_t(this->m_pos), buf, size);
        this->m_pos += static_cast<decltype(this->m_pos)>(n);
        return n;
    }
    std::size_t pwrite(const void* buf, std::size_t size, std::int64_t offset) override {
        return offset < 0 ? 0 : m_out.write_at(std::uint64_t(offset), buf, size);
    }
    std::size_t size() const override { return std::size_t(m_out.size()); }

private:
    AtomicOutput& m_out;
};

}  // namespace npf
