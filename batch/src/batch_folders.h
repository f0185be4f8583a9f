// The places a batch run works in (private to npf_batch): the output folder (the user's: a link
// to it is followed), and the batch's own, never reached through a link (owned_folder.h):
// `.npf-batch`, the shard's lock and stage folder (mode 0700: nobody else plants anything in
// it), `renders/` when first needed.
#pragma once

#include <npf/batch/runner.h>
#include <npf/core/owned_folder.h>

#include <optional>
#include <string>

namespace npf::batch::detail {

// The tool named in messages about the places it owns.
inline constexpr const char* kOwner = "npf batch";

// "shard-K-of-N": the shard's stage folder, lock and summary suffix.
std::string shard_tag(const Shard& s);

// Holds an exclusive lock on a file for the lifetime of the object (released by the kernel if
// the process dies). The file is the batch's own: made in its work folder, never through a link.
class FileLock {
public:
    FileLock(const OwnedFolder& folder, const std::string& name);
    ~FileLock();
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;

private:
    int m_fd = -1;
};

class BatchFolders {
public:
    // Takes the shard's lock and empties its stage (what a killed run left).
    BatchFolders(const std::string& output_dir, const Shard& shard);
    const OwnedFolder& stage() const { return m_stage; }
    // Refuses a link or a file at `renders` before any work (it is made when first needed).
    void check_renders() const { m_output.check_owned_child("renders"); }
    const OwnedFolder& renders();

private:
    OwnedFolder m_output, m_work;
    FileLock m_lock;
    OwnedFolder m_stage;
    std::optional<OwnedFolder> m_renders;
};

std::string file_name(const std::string& path);

// The staged file `name` to its place `to`, by the rules every npf output follows (atomic_file.h):
// at an output's name a link is followed, a FIFO written through, a folder refused, the bytes
// synced before the name changes; a validation render (`render`) is the batch's own file in its
// own `renders/` folder, where a link is refused.
void publish_finished(BatchFolders& folders, const std::string& name, const std::string& to, bool render);

}  // namespace npf::batch::detail
