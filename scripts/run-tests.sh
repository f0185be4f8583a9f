#!/usr/bin/env bash
# The project's test command (README, second line; .ci/run calls exactly this): the build
# run-default.sh makes too (scripts/build.sh: after the first command nothing is rebuilt), then
# the unit tests and the Python package's pytest suite (slow suites are opt-in).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j2
