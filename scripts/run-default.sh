#!/usr/bin/env bash
# The main job on the shipped default (README, first line): installs what is missing, builds,
# then inspects and probes the shipped measured material.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
material=data/materials/ilm_l3_37_metallic_rgb.bsdf
build/tools/npf/npf info "$material"
echo
echo "f_r (1/sr) at the probe directions of data/materials/probe_dirs.txt:"
build/tools/npf/npf eval "$material" --dirs data/materials/probe_dirs.txt
