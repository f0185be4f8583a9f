# The README's Python example: convert the shipped material, evaluate it on a million direction
# pairs, render it in Mitsuba 3 (pip install mitsuba) with npf's plugin.
#   python examples/python/quickstart.py [OUTPUT_FOLDER]      (default: the working directory)
# Runs from any folder; writes ilm.exr and ilm.png into OUTPUT_FOLDER.
import os, sys
import numpy as np, mitsuba as mi, npf, npf.mitsuba

here = os.path.dirname(os.path.abspath(__file__))
out = sys.argv[1] if len(sys.argv) > 1 else "."
os.makedirs(out, exist_ok=True)
material = os.path.join(out, "ilm.exr")
npf.convert(os.path.join(here, "..", "..", "data", "materials", "ilm_l3_37_metallic_rgb.bsdf"), material, preset="preview")
m = npf.open(material)
rng = np.random.default_rng(1)
wi, wo = rng.normal(size=(2, 1_000_000, 3)); wi[:, 2], wo[:, 2] = abs(wi[:, 2]), abs(wo[:, 2])
f = m.eval(wi, wo)                                     # (1000000, 3): f_r in 1/sr, R G B
try:
    npf.mitsuba.set_variant("llvm_ad_rgb")             # checks first that Dr.Jit finds a usable LLVM
except npf.Error as e:
    sys.exit("quickstart: " + str(e))
npf.mitsuba.register()
scene = mi.load_file(os.path.join(here, "sphere.xml"), material=os.path.abspath(material))
mi.util.write_bitmap(os.path.join(out, "ilm.png"), mi.render(scene, spp=64))
print(f.shape, f.mean(axis=0), "->", os.path.join(out, "ilm.png"))
