#!/usr/bin/env bash
# Before/after renders of each kind of edit (docs/editing.md, section "Pictures"), in the spirit
# of the paper's Figs. 8 to 11. Converts the synthetic materials it needs (or reuses those of
# scripts/make-results.py in build/results-work), edits them, renders every version on the
# Sphere scene with the same seed, and writes one labelled strip per edit kind to docs/results/.
#   bash scripts/make-edit-pictures.sh [SIZE] [SPP]
set -euo pipefail
cd "$(dirname "$0")/.."
npf=build/tools/npf/npf
size=${1:-192}
spp=${2:-64}
work=build/edit-pictures
out=docs/results
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
mkdir -p "$work" "$out"

material() {  # name -> fitted NPF file: make-results.py's production fit, else a preview fit
  local reuse=build/results-work/$1.ours.npf.exr
  if [ -f "$reuse" ]; then echo "$reuse"; return; fi
  [ -f "$work/$1.exr" ] || $npf convert "configs/materials/$1.yaml" -o "$work/$1.exr" --preset preview \
      --max-wavelengths 41 --quiet >&2
  echo "$work/$1.exr"
}

render() {  # in.exr label -> png path
  local png=$work/$(basename "$1" .exr).render.png
  [ -f "$png" ] || $npf render "$1" -o "${png%.png}.exr" --png "$png" --size "$size" --spp "$spp" --seed 1 \
      --wavelengths 380:780:41 --quiet >&2
  echo "$png"
}

strip() {  # out.png then pairs of (file.png label)
  local dest=$1; shift
  local args=()
  while [ $# -gt 0 ]; do
    args+=("$1" --ch R,G,B --text:x=6:y=18:size=14:color=1,1,1:font=$font "$2"); shift 2
  done
  local n=$(( ${#args[@]} / 5 ))
  oiiotool "${args[@]}" --mosaic "${n}x1" -d uint8 -o "$dest.tmp.png"
  mv "$dest.tmp.png" "$dest"
  echo "wrote $dest"
}

edit() {  # in.exr tag flags... -> out.exr
  local in=$1 tag=$2; shift 2
  local o=$work/$tag.exr
  [ -f "$o" ] || $npf edit "$in" -o "$o" "$@" >&2
  echo "$o"
}

copper=$(material brushed_copper)
plastic=$(material red_plastic)
satin=$(material satin_fabric)

# NDF (Fig. 8): brushed copper, anisotropic and spectral.
strip "$out/edits_ndf.png" \
  "$(render "$copper")" "brushed copper" \
  "$(render "$(edit "$copper" copper_identity --recipe configs/edits/identity.yaml)")" "identity" \
  "$(render "$(edit "$copper" copper_stretch_t2 --stretch-tangent 2)")" "stretch tangent x2" \
  "$(render "$(edit "$copper" copper_rotate90 --rotate 90)")" "rotate 90 deg" \
  "$(render "$(edit "$copper" copper_sharpen2 --sharpen 2)")" "sharpen x2" \
  "$(render "$(edit "$plastic" plastic_stretch_t3 --stretch-tangent 3)")" "red plastic stretched x3"

# Diffuse colour (Fig. 9) and specular colour (Fig. 10).
strip "$out/edits_colour.png" \
  "$(render "$satin")" "satin" \
  "$(render "$(edit "$satin" satin_red --recipe configs/edits/diffuse_red.yaml)")" "diffuse red" \
  "$(render "$plastic")" "red plastic" \
  "$(render "$(edit "$plastic" plastic_diffuse_blue --diffuse-srgb 0.1,0.2,0.6)")" "diffuse sRGB blue" \
  "$(render "$(edit "$plastic" plastic_copper_spec --specular-from "$copper")")" "specular from copper"

# Thin film (Fig. 11): thickness series at index 1.3 on the red plastic, and on copper.
strip "$out/edits_thin_film.png" \
  "$(render "$plastic")" "red plastic" \
  "$(render "$(edit "$plastic" plastic_film300 --thin-film 300,1.3)")" "film 300 nm" \
  "$(render "$(edit "$plastic" plastic_film450 --thin-film 450,1.3)")" "film 450 nm" \
  "$(render "$(edit "$plastic" plastic_film615 --thin-film 615,1.3)")" "film 615 nm" \
  "$(render "$(edit "$copper" copper_film --recipe configs/edits/thin_film_iridescent.yaml)")" "copper + film"

# The identity edit must render exactly as its input.
$npf compare "$work/$(basename "$copper" .exr).render.exr" "$work/copper_identity.render.exr" | head -2
