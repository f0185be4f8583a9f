"""What make-results.py measures: the materials, the tiers of the accuracy ladder, the lightings
and the targets the ladder is judged by. make-results.py's options change the material lists on its
own arguments (args.real, args.ladder_synthetic, ...); these are the defaults."""

import os

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"

REAL = ["acrylic_felt_green_rgb", "cg_sunflower_rgb", "ilm_l3_37_metallic_rgb", "paper_white_rgb",
        "vch_golden_yellow_rgb"]
# Synthetic materials of the ladder: the recipe written out as an RGL file by `npf synth` (what a
# user converts; brushed copper: 195 wavelengths, 167 MB), which is then the reference too.
LADDER_SYNTHETIC = ["brushed_copper"]
# Synthetic anisotropic spectral materials converted straight from their recipes (rendered exactly
# as reference): Table 2 and the rank sweep use the failure case.
SYNTHETIC = ["crossed_lobes_failure"]
# Recipes that also get Table 1 rows (--table1-synthetic): none by default. Each production fit of
# a recipe at 41 wavelengths takes 4 to 7 minutes on 2 cores, and Table 1 needs two (ours and
# Bagher's); brushed copper's Table 1 row comes with the ladder. satin_fabric, red_plastic and
# thin_film_aluminium are left out for the same reason.
TABLE1_SYNTHETIC = []
FAILURE = "crossed_lobes_failure"
PCA_RATIOS = [None, (0.99, 0.99), (0.99, 0.95), (0.99, 0.90), (0.95, 0.95), (0.90, 0.90)]
RANKS = [1, 2, 4, 8, 16]
# The accuracy ladder (docs/fitting.md): tag (file names), label, npf convert flags. "ours" is the
# production conversion's tag (Table 1's, and scripts/make-edit-pictures.sh reuses it).
TIERS = [("paper", "paper", ["--preset", "paper"]),
         ("preview", "preview", ["--preset", "preview"]),
         ("ours", "production (default)", ["--preset", "production"]),
         ("fine", "fine", ["--preset", "fine"])]
NBRDF = "Neural BRDF"
# Albedo column of the ladder: the views the detail fit holds (0..80 degrees), as in fitting.md.
LADDER_THETAS = [0, 20, 40, 60, 70, 80]
# Estimator cells per strategy (npf albedo --samples): NPF files sample their own lobes well
# (standard errors about 0.1 %); a Neural BRDF is sampled by the cosine and its MIS partner, so
# glossy networks need more cells to bring the standard error of the worst difference down.
ALBEDO_SAMPLES = {"npf": 256, "nbrdf": 1024}
# The ladder's lightings besides the shipped studio map (npf render --light, docs/render.md sec. 2a):
# key-rim is a map (environment sampling and a paired floor, as studio); directional is delta
# lights without Monte Carlo, so one render and no floor.
LIGHTS = ["key-rim", "directional"]
# BRDF space: count the pairs with both directions within this angle (the views the fit holds).
BRDF_MAX_THETA = 80.0
# The targets the ladder is judged by: (PSNR in dB, largest file as a fraction of the input).
TARGETS = [(40.0, 1.0 / 8), (45.0, 1.0 / 3)]
