#!/usr/bin/env bash
# The main job on the shipped default (README, first line): installs what is missing, builds,
# converts the shipped measured material to an NPF factor texture (out/), compares the measured
# and the fitted material at the probe directions, times shading, and renders both on the
# Sphere scene and compares the pictures.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
material=data/materials/ilm_l3_37_metallic_rgb.bsdf
mkdir -p out
build/tools/npf/npf info "$material"
echo
build/tools/npf/npf convert "$material" -o out/ilm_l3_37_metallic.exr --preset production
echo
build/tools/npf/npf info out/ilm_l3_37_metallic.exr
echo
echo "Energy: the conversion's directional albedo against the measurement's (the detail layer holds it at"
echo "0 to 80 degrees; G is closed at the horizon, so grazing views gain no light):"
build/tools/npf/npf albedo out/ilm_l3_37_metallic.exr --against "$material" --theta 0,30,60,70,80,85,89,89.99 --samples 64
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
echo "Sphere renders under the shipped studio map, measured against fitted: the pictures (out/*.png) with"
echo "MIS; the comparison with environment sampling alone, both at seed 1 (the same light directions, so"
echo "their difference is nearly free of noise) and again at seed 2 for the PSNR's noise floor (docs/metrics.md):"
build/tools/npf/npf render "$material" -o out/ilm_measured.exr --png out/ilm_measured.png --spp 64 --seed 1 --quiet
build/tools/npf/npf render out/ilm_l3_37_metallic.exr -o out/ilm_fitted.exr --png out/ilm_fitted.png --spp 64 --seed 1 --quiet
for seed in 1 2; do
    build/tools/npf/npf render "$material" -o out/ilm_measured_env_seed$seed.exr --spp 128 --seed $seed --sampling env --quiet
    build/tools/npf/npf render out/ilm_l3_37_metallic.exr -o out/ilm_fitted_env_seed$seed.exr --spp 128 --seed $seed \
        --sampling env --quiet
done
build/tools/npf/npf compare out/ilm_measured_env_seed1.exr out/ilm_fitted_env_seed1.exr \
    --floor out/ilm_measured_env_seed2.exr out/ilm_fitted_env_seed2.exr --heatmap out/ilm_relmse.png
