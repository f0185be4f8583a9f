#!/usr/bin/env bash
# Makes (or brings up to date) the Python virtual environment the build and the tests use:
#   bash scripts/python-env.sh [FOLDER]      (default build/python-venv)
# with python/requirements-dev.txt from PyPI (nanobind, numpy, pytest, materialx, ...), and prints
# its interpreter's path last. A virtual environment, because Debian 12's own Python refuses
# pip installs into the system (PEP 668).
set -euo pipefail
cd "$(dirname "$0")/.."
venv=${1:-build/python-venv}
requirements=python/requirements-dev.txt
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv" >&2
fi
stamp="$venv/.requirements"
if ! cmp -s "$requirements" "$stamp"; then
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$requirements" >&2
  cp "$requirements" "$stamp"
fi
echo "$venv/bin/python"
