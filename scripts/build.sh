#!/usr/bin/env bash
# The one build both README commands use (run-default.sh, run-tests.sh): installs what is missing
# (the Debian packages, then the Python build's virtual environment) and configures and builds
# build/ the same way each time, warnings as errors and the Python package included, so that the
# second command reuses the first's build instead of redoing it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
python=$(bash scripts/python-env.sh build/python-venv)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DNPF_WARNINGS_AS_ERRORS=ON \
      -DNPF_BUILD_PYTHON=ON -DPython_EXECUTABLE="$PWD/$python"
cmake --build build -j2
