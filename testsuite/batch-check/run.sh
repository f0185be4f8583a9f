# A batch configuration checked without converting: what would be done, and its errors.
mkdir in
run npf synth -o in/grey.bsdf --diffuse 0.5 --alpha 0.3 --dielectric 1.5 --wavelengths rgb --theta 3 --ndf 8 --ndf-rows 4 --vndf 8 --data 4 --threads 1 --quiet
cat > batch.yaml <<'YAML'
output_dir: out
inputs: [in/*.bsdf]
defaults: {preset: preview, error_pairs: 0}
YAML
run npf batch --check batch.yaml
cat > bad.yaml <<'YAML'
output_dir: out
inputs: [in/*.bsdf]
defaults: {preset: medium}
YAML
run npf batch --check bad.yaml
