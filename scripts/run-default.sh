#!/usr/bin/env bash
# The main job on the shipped default (README, first line): installs what is missing, builds,
# converts the shipped measured material to an NPF factor texture (out/), compares the measured
# and the fitted material at the probe directions, times shading, and renders both on the
# Sphere scene and compares the pictures.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
material=data/materials/ilm_l3_37_metallic_rgb.bsdf
mkdir -p out
build/tools/npf/npf info "$material"
echo
build/tools/npf/npf convert "$material" -o out/ilm_l3_37_metallic.exr --preset production
echo
build/tools/npf/npf info out/ilm_l3_37_metallic.exr
echo
echo "Energy: the fit's albedo grows without bound in the last fraction of a degree before the horizon"
echo "(G extrapolated above 0 there); the cap lowers G only where the albedo exceeds 1:"
build/tools/npf/npf edit out/ilm_l3_37_metallic.exr -o out/ilm_l3_37_metallic_capped.exr --limit-albedo 1
build/tools/npf/npf albedo out/ilm_l3_37_metallic_capped.exr --against out/ilm_l3_37_metallic.exr --theta 0,60,85,89,89.9,89.99 --samples 64
echo
echo "f_r (1/sr) at the probe directions of data/materials/probe_dirs.txt, measured:"
build/tools/npf/npf eval "$material" --dirs data/materials/probe_dirs.txt
echo "and fitted (out/ilm_l3_37_metallic.exr):"
build/tools/npf/npf eval out/ilm_l3_37_metallic.exr --dirs data/materials/probe_dirs.txt
echo "and through OpenImageIO's TextureSystem (the shading module's texture path):"
build/tools/npf/npf eval out/ilm_l3_37_metallic.exr --dirs data/materials/probe_dirs.txt --path texture
echo
build/tools/npf/npf bench out/ilm_l3_37_metallic.exr --against "$material" --seconds 0.3
echo
echo "Sphere renders under the shipped studio map (out/*.png), measured against fitted:"
build/tools/npf/npf render "$material" -o out/ilm_measured.exr --png out/ilm_measured.png --spp 64 --seed 1 --quiet
build/tools/npf/npf render out/ilm_l3_37_metallic.exr -o out/ilm_fitted.exr --png out/ilm_fitted.png --spp 64 --seed 1 --quiet
build/tools/npf/npf compare out/ilm_measured.exr out/ilm_fitted.exr --heatmap out/ilm_relmse.png
