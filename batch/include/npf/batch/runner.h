// Running a batch: every material of a shard, each converted (fit, compress, optional edits),
// written atomically with its content hash in its metadata, optionally rendered and compared
// with its input; unchanged materials are skipped; a failing material is reported and the
// others go on (docs/batch.md).
#pragma once

#include <npf/batch/config.h>
#include <npf/batch/summary.h>

#include <csignal>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace npf::batch {

// Version of the content hash's recipe: bumped whenever the converter's output for the same
// inputs and settings changes without a change of the npf version, so that outputs redo.
// 2: the settings' lines are the canonical text's, sorted by key (docs/batch.md): every output
// of version 1 is rebuilt once.
inline constexpr int kContentHashVersion = 2;

struct Shard {
    int index = 0, count = 1;  // 0 <= index < count
};
// "K/N" (0 <= K < N <= 100000). Throws npf::Error naming `what`.
Shard parse_shard(const std::string& text, const std::string& what = "--shard");
// The materials (indices into a name-sorted list of `count`) of shard K of N: the indices i with
// i mod N == K. Deterministic, disjoint, and together all of them.
std::vector<std::size_t> shard_members(std::size_t count, const Shard& shard);

// Called before a material is read, with its name and the memory limit of the process it is
// processed in (0: none): the seam through which tests make a material fail the way a broken
// reader can (tests/fault_worker.cpp, docs/batch.md "Failure isolation"). `npf batch` sets none.
using MaterialHook = std::function<void(const std::string& name, std::uint64_t memory_limit)>;

struct BatchOptions {
    Shard shard;
    bool force = false;    // redo every material whatever its hash says
    int threads = 0;       // > 0: overrides every material's `threads`
    // Non-empty: override every material's memory_limit / time_limit (text as in the configuration).
    std::string memory_limit, time_limit;
    // The npf executable: each material that is not up to date is converted in a child process of
    // its own (`EXECUTABLE batch --worker JOB`) under its memory_limit and time_limit, so that a
    // crash, an abort, running out of memory or a hang fails that material only (docs/batch.md
    // "Failure isolation"). Empty: in this process, without isolation or limits (a reader that
    // crashes ends the caller); for library callers that cannot name an npf executable.
    // `npf batch` sets it to itself.
    std::string worker_executable;
    // One line per event ("[2/7] felt: converted in 1.2 s ..."), control characters in names
    // escaped (npf::printable); none when empty.
    std::function<void(const std::string&)> log;
    // Non-null: a stop request (a signal number, set by a signal handler), read between materials
    // and while a worker runs. Once non-zero, the running worker is killed, the stage folder
    // emptied, and run_batch returns with BatchSummary::stopped_by set and the materials done so
    // far (not the one cut short). A material converting in this process is finished first.
    const volatile std::sig_atomic_t* stop = nullptr;
    // Materials processed in this process only (no worker_executable); a worker's is its own
    // (run_batch_worker).
    MaterialHook before_material;
};

// The hash a material's output carries (metadata `batch_hash`): SHA-256 of the hash version,
// the npf version and texture format version, the input file's SHA-256, the settings resolved
// for the source (every field of ConvertSettings but the thread count), and the edit recipe's
// SHA-256 with those of the files it names. `source_isotropic` is the opened source's.
std::string material_hash(const MaterialJob& job, bool source_isotropic);

// Runs the shard's materials in name order, one after another. Temporaries live in <output_dir>/.npf-batch/
// shard-K-of-N/ (cleared when a run of that shard starts and after every material; a lock file,
// .npf-batch/shard-K-of-N.lock, stops two runs of one shard at once); outputs appear under their
// names only when whole (a rename). `.npf-batch`, the shard folder, the lock, the worker's files
// and `renders/` are the batch's own and never reached through a symbolic link (owned_folder.h):
// a link there is an error naming it, and nothing outside the output folder is touched. Throws
// npf::Error only when the batch cannot run at all (output folder, its own folders, lock, outputs
// that are inputs: check_batch_files); a material's failure is in its result.
BatchSummary run_batch(const BatchConfig& config, const BatchOptions& options);

// Throws npf::Error (one line, naming the later file) when an output of the batch (a material's,
// its validation renders, and the summary's SUMMARY_BASE.json and .md when `summary_base` is not
// empty) is the same file as another output or as an input (the configuration included), by
// device and inode, so that symbolic links, hard links and other spellings count
// (npf/core/file_identity.h). Every material of the configuration, whatever the shard.
void check_batch_files(const BatchConfig& config, const std::string& summary_base);

// `npf batch --worker JOB`: converts the one material a job file (written by run_batch) names
// into the stage folder, and writes its result and the list of finished files for the parent to
// move into place. Returns the exit status (0 when it answered; the material's own failure is in
// the answer). Not for people: the job file's format is private to this version.
// `before_material` (tests) runs before the material is read.
int run_batch_worker(const std::string& job_path, const MaterialHook& before_material = {});

// Checks that `dir` is a writable folder, or can be created (the nearest existing folder above
// it is writable); creates it when `create`. Throws npf::Error naming `what` ("summary folder")
// and the folder at fault. For the summary's and output's folders, before any conversion and at --check.
void prepare_folder(const std::string& dir, const std::string& what, bool create);

// The summary's default base name (without .json/.md): config.summary, or
// <output_dir>/batch-summary; "<base>.shard-K-of-N" for shard K of N > 1.
std::string summary_base(const BatchConfig& config, const Shard& shard);

}  // namespace npf::batch
