#!/usr/bin/env bash
# The sweep behind the fitter's default weights (docs/fitting.md): BRDF-space error of the fit
# for w_I = (cos_i cos_o)^p and w_C = (rho + eps)^-q, on analytic recipes (RGB) and on the
# real measured materials of ../shared/data/rgl when present.
#   bash bench/weight_sweep.sh [BUILD_DIR] > sweep.md
set -euo pipefail
build=${1:-build}
here=$(cd "$(dirname "$0")/.." && pwd)
fit="$build/bench/npf_bench_fit"
sources=("$here/configs/materials/red_plastic.yaml" "$here/configs/materials/brushed_copper.yaml"
         "$here/configs/materials/thin_film_aluminium.yaml")
for f in "$here"/../shared/data/rgl/*.bsdf; do [ -e "$f" ] && sources+=("$f"); done
printf '| source | w_I power p | w_C power q | sweeps | BRDF-space rel. RMS (mean / worst channel) | fit s |\n|---|---|---|---|---|---|\n'
for src in "${sources[@]}"; do
  case $(basename "$src") in
    red_plastic.yaml|*.bsdf) grid="90,1,90,180"; g="90,1"; k=0 ;;
    *) grid="48,96,48,96"; g="48,96"; k=8 ;;
  esac
  for p in 1 2; do
    for q in 0 1; do
      out=$("$fit" "$src" --grid $grid --g-grid $g --phi-d-samples $k --wavelengths rgb \
            --importance $p --compressive $q --epsilon 0.01 --pairs 20000)
      its=$(sed -n 's/^iterations *\([0-9]*\).*/\1/p' <<<"$out")
      err=$(sed -n 's/.*relative RMS mean \([0-9.]*\) %, worst channel \([0-9.]*\) %.*/\1 % \/ \2 %/p' <<<"$out")
      secs=$(sed -n 's/.*fitting \([0-9.]*\).*/\1/p' <<<"$out")
      printf '| %s | %s | %s | %s | %s | %s |\n' "$(basename "$src")" "$p" "$q" "$its" "$err" "$secs"
    done
  done
done
