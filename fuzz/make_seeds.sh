#!/usr/bin/env bash
# Small valid inputs for each fuzz target, made with the npf tool: RGL files (isotropic RGB,
# anisotropic spectral), MERL files of small dimensions, NPF textures converted from them, and
# batch configurations; and the published Neural BRDF networks, when the shared data folder has
# them (the committed fuzz/corpus/nbrdf/ holds small hand-made ones either way).
# usage: make_seeds.sh NPF SOURCE_DIR OUT_DIR [SHARED_DATA_DIR]
set -euo pipefail
npf=$1 src=$2 out=$3 shared=${4:-}
mkdir -p "$out"/{rgl,merl,nbrdf,npf_exr,npf_parts,batch_config}
if [[ -n "$shared" && -d "$shared/nbrdf" ]]; then
    for network in "$shared"/nbrdf/*.h5; do install -m 0644 "$network" "$out/nbrdf/"; done
fi
small=(--theta 3 --ndf 8 --ndf-rows 4 --vndf 8 --data 4 --threads 1 --quiet)
"$npf" synth -o "$out/rgl/plastic_rgb.bsdf" --recipe "$src/configs/materials/red_plastic.yaml" --wavelengths rgb "${small[@]}" > /dev/null
"$npf" synth -o "$out/rgl/copper_aniso.bsdf" --recipe "$src/configs/materials/brushed_copper.yaml" --wavelengths 400:700:3 \
    --phi 4 "${small[@]}" > /dev/null
"$npf" synth -o "$out/rgl/felt_spectral.bsdf" --diffuse 0.5 --alpha 0.3 --dielectric 1.5 --wavelengths 450,550,650 "${small[@]}" > /dev/null
# MERL: 12-byte header (theta_h, theta_d, phi_d counts, int32 little-endian), then R, G, B blocks of doubles.
python3 - "$out/merl" << 'PY'
import struct, sys, math
for (nth, ntd, npd) in [(2, 2, 2), (3, 2, 4), (1, 1, 1)]:
    n = nth * ntd * npd
    vals = [[1500.0 * (0.1 + 0.05 * c + 0.01 * i) * (-1 if i == n - 1 and n > 2 else 1) for i in range(n)] for c in range(3)]
    with open(f"{sys.argv[1]}/merl_{nth}x{ntd}x{npd}.binary", "wb") as f:
        f.write(struct.pack("<3i", nth, ntd, npd))
        for c in range(3):
            f.write(struct.pack(f"<{n}d", *vals[c]))
PY
# Tiny tables and a tiny (or no) detail layer: a few KB a file, so that each input costs the
# fuzzer OpenEXR's fixed work and little decoding.
tiny=(--grid 4,4,4,8 --g-grid 4,4 --error-pairs 0 --threads 1 --quiet --iterations 3)
"$npf" convert "$out/rgl/plastic_rgb.bsdf" -o "$out/npf_exr/plastic_rgb.exr" "${tiny[@]}" --detail 4,4,8 > /dev/null
"$npf" convert "$out/rgl/copper_aniso.bsdf" -o "$out/npf_exr/copper_aniso.exr" "${tiny[@]}" --detail 4,4,8 > /dev/null
"$npf" convert "$out/rgl/felt_spectral.bsdf" -o "$out/npf_exr/felt_spectral_rank1.exr" "${tiny[@]}" --rank 1,1 --detail none > /dev/null
cp "$src/configs/batch/example.yaml" "$out/batch_config/"
