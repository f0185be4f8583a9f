#!/usr/bin/env python3
"""The npf Mitsuba 3 plugin (python/npf/mitsuba.py) against Mitsuba's own `measured` plugin, and
npf's renderer beside both (docs/mitsuba.md):

1. For each RGL file: its conversion (`npf convert`, default preset) rendered in Mitsuba with the
   traced npf plugin (Mitsuba's default symbolic mode); the raw file with `measured`, and with
   npf's own reader in the numpy fallback `npf_numpy` (wavefront mode, turned on around its
   renders only); on npf's
   Sphere scene (unit sphere, camera at (0, 0, 4), the shipped studio map) by Mitsuba's `direct`
   integrator with emitter samples only (the same light directions in every render of a seed, as
   `npf render --sampling env`). PSNRs by `npf compare` (with the paired noise floor from a second
   seed), beside `npf compare` of npf's own renders of the file and its conversion (`npf render
   --sampling env`, same size and spp), and the plugin's render of the conversion against npf's
   render of it under npf's directional lights (`--light directional`: pixel centres, no Monte
   Carlo, so paired with no noise floor; Mitsuba's sensor, intersection, shading frame and the
   plugin's eval); it must reach MIN_PAIRED_DB; Mitsuba's render time per camera sample for both plugins
   (MIS: `direct` with one sample of each).
   Passes when the plugin reproduces npf's comparison within 1 dB: against npf's reader always,
   and against `measured` where the two readers' raw renders agree (above READERS_AGREE_DB;
   `measured` keeps an RGB file's negative values, which npf clamps to 0).
2. mitsuba.chi2's test of the plugin's sampling against its pdf at 0 to 84 degrees; materials
   named by --chi2-must-pass must pass every direction. (Its quadrature cannot integrate a
   mirror-like pdf: it reports the pdf integrating above 1, and rejects Mitsuba's own `measured`
   plugin there too, on the raw ilm file.)

usage: npf_plugin.py NPF_TOOL [--size N] [--spp N] [--chi2-resolution N] [--chi2-must-pass STEM,...]
                     [--json OUT] RGL_FILE...
Needs `pip install mitsuba` and the npf package on PYTHONPATH; the LLVM variants need an LLVM
Dr.Jit accepts (Debian 12: apt-get install libllvm19). Exit 0 when every check passes, 1
otherwise, 77 (skipped) when mitsuba cannot be imported.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

try:
    import drjit as dr
    import mitsuba as mi
    import npf
    import npf.mitsuba
except ImportError as e:
    print("SKIP: mitsuba is not importable ({}): pip install mitsuba".format(e))
    sys.exit(77)

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STUDIO = os.path.join(REPO, "data", "envmaps", "studio.exr")
# npf's Sphere scene camera (docs/render.md): the silhouette spans 90 % of the image height.
FOV_DEG = math.degrees(2.0 * math.atan(math.tan(math.asin(0.25)) / 0.9))
# Above this the raw renders of `measured` and of npf's reader agree (both read the same values).
READERS_AGREE_DB = 80.0
# The plugin's render of a conversion against npf's own render of it (paired).
MIN_PAIRED_DB = 50.0


class Wavefront:
    """Dr.Jit's symbolic loops and calls off for the numpy fallback's renders, restored after."""

    def __enter__(self):
        self.saved = dr.flag(dr.JitFlag.SymbolicLoops), dr.flag(dr.JitFlag.SymbolicCalls)
        dr.set_flag(dr.JitFlag.SymbolicLoops, False)
        dr.set_flag(dr.JitFlag.SymbolicCalls, False)

    def __exit__(self, *exc):
        dr.set_flag(dr.JitFlag.SymbolicLoops, self.saved[0])
        dr.set_flag(dr.JitFlag.SymbolicCalls, self.saved[1])
CHI2_DIRECTIONS = [(0.0, 0.0, 1.0), (0.5, 0.3, 0.81), (-0.7, 0.2, 0.3), (0.95, 0.0, 0.1)]  # 0 to 84 degrees


def scene(bsdf, size, spp, seed, emitter_samples, bsdf_samples):
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": emitter_samples, "bsdf_samples": bsdf_samples},
        "sensor": {
            "type": "perspective", "fov": FOV_DEG, "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 4], target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": size, "height": size, "pixel_format": "rgba",
                     "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": spp, "seed": seed},
        },
        # Mitsuba's envmap is npf's lat-long turned half a turn about +y (docs/render.md).
        "light": {"type": "envmap", "filename": STUDIO, "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], 180)},
        # The sphere's pole on +y, so that its dp/du (the shading tangent) runs around the vertical
        # axis, as npf's tangent field.
        "sphere": {"type": "sphere", "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90), "bsdf": bsdf},
    })


def render(bsdf, path, size, spp, seed, emitter_samples=1, bsdf_samples=0):
    s = scene(bsdf, size, spp, seed, emitter_samples, bsdf_samples)
    start = time.perf_counter()
    image = mi.render(s)
    dr.eval(image)
    dr.sync_thread()  # the LLVM backend launches asynchronously: wait for the render itself
    seconds = time.perf_counter() - start
    mi.Bitmap(image, channel_names=["R", "G", "B", "A"]).write(path)
    return seconds / (size * size * spp)


# npf render --light directional's lights (docs/render.md, section 2a): direction towards the light
# and irradiance; read from the render's own metadata (npf:lights) so that the two cannot drift.
def directional_lights(npf_exr):
    text = mi.Bitmap(npf_exr).metadata()["npf:lights"]
    lights = []
    for part in text.split(";"):
        direction = part[part.index("(") + 1:part.index(")")]
        lights.append(([float(c) for c in direction.split(",")], float(part.split("irradiance")[1])))
    return lights


def render_directional(bsdf, path, size, lights):
    """npf render --light directional in Mitsuba's terms, with no Monte Carlo: one ray through each
    pixel's centre from Mitsuba's sensor, Mitsuba's intersection and shading frame, and
    pixel = sum over lights of E eval(wi, wo) (the plugin's eval includes cos theta_o; the sphere is
    convex, so nothing else shadows). Noise-free, so a paired comparison has no floor."""
    s = scene(bsdf, size, 1, 0, 1, 0)
    sensor = s.sensors()[0]
    y, x = dr.meshgrid(dr.arange(mi.Float, size), dr.arange(mi.Float, size), indexing="ij")
    ray, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f((x + 0.5) / size, (y + 0.5) / size), mi.Point2f(0.5))
    si = s.ray_intersect(ray)
    value = mi.Color3f(0.0)
    for direction, irradiance in lights:
        value += irradiance * si.bsdf().eval(mi.BSDFContext(), si, si.to_local(mi.Vector3f(direction)), si.is_valid())
    alpha = dr.select(si.is_valid(), 1.0, 0.0)
    import numpy as np
    rgba = np.stack([np.array(value[0]), np.array(value[1]), np.array(value[2]), np.array(alpha)], 1).reshape(size, size, 4)
    mi.Bitmap(rgba.astype(np.float32), channel_names=["R", "G", "B", "A"]).write(path)


def npf_psnr(npf_tool, reference, test, floor=None):
    args = [npf_tool, "compare", reference, test, "--json"] + (["--floor"] + floor if floor else [])
    d = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    return float(d["PSNR"]), float(d["noise_floor_db"]) if floor else None


def compare_one(npf_tool, rgl, folder, size, spp):
    name = os.path.splitext(os.path.basename(rgl))[0]
    exr = os.path.join(folder, name + ".exr")
    subprocess.run([npf_tool, "convert", rgl, "-o", exr, "--quiet", "--no-predict"], check=True, capture_output=True)
    measured = {"type": "measured", "filename": rgl}
    ours = {"type": "npf", "filename": exr}
    raw_ours = {"type": "npf_numpy", "filename": rgl}  # the raw file through npf's reader (numpy fallback)
    f = lambda tag: os.path.join(folder, "{}_{}.exr".format(name, tag))  # noqa: E731
    # Warm-up renders compile the kernels; the timed ones are the MIS renders after them.
    render(measured, f("warm"), 16, 1, 0)
    render(ours, f("warm"), 16, 1, 0)
    render(measured, f("mi_measured"), size, spp, 1)
    render(ours, f("mi_npf"), size, spp, 1)
    render(measured, f("mi_measured2"), size, spp, 2)
    render(ours, f("mi_npf2"), size, spp, 2)
    with Wavefront():
        render(raw_ours, f("mi_raw"), size, spp, 1)
        render(raw_ours, f("mi_raw2"), size, spp, 2)
    t_measured = render(measured, f("mis_measured"), size, spp, 3, 1, 1)
    t_npf = render(ours, f("mis_npf"), size, spp, 3, 1, 1)
    psnr_mi, floor_mi = npf_psnr(npf_tool, f("mi_measured"), f("mi_npf"), [f("mi_measured2"), f("mi_npf2")])
    # Mitsuba's `measured` keeps an RGB file's negative (out-of-gamut) values, npf clamps them to 0
    # (docs/measured-readers.md): where a file has them, the two raw renders differ by that alone.
    psnr_readers, _ = npf_psnr(npf_tool, f("mi_measured"), f("mi_raw"))
    psnr_mi_raw, floor_mi_raw = npf_psnr(npf_tool, f("mi_raw"), f("mi_npf"), [f("mi_raw2"), f("mi_npf2")])
    mis_psnr, _ = npf_psnr(npf_tool, f("mis_measured"), f("mis_npf"))
    for seed in (1, 2):
        for src, tag in ((rgl, "raw"), (exr, "conv")):
            subprocess.run([npf_tool, "render", src, "-o", f("npf_{}{}".format(tag, seed)), "--size", str(size), "--spp",
                            str(spp), "--seed", str(seed), "--sampling", "env", "--quiet"], check=True, capture_output=True)
    psnr_npf, floor_npf = npf_psnr(npf_tool, f("npf_raw1"), f("npf_conv1"), [f("npf_raw2"), f("npf_conv2")])
    # The plugin's render of the conversion against npf's own, noise-free (directional lights).
    subprocess.run([npf_tool, "render", exr, "-o", f("npf_directional"), "--size", str(size), "--light", "directional",
                    "--quiet"], check=True, capture_output=True)
    render_directional(ours, f("mi_directional"), size, directional_lights(f("npf_directional")))
    psnr_paired, _ = npf_psnr(npf_tool, f("npf_directional"), f("mi_directional"))
    return {"material": name, "psnr_mitsuba": psnr_mi, "floor_mitsuba": floor_mi, "psnr_readers": psnr_readers,
            "psnr_mitsuba_npf_reader": psnr_mi_raw, "floor_mitsuba_npf_reader": floor_mi_raw, "psnr_npf": psnr_npf,
            "floor_npf": floor_npf, "psnr_plugin_vs_npf_render": psnr_paired,
            "psnr_mitsuba_mis": mis_psnr, "us_per_sample_measured": t_measured * 1e6,
            "us_per_sample_npf": t_npf * 1e6}


def chi2_one(exr, directions=CHI2_DIRECTIONS, resolution=101, subsamples=4):
    """mitsuba.chi2's test of the plugin's sample() against its pdf() at each incident direction.
    A sample counts where its pdf is positive: Mitsuba's BSDFAdapter drops samples whose weight is
    0, which tests the material's values as well (a conversion that is black in a corner the
    sampler still reaches, as some are at grazing retro-reflection, fails it there)."""
    from mitsuba.chi2 import ChiSquareTest, SphericalDomain
    bsdf = mi.load_dict({"type": "npf", "filename": exr})
    ctx = mi.BSDFContext()
    results = []
    for wi in directions:
        n = math.sqrt(sum(c * c for c in wi))
        wi = [c / n for c in wi]

        def context(count, wi=wi):
            si = dr.zeros(mi.SurfaceInteraction3f, count)
            si.wi = mi.Vector3f(wi)
            return si

        def sample(u):
            bs, _ = bsdf.sample(ctx, context(dr.width(u)), u[0], mi.Vector2f(u[1], u[2]))
            return bs.wo, dr.select(bs.pdf > 0, 1.0, 0.0)

        def pdf(wo):
            return bsdf.pdf(ctx, context(dr.width(wo)), wo)

        test = ChiSquareTest(domain=SphericalDomain(), sample_func=sample, pdf_func=pdf, sample_dim=3,
                             sample_count=1000000, res=resolution, ires=subsamples)
        results.append((wi, bool(test.run())))
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("npf_tool")
    parser.add_argument("files", nargs="+")
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--json")
    parser.add_argument("--keep", action="store_true", help="keep the renders (their folder is printed)")
    parser.add_argument("--chi2-must-pass", default="",
                        help="comma-separated materials (file stems) whose chi-square tests must all pass; the others "
                             "are reported")
    parser.add_argument("--chi2-resolution", type=int, default=101,
                        help="cells in cos theta (twice as many in phi: mitsuba.chi2's res); a mirror-like material "
                             "needs more")
    args = parser.parse_args()
    try:
        npf.mitsuba.set_variant("llvm_ad_rgb")
    except npf.Error as e:
        sys.exit("npf_plugin.py: " + str(e))
    npf.mitsuba.register()
    with Wavefront():  # register_numpy turns them off; only its renders need that
        npf.mitsuba.register_numpy()
    folder = tempfile.mkdtemp(prefix="npf-mitsuba-plugin-")
    npf_tool = os.path.abspath(args.npf_tool)
    files = [os.path.abspath(f) for f in args.files]
    json_path = os.path.abspath(args.json) if args.json else None
    os.chdir(folder)  # mitsuba.chi2 writes chi2_data.py into the working folder when a test fails
    if args.keep:
        print("renders in", folder)
    rows, ok = [], True
    print("%-24s %8s %8s %9s %8s %8s %8s %8s %8s %7s %7s  %s" % (
        "material", "measured", "floor", "readers", "npf rdr", "floor", "npf", "floor", "mi/npf", "us mea",
        "us npf", "chi2"))
    for rgl in files:
        row = compare_one(npf_tool, rgl, folder, args.size, args.spp)
        row["chi2"] = [(wi, ok) for wi, ok in chi2_one(os.path.join(folder, row["material"] + ".exr"),
                                                        resolution=args.chi2_resolution)]
        # The plugin must reproduce npf's comparison: against the same raw values (npf's reader in
        # the plugin) always, against `measured` where the two readers agree (no negative values).
        same_readers = row["psnr_readers"] >= READERS_AGREE_DB
        agree = abs(row["psnr_mitsuba_npf_reader"] - row["psnr_npf"]) <= 1.0 and (
            not same_readers or abs(row["psnr_mitsuba"] - row["psnr_npf"]) <= 1.0) and (
            row["psnr_plugin_vs_npf_render"] >= MIN_PAIRED_DB)
        chi2 = "".join("+" if passed else "-" for _, passed in row["chi2"])
        ok &= agree and (row["material"] not in args.chi2_must_pass.split(",") or "-" not in chi2)
        print("%-24s %8.2f %8.2f %9.2f %8.2f %8.2f %8.2f %8.2f %8.2f %7.3f %7.3f  %s%s" % (
            row["material"], row["psnr_mitsuba"], row["floor_mitsuba"], row["psnr_readers"],
            row["psnr_mitsuba_npf_reader"], row["floor_mitsuba_npf_reader"], row["psnr_npf"], row["floor_npf"],
            row["psnr_plugin_vs_npf_render"],
            row["us_per_sample_measured"], row["us_per_sample_npf"], chi2, "" if agree else "  PSNR DISAGREES"))
        sys.stdout.flush()
        rows.append(row)
    if json_path:
        with open(json_path, "w") as out:
            json.dump(rows, out, indent=1)
    if not args.keep:
        os.chdir(REPO)
        shutil.rmtree(folder)
    print("agree" if ok else "DISAGREE")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
