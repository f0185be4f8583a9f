# The README's Python example: convert the shipped material, evaluate it on a million direction
# pairs, render it in Mitsuba 3 (pip install mitsuba). Run from the repository root.
import numpy as np, mitsuba as mi, npf, npf.mitsuba
npf.convert("data/materials/ilm_l3_37_metallic_rgb.bsdf", "ilm.exr", preset="preview")
m = npf.open("ilm.exr")
rng = np.random.default_rng(1)
wi, wo = rng.normal(size=(2, 1_000_000, 3)); wi[:, 2], wo[:, 2] = abs(wi[:, 2]), abs(wo[:, 2])
f = m.eval(wi, wo)                                     # (1000000, 3): f_r in 1/sr, R G B
mi.set_variant("llvm_ad_rgb"); npf.mitsuba.register()  # Debian 12: see docs/mitsuba.md for LLVM
mi.util.write_bitmap("ilm.png", mi.render(mi.load_file("examples/python/sphere.xml", material="ilm.exr"), spp=64))
print(f.shape, f.mean(axis=0), "-> ilm.png")
