# Every tool reads every material source (issue 18): a recipe, an RGL file made from it, and
# its factor texture, through info and eval.
cp "$SRC/configs/materials/red_plastic.yaml" .
printf '0 0 1 0 0 1\n0.6 0 0.8 -0.6 0 0.8\n0 0.8 0.6 0.3 -0.4 0.866\n' > pairs.txt
small=(--theta 4 --ndf 16 --ndf-rows 8 --vndf 16 --data 8 --threads 1 --quiet)
run npf synth -o red_plastic.bsdf --recipe red_plastic.yaml --wavelengths rgb "${small[@]}"
run npf convert red_plastic.bsdf -o red_plastic.exr --preset preview --error-pairs 0 --no-predict --threads 1 --quiet
for m in red_plastic.yaml red_plastic.bsdf red_plastic.exr; do
    run npf eval "$m" --dirs pairs.txt --pdf
done
run npf info red_plastic.bsdf
