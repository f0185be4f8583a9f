#!/usr/bin/env bash
# The project's test command (README, second line; .ci/run calls exactly this): installs what
# is missing (the Debian packages, then the Python build's virtual environment), builds with
# warnings as errors, the Python package included, runs the unit tests and the Python package's
# pytest suite (slow suites are opt-in).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
python=$(bash scripts/python-env.sh build/python-venv)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DNPF_WARNINGS_AS_ERRORS=ON \
      -DNPF_BUILD_PYTHON=ON -DPython_EXECUTABLE="$PWD/$python"
cmake --build build -j2
ctest --test-dir build --output-on-failure -j2
