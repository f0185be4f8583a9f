// Shards of a batch: which materials shard K of N runs, and its summary's name.
#include <npf/batch/runner.h>

#include "batch_folders.h"

#include <npf/core/error.h>

#include <cstdlib>
#include <filesystem>

namespace npf::batch {

Shard parse_shard(const std::string& text, const std::string& what) {
    const std::size_t slash = text.find('/');
    const auto whole = [&](const std::string& v) -> long {
        if (v.empty() || v.size() > 6 || v.find_first_not_of("0123456789") != std::string::npos)
            throw Error(what, "expects K/N with whole numbers 0 <= K < N, got '" + text + "'");
        return std::atol(v.c_str());
    };
    if (slash == std::string::npos) throw Error(what, "expects K/N (shard K of N, from 0), got '" + text + "'");
    const long k = whole(text.substr(0, slash)), n = whole(text.substr(slash + 1));
    if (n < 1 || n > 100000 || k >= n) throw Error(what, "expects K/N with 0 <= K < N <= 100000, got '" + text + "'");
    return Shard{int(k), int(n)};
}

std::vector<std::size_t> shard_members(std::size_t count, const Shard& shard) {
    std::vector<std::size_t> out;
    for (std::size_t i = std::size_t(shard.index); i < count; i += std::size_t(shard.count)) out.push_back(i);
    return out;
}

std::string summary_base(const BatchConfig& config, const Shard& shard) {
    std::string base = config.summary.empty() ? (std::filesystem::path(config.output_dir) / "batch-summary").string() : config.summary;
    if (shard.count > 1) base += "." + detail::shard_tag(shard);
    return base;
}

}  // namespace npf::batch
