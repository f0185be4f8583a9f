# Edits from flags and from a recipe through the one registry of edit kinds: the same steps, in
# order, with their records and the albedo check; bad values name the flag or the recipe line.
small=(--theta 4 --phi 4 --ndf 16 --ndf-rows 8 --vndf 16 --data 8 --threads 1 --quiet)
run npf synth -o copper.bsdf --conductor Cu --alpha 0.1,0.3 --wavelengths 450,550,650 "${small[@]}"
run npf convert copper.bsdf -o copper.exr --preset preview --error-pairs 0 --no-predict --threads 1 --quiet
run npf edit copper.exr -o flags.exr --stretch-tangent 2 --rotate 30 --diffuse-linear 0.1,0.05,0.02
cat > steps.yaml <<'YAML'
steps:
  - stretch: {tangent: 2}
  - rotate: 30
  - diffuse: {linear_srgb: [0.1, 0.05, 0.02]}
YAML
run npf edit copper.exr -o recipe.exr --recipe steps.yaml
run npf edit copper.exr --dry-run --limit-albedo 0.5
run npf edit copper.exr -o bad.exr --rotate thirty
run npf edit copper.exr -o bad.exr --film-base Cu
printf 'steps:\n  - rotate: 30\n  - twist: 2\n' > bad.yaml
run npf edit copper.exr -o bad.exr --recipe bad.yaml
[[ -e bad.exr ]] && note "bad.exr was written" || note "no bad.exr"
