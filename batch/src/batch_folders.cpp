#include "batch_folders.h"

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <filesystem>

#include <sys/file.h>
#include <unistd.h>

namespace npf::batch::detail {

std::string shard_tag(const Shard& s) { return "shard-" + std::to_string(s.index) + "-of-" + std::to_string(s.count); }

FileLock::FileLock(const OwnedFolder& folder, const std::string& name) : m_fd(folder.open_file(name, true)) {
    if (::flock(m_fd, LOCK_EX | LOCK_NB) != 0) {
        ::close(m_fd);
        throw Error(folder.path_of(name), "another npf batch is running this shard in this output folder (the lock is held)");
    }
}

FileLock::~FileLock() { ::close(m_fd); }

BatchFolders::BatchFolders(const std::string& output_dir, const Shard& shard)
    : m_output(OwnedFolder::user_folder(output_dir, kOwner, true)), m_work(m_output.owned_child(".npf-batch")),
      m_lock(m_work, shard_tag(shard) + ".lock"), m_stage(m_work.owned_child(shard_tag(shard), 0700)) {
    m_stage.clear();  // what a killed run left
}

const OwnedFolder& BatchFolders::renders() {
    if (!m_renders) m_renders.emplace(m_output.owned_child("renders"));
    return *m_renders;
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

void publish_finished(BatchFolders& folders, const std::string& name, const std::string& to, bool render) {
    const OwnedFolder& stage = folders.stage();
    try {
        if (render) {
            const OwnedFolder& renders = folders.renders();
            const std::string file = file_name(to);
            publish_staged_file(stage.through(name), renders.through(file), OutputOptions{kOwner, renders.path_of(file)});
        } else {
            publish_staged_file(stage.through(name), to);
        }
    } catch (const Error& e) {
        throw Error(stage.shown(e.source()), stage.shown(e.problem()));
    }
}

}  // namespace npf::batch::detail
