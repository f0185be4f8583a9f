// Folders a tool owns inside a folder the user named (docs/reliability.md sec. 3): a batch's work
// folder `.npf-batch`, its shard folders, its `renders/`. The user's folder may be reached through
// a symbolic link, as -o's folder is; a place the tool owns never is. Each owned folder is made
// and opened relative to its parent's descriptor (mkdirat; openat with O_NOFOLLOW | O_DIRECTORY),
// held open, and emptied with unlinkat without following anything, so that a link planted there
// (`ln -s ../../victim out/.npf-batch/shard-0-of-1`) is an error naming it and nothing outside the
// user's folder is touched. Files inside are named through the descriptor (/proc/self/fd/N/NAME),
// so that the folder's name swapped for a link while the tool runs redirects nothing.
#pragma once

#include <npf/core/text_input.h>

#include <cstdint>
#include <string>

#include <sys/types.h>

namespace npf {

class OwnedFolder {
public:
    // The user's folder `path`, links followed; created first (with the folders above it) when
    // `create`. `owner` names the tool in messages ("npf batch"). Throws npf::Error naming `path`.
    static OwnedFolder user_folder(const std::string& path, const std::string& owner, bool create);
    // A folder the tool owns, opened again by `path` in another process (a batch's worker): refused
    // unless it is the very folder `device` and `inode` name (the one the first process made), so
    // that a folder swapped in between redirects nothing.
    static OwnedFolder reopen(const std::string& path, std::uint64_t device, std::uint64_t inode, const std::string& owner);

    OwnedFolder(OwnedFolder&& other) noexcept;
    OwnedFolder& operator=(OwnedFolder&& other) noexcept;
    OwnedFolder(const OwnedFolder&) = delete;
    OwnedFolder& operator=(const OwnedFolder&) = delete;
    ~OwnedFolder();

    // The folder `name` inside this one, which the tool owns: made with `mode` when missing, then
    // opened without following a link. A link there, or anything but a folder, is an npf::Error:
    // "PATH: is a symbolic link (to T): a folder OWNER owns is never followed; remove it".
    OwnedFolder owned_child(const std::string& name, mode_t mode = 0777) const;
    // Checks, without making anything, that `name` is missing or a folder owned_child() would
    // open; throws as it would. Returns whether it exists.
    bool check_owned_child(const std::string& name) const;

    const std::string& path() const { return m_path; }  // as messages name it
    std::string path_of(const std::string& name) const { return m_path + "/" + name; }
    int descriptor() const { return m_fd; }
    std::uint64_t device() const { return m_device; }
    std::uint64_t inode() const { return m_inode; }
    // The entry `name` reached through the descriptor (/proc/self/fd/N/NAME), for code that opens
    // files by name (AtomicOutput, OpenImageIO); path_of(name) where /proc is missing.
    std::string through(const std::string& name) const;
    // `text` (a message) with this folder's through() prefix written as path().
    std::string shown(const std::string& text) const;

    // Removes everything inside, folders with their contents, never following a link (a link is
    // removed, not what it points to). Throws npf::Error naming the entry that cannot be removed.
    void clear() const;
    // Creates the file `name` for reading and writing, exclusively: anything already there, a link
    // included, is an error. Returns its descriptor (close-on-exec; the caller closes it).
    int create_file(const std::string& name, mode_t mode = 0666) const;
    // Writes `text` into a file create_file() makes.
    void write_new_file(const std::string& name, const std::string& text) const;
    // Opens the regular file `name` for reading and writing, made when missing if `create` (a lock
    // file); a link or anything but a regular file there is an error. Returns its descriptor.
    int open_file(const std::string& name, bool create) const;
    // The text of the regular file `name` within `bounds` (text_input.h); a link is refused.
    std::string read_text(const std::string& name, const std::string& what, const TextBounds& bounds) const;
    // Whether `name` is a regular file here (a link is not).
    bool has_regular_file(const std::string& name) const;

private:
    OwnedFolder(int fd, std::string path, std::string owner);
    [[noreturn]] void refuse(const std::string& name, const char* kind) const;

    int m_fd = -1;
    std::string m_path, m_owner;
    std::uint64_t m_device = 0, m_inode = 0;
    bool m_proc = false;  // /proc/self/fd/N reaches this folder
};

}  // namespace npf
