#include "worker_job.h"

#include <npf/core/error.h>
#include <npf/core/text_input.h>

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace npf::batch::detail {

namespace {

constexpr int kJobVersion = 2;

}  // namespace

std::string job_text(const MaterialJob& job, const MaterialContext& ctx, const std::string& result, const std::string& moves) {
    YAML::Emitter out;
    // Quoted, so that no text reads back as null, a number or a boolean.
    const auto text = [&out](const char* key, const std::string& value) {
        out << YAML::Key << key << YAML::Value << YAML::DoubleQuoted << value;
    };
    out << YAML::BeginMap;
    out << YAML::Key << "npf_batch_worker_job" << YAML::Value << kJobVersion;
    out << YAML::Key << "parent" << YAML::Value << long(::getpid());
    text("name", job.name);
    text("input", job.input);
    text("output", job.output);
    text("origin", job.origin);
    text("stage", ctx.stage->path());
    out << YAML::Key << "stage_device" << YAML::Value << std::to_string(ctx.stage->device());
    out << YAML::Key << "stage_inode" << YAML::Value << std::to_string(ctx.stage->inode());
    out << YAML::Key << "force" << YAML::Value << ctx.force;
    out << YAML::Key << "shard" << YAML::Value << ctx.shard;
    out << YAML::Key << "memory_limit" << YAML::Value << std::to_string(ctx.memory_limit);
    text("result", result);
    text("moves", moves);
    out << YAML::Key << "settings" << YAML::Value << YAML::BeginMap;
    for (const auto& [k, v] : job.settings) {
        out << YAML::Key << k << YAML::Value << YAML::Flow << YAML::BeginSeq;
        out << YAML::DoubleQuoted << v.value << YAML::DoubleQuoted << v.origin;
        out << YAML::EndSeq;
    }
    out << YAML::EndMap << YAML::EndMap;
    return std::string(out.c_str()) + "\n";
}

WorkerJob read_worker_job(const std::string& job_path) {
    const int fd = ::open(job_path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) throw Error(job_path, std::string("cannot open the job: ") + std::strerror(errno));
    std::string text;
    struct stat job {};
    try {
        text = read_text_file(fd, job_path, "an npf batch job", kConfigTextBounds);
        if (::fstat(fd, &job) != 0) throw Error(job_path, std::string("cannot examine the job: ") + std::strerror(errno));
    } catch (...) {
        ::close(fd);
        throw;
    }
    ::close(fd);
    const YAML::Node j = YAML::Load(text);
    if (!j.IsMap() || !j["npf_batch_worker_job"] || j["npf_batch_worker_job"].as<int>() != kJobVersion)
        throw Error(job_path, "not an npf batch job");
    OwnedFolder stage = OwnedFolder::reopen(j["stage"].as<std::string>(), std::stoull(j["stage_device"].as<std::string>()),
                                            std::stoull(j["stage_inode"].as<std::string>()), kOwner);
    struct stat there {};
    if (::fstatat(stage.descriptor(), file_name(job_path).c_str(), &there, AT_SYMLINK_NOFOLLOW) != 0 || there.st_dev != job.st_dev ||
        there.st_ino != job.st_ino)
        throw Error(job_path, "is not a job in the work folder the batch made: not used");
    WorkerJob w{MaterialJob{}, std::move(stage), 0, false, 0, 0, "", ""};
    w.parent = j["parent"].as<long>();
    w.force = j["force"].as<bool>();
    w.shard = j["shard"].as<int>();
    w.memory_limit = std::stoull(j["memory_limit"].as<std::string>());
    w.result = j["result"].as<std::string>();
    w.moves = j["moves"].as<std::string>();
    w.job.name = j["name"].as<std::string>();
    w.job.input = j["input"].as<std::string>();
    w.job.output = j["output"].as<std::string>();
    w.job.origin = j["origin"].as<std::string>();
    for (const auto& kv : j["settings"]) w.job.settings[kv.first.as<std::string>()] = {kv.second[0].as<std::string>(), kv.second[1].as<std::string>()};
    return w;
}

}  // namespace npf::batch::detail
