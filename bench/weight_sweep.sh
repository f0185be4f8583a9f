#!/usr/bin/env bash
# The sweep behind the fitter's default weights (docs/fitting.md): BRDF-space error of the fit
# for w_I = (cos_i cos_o)^p and w_C = (rho + eps)^-q on the shipped analytic recipes, RGB.
#   bash bench/weight_sweep.sh [BUILD_DIR] > sweep.txt
set -euo pipefail
build=${1:-build}
here=$(cd "$(dirname "$0")/.." && pwd)
fit="$build/bench/npf_bench_fit"
printf '| recipe | grid | w_I power | w_C power | iterations | BRDF-space rel. RMS (mean / worst channel) | fit s |\n|---|---|---|---|---|---|---|\n'
for recipe in red_plastic brushed_copper thin_film_aluminium; do
  case $recipe in
    red_plastic) grid="90,1,90,180"; g="90,1"; k=0 ;;
    *) grid="64,128,64,128"; g="64,128"; k=8 ;;
  esac
  for p in 1 2; do
    for q in 0 1; do
      out=$("$fit" "$here/configs/materials/$recipe.yaml" --grid $grid --g-grid $g --phi-d-samples $k \
            --wavelengths rgb --importance $p --compressive $q --epsilon 0.01 --pairs 20000)
      its=$(sed -n 's/^iterations *\([0-9]*\).*/\1/p' <<<"$out")
      err=$(sed -n 's/.*relative RMS mean \([0-9.]*\) %, worst channel \([0-9.]*\) %.*/\1 % \/ \2 %/p' <<<"$out")
      secs=$(sed -n 's/.*fitting \([0-9.]*\).*/\1/p' <<<"$out")
      printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$recipe" "$grid" "$p" "$q" "$its" "$err" "$secs"
    done
  done
done
