// Test-only faults for the batch (docs/batch.md "Failure isolation"): NPF_TEST_FAULT=KIND:NAME[,...]
// makes material NAME fail the way a broken reader can (abort, segv, oom, hang, kill, exit), so
// that the tests can show that a batch survives it. Read by the test-only worker executable
// (tests/fault_worker.cpp, NPF_FAULT_WORKER_PATH) and by in-process test batches; the shipped
// npf never reads it.
#pragma once

#include <npf/batch/runner.h>

namespace npf::testing {

// The hook that applies NPF_TEST_FAULT (as set when a material starts). In a worker every kind;
// in the test's own process only `oom`, which throws std::bad_alloc (the rest would end it).
batch::MaterialHook injected_faults(bool in_worker);

}  // namespace npf::testing
