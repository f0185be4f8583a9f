#!/usr/bin/env bash
# The project's test command (README, second line; .ci/run calls exactly this): installs what
# is missing, builds with warnings as errors, runs the unit tests (slow suites are opt-in).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DNPF_WARNINGS_AS_ERRORS=ON
cmake --build build -j2
ctest --test-dir build --output-on-failure -j2
