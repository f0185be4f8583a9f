#include "injected_faults.h"

#include <csignal>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace npf::testing {

namespace {

// Memory until the limit refuses it (RLIMIT_DATA counts it untouched), then std::bad_alloc.
[[noreturn]] void run_out_of_memory(std::uint64_t limit) {
    std::vector<void*> blocks;
    const std::size_t block = std::size_t(64) << 20;
    try {
        for (std::uint64_t total = 0; total <= limit; total += block) blocks.push_back(::operator new(block));
    } catch (...) {
        for (void* b : blocks) ::operator delete(b);
        throw;
    }
    for (void* b : blocks) ::operator delete(b);
    throw std::bad_alloc();
}

void apply(const std::string& kind, std::uint64_t memory_limit, bool in_worker) {
    if (kind == "oom") {
        if (!in_worker || memory_limit == 0) throw std::bad_alloc();
        run_out_of_memory(memory_limit);
    }
    if (!in_worker) return;
    const struct rlimit no_core {0, 0};
    ::setrlimit(RLIMIT_CORE, &no_core);  // no core files from a test
    if (kind == "abort") std::abort();
    if (kind == "segv") {
        std::signal(SIGSEGV, SIG_DFL);
        std::raise(SIGSEGV);
    }
    if (kind == "kill") std::raise(SIGKILL);
    if (kind == "exit") std::_Exit(9);
    if (kind == "hang") {
        for (;;) ::pause();
    }
}

}  // namespace

batch::MaterialHook injected_faults(bool in_worker) {
    return [in_worker](const std::string& name, std::uint64_t memory_limit) {
        const char* env = std::getenv("NPF_TEST_FAULT");
        if (!env) return;
        const std::string spec = env;
        for (std::size_t at = 0; at <= spec.size();) {
            const std::size_t comma = std::min(spec.find(',', at), spec.size());
            const std::string item = spec.substr(at, comma - at);
            at = comma + 1;
            const std::size_t colon = item.find(':');
            if (colon != std::string::npos && item.substr(colon + 1) == name) apply(item.substr(0, colon), memory_limit, in_worker);
        }
    };
}

}  // namespace npf::testing
