// npf_fault_worker batch --worker JOB: the batch's worker entry point (npf::batch::run_batch_worker)
// with the test-only faults of NPF_TEST_FAULT (injected_faults.h). Tests that show that a batch
// survives a crashing, hanging or memory-hungry material name it as the batch's worker
// executable (BatchOptions::worker_executable, `npf batch --worker-executable`).
#include "injected_faults.h"

#include <npf/batch/runner.h>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    if (argc != 4 || std::string(argv[1]) != "batch" || std::string(argv[2]) != "--worker") {
        std::fprintf(stderr, "usage: npf_fault_worker batch --worker JOB\n");
        return 2;
    }
    return npf::batch::run_batch_worker(argv[3], npf::testing::injected_faults(true));
}
