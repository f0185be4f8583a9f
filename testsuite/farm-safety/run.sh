# Texture farms over factor textures (docs/farms.md): what the real maketx and oiiotool make of a
# factor texture, and `npf info --check` on each result: the same tables shade (ok), anything
# else is refused with one line naming the file. unsealed/ holds two files written before
# npf:tables_checksum (npf 0.1.0 before issue 20): they still read, with the values they had.
cp "$SRC/configs/materials/red_plastic.yaml" .
cp "$SRC/testsuite/farm-safety/unsealed/"*.exr .
printf '0 0 1 0 0 1\n0.6 0 0.8 -0.6 0 0.8\n0 0.8 0.6 0.3 -0.4 0.866\n' > pairs.txt
small=(--theta 4 --ndf 16 --ndf-rows 8 --vndf 16 --data 8 --threads 1 --quiet)
run npf synth -o red_plastic.bsdf --recipe red_plastic.yaml --wavelengths rgb "${small[@]}"
run npf convert red_plastic.bsdf -o m.exr --preset preview --error-pairs 0 --no-predict --threads 1 --quiet

note "what a farm's commands make of a factor texture (every command exits 0)"
run maketx m.exr
run maketx m.exr -o mip.exr
run oiiotool m.exr -o copy.exr
run oiiotool -a m.exr --compression dwaa -o dwaa.exr
run oiiotool m.exr -d half -o half.exr
run oiiotool m.exr --compression pxr24 -o pxr24.exr
run oiiotool -a m.exr --colorconvert linear sRGB -o srgb.exr
run oiiotool m.exr --colorconvert linear sRGB -o first_part.exr
run npf info --check m.exr m.tx mip.exr copy.exr dwaa.exr half.exr pxr24.exr srgb.exr first_part.exr
run npf info --check --json m.exr m.tx
run npf info --check m.exr copy.exr dwaa.exr red_plastic.bsdf red_plastic.yaml

note "files written before the checksum read as before"
run npf info --check v2-rgb-detail.exr v1-spectral-aniso.exr
run npf eval v2-rgb-detail.exr --dirs pairs.txt --pdf
run npf eval v2-rgb-detail.exr --dirs pairs.txt --pdf --path texture
run npf eval v1-spectral-aniso.exr --dirs pairs.txt --wavelengths 450,550,650
run oiiotool v2-rgb-detail.exr -d half -o v2-half.exr
run npf info --check v2-half.exr
