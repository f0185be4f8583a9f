"""make-results.py's measurements, one function a section of docs/results.md: each runs its steps
through the Runner (cached in the work folder) and returns the figures the report writes."""

import os

from results.formatting import short
from results.plots import COLOURS, plot, side_by_side
from results.runner import file_mb, log
from results.settings import (ALBEDO_SAMPLES, FAILURE, LADDER_THETAS, LIGHTS, NBRDF, PCA_RATIOS, RANKS,
                              TARGETS, TIERS)


def ladder_tier_row(r, name, raw, ref, tag, label, extra):
    """One tier of a material: its conversion judged against the raw file, or None with npf's
    refusal."""
    if tag == "ours":  # Table 1 and the pictures need the production conversion: no failing there
        fitted, seconds = r.convert(name, tag, extra)
    else:
        fitted, seconds = r.convert_or_fail(name, tag, extra)
        if fitted is None:
            return None, {"tier": label, "tag": tag, "error": seconds}
    img = r.render_pair(fitted, tag, name)
    heat = r.path("%s.%s.heat.png" % (name, tag)) if tag == "ours" else None
    return {"tier": label, "tag": tag, "file": fitted, "mb": file_mb(fitted), "fit_s": seconds,
            "dropped": r.detail_dropped(fitted),
            "m": r.compare_pair(ref, img, heat),
            "lights": {light: r.compare_light(fitted, raw, tag, name, light) for light in LIGHTS},
            "brdf": r.brdf_rms(fitted, name),
            "albedo": r.albedo(fitted, raw, LADDER_THETAS, ALBEDO_SAMPLES["npf"])["worst"],
            "eval_ns": r.bench(fitted)["eval_memory_ns"]}, None


def network_row(r, name, raw, ref, nb, rows):
    """The Neural BRDF of the material by the same measures (npf bench times NPF files; the
    network's own evaluation is its --against column)."""
    img = r.render_pair(nb, "nbrdf", name)
    production = [row for row in rows if row["tag"] == "ours"][0]
    return {"tier": NBRDF, "tag": "nbrdf", "file": nb, "mb": file_mb(nb), "fit_s": None,
            "m": r.compare_pair(ref, img),
            "lights": {light: r.compare_light(nb, raw, "nbrdf", name, light) for light in LIGHTS},
            "brdf": r.brdf_rms(nb, name),
            "albedo": r.albedo(nb, raw, LADDER_THETAS, ALBEDO_SAMPLES["nbrdf"])["worst"],
            "eval_ns": r.bench(production["file"], against=nb)["eval_raw_ns"]}


def measure_ladder(r, args):
    """The accuracy ladder: every preset and the Neural BRDF on each material, judged against the
    raw file by paired renders (with the noise floor), albedo, size and speed. Returns (ladder,
    capped: material -> the paper tier's sweep cap, where it has one)."""
    log("Ladder")
    ladder, capped = {}, {}
    for name in args.real + args.ladder_synthetic:
        raw = r.source(name)
        ref = r.render_pair(raw, "reference", name)
        rows = []
        failed = []  # tiers whose conversion npf refused: (label, its error), shown as such
        for tag, label, extra in TIERS:
            if tag == "paper" and name in args.ladder_synthetic and args.paper_sweeps > 0 and \
                    "--iterations" not in args.synthetic_convert_flags:
                tag, extra = "paper-%dsweeps" % args.paper_sweeps, extra + ["--iterations", str(args.paper_sweeps)]
                capped[name] = args.paper_sweeps
            row, refusal = ladder_tier_row(r, name, raw, ref, tag, label, extra)
            if row:
                rows.append(row)
            else:
                failed.append(refusal)
        nb = r.nbrdf(name)
        if nb:
            rows.append(network_row(r, name, raw, ref, nb, rows))
        # The raw file through npf's own reader, by the same measure: what the column reads when
        # the conversion is perfect (the reader against the RGL loader).
        reader = r.brdf_rms(raw, name) if r.reference_values(name) else None
        ladder[name] = {"input_mb": file_mb(raw), "input": raw, "rows": rows, "nbrdf": nb, "failed": failed,
                        "reader": reader,
                        "by_label": {row["tier"]: row for row in rows}}
    return ladder, capped


def plot_ladder(images, ladder):
    plot(os.path.join(images, "ladder.png"), [
        {"title": "the accuracy ladder: render PSNR against file size", "xlabel": "file size (KB, log)",
         "ylabel": "PSNR (dB)", "logx": True, "legend": "left",
         "hlines": [(psnr, "%g dB" % psnr) for psnr, _ in TARGETS],
         "series": [s for k, name in enumerate(ladder) for s in (
             (short(name), COLOURS[k % len(COLOURS)],
              [(row["mb"] * 1e3, min(row["m"]["PSNR"], 99)) for row in ladder[name]["rows"] if row["tag"] != "nbrdf"],
              {"in_order": True}),
             ("", COLOURS[k % len(COLOURS)],
              [(row["mb"] * 1e3, min(row["m"]["PSNR"], 99)) for row in ladder[name]["rows"] if row["tag"] == "nbrdf"],
              {"line": False, "marker": "cross", "legend": False}))] +
            [("crosses: Neural BRDF", "0,0,0", [], {})]}], width=900, height=520)


def measure_table1(r, args):
    """Table 1: the paper's weight against Bagher's; ours is the ladder's production conversion."""
    log("Table 1")
    t1 = []
    for name in args.real + args.ladder_synthetic + args.table1_synthetic:
        ref = r.render_pair(r.source(name), "reference", name)
        row = {"name": name}
        for tag, extra in (("ours", ["--preset", "production"]),
                           ("bagher", ["--preset", "production", "--volume-weight", "three-angle"])):
            fitted, seconds = r.convert(name, tag, extra)
            img = r.render_pair(fitted, tag, name)
            heat = r.path("%s.%s.heat.png" % (name, tag))
            row[tag] = r.compare_pair(ref, img, heat)
            row[tag + "_fit_s"] = seconds
            row[tag + "_mb"] = file_mb(fitted)
        t1.append(row)
    return t1


def measure_energy(r, args, albedo_thetas):
    """Directional albedo of each real conversion against its raw file (npf albedo), mean over the
    channels of the relative difference, at a few view angles up to grazing."""
    log("Energy")
    energy = {}
    for name in args.real:
        rows = r.albedo(r.path("%s.ours.npf.exr" % name), r.source(name), albedo_thetas)["rows"]
        energy[name] = [sum(row[-1]) / len(row[-1]) for row in rows]
    return energy


def measure_convergence(r, args, high_spp):
    """Table 1's real comparisons again with `converge` times the samples. If the PSNR barely
    moves, the fit's error, not Monte Carlo noise, is what Table 1 measures: a check of the floors."""
    log("Convergence")
    converged = {}
    for name in args.real:
        ref_hi = r.render_pair(r.source(name), "reference-%dspp" % high_spp, name, spp=high_spp)
        ours_hi = r.render_pair(r.path("%s.ours.npf.exr" % name), "ours-%dspp" % high_spp, name, spp=high_spp)
        converged[name] = {"ours": r.compare_pair(ref_hi, ours_hi)}
    return converged


def measure_table2(r, args, pca_material):
    """Table 2: PCA ratios on a spectrally varying material (the one recipe whose D and G change
    with wavelength: two lobes with different Fresnel, gold and silver, and so different weights
    per wavelength). One lossless fit; every ratio is a re-compression of it (`npf edit
    --compress-pca`), which equals a conversion at that ratio from the same fit. Returns (rows,
    the reference renders, the lossless file)."""
    log("Table 2")
    ref = r.render_pair(r.source(pca_material), "reference", pca_material)  # Table 1's, when it ran
    lossless, lossless_s = r.convert(pca_material, "pca-none", ["--preset", "production", "--pca", "1,1"])
    t2 = []
    for ratios in PCA_RATIOS:
        if ratios is None:
            fitted, seconds, tag = lossless, lossless_s, "pca-none"
        else:
            tag = "pca-%g-%g" % ratios
            fitted = r.path("%s.%s.npf.exr" % (pca_material, tag))
            seconds = r.timed("edit:" + fitted, fitted, [args.npf, "edit", lossless, "-o", fitted, "--no-albedo-check",
                                                         "--compress-pca", "%g,%g" % ratios], source=lossless)
        info = r.run([args.npf, "info", fitted], capture=True)
        ranks = [l.split(":", 1)[1].split()[0] for l in info.splitlines() if l.strip().startswith(("D rank", "G rank"))][:2]
        img = r.render_pair(fitted, tag, pca_material)
        t2.append({"ratios": ratios, "mb": file_mb(fitted), "ranks": ranks, "fit_s": seconds,
                   "m": r.compare_pair(ref, img)})
    return t2, ref, lossless


def measure_ranks(r, args, pca_material, ref, lossless):
    """Evaluation time and PSNR against the SVD rank (re-compressions of the lossless fit)."""
    log("Speed and accuracy")
    rank_rows = []
    for k in RANKS:
        fitted = r.path("%s.rank-%d.npf.exr" % (pca_material, k))
        r.timed("edit:" + fitted, fitted, [args.npf, "edit", lossless, "-o", fitted, "--no-albedo-check",
                                            "--compress-rank", "%d,%d" % (k, k)], source=lossless)
        img = r.render_pair(fitted, "rank-%d" % k, pca_material)
        b = r.bench(fitted)
        rank_rows.append({"rank": k, "mb": file_mb(fitted), "eval_ns": b["eval_memory_ns"],
                          "eval_full_ns": b["eval_memory_full_ns"], "m": r.compare_pair(ref, img)})
    return rank_rows


def plot_speed(images, ladder, pca_material, rank_rows):
    plot(os.path.join(images, "speed_accuracy.png"), [
        {"title": "fit time against render PSNR (the ladder's tiers)", "xlabel": "fit time (s, log)",
         "ylabel": "PSNR (dB)", "logx": True, "legend": "left",
         "series": [(short(name), COLOURS[k % len(COLOURS)],
                     [(max(row["fit_s"], 0.05), min(row["m"]["PSNR"], 99)) for row in ladder[name]["rows"]
                      if row["fit_s"] is not None])
                    for k, name in enumerate(ladder)]},
        {"title": "evaluation time against rank (%s)" % pca_material, "xlabel": "SVD rank of D and G",
         "ylabel": "ns per eval", "series": [
             ("4 hero wavelengths", "0.1,0.3,0.8", [(q["rank"], q["eval_ns"]) for q in rank_rows]),
             ("every stored channel", "0.8,0.2,0.1", [(q["rank"], q["eval_full_ns"]) for q in rank_rows])]}],
        width=1100, height=460)


def draw_pictures(r, args, images):
    """Side-by-side images: the production conversion and the heatmap of its comparison (Table
    1's); the failure case, when it has no Table 1 row, as Table 2's 99 / 99 row (the production
    preset's ratios, without the detail layer, which production keeps on an anisotropic material
    only where it lowers the BRDF-space error). Returns [(material, tag, label)] shown."""
    shown = []
    for name in ("ilm_l3_37_metallic_rgb", "brushed_copper", FAILURE):
        if name in args.real + args.ladder_synthetic + args.table1_synthetic:
            shown.append((name, "ours", "NPF (production)"))
        elif name == FAILURE:
            shown.append((name, "pca-0.99-0.99", "NPF (PCA 99 / 99)"))
    for name, tag, label in shown:
        heat = r.path("%s.%s.heat.png" % (name, tag))
        if not os.path.exists(heat):
            r.compare_pair(r.render_pair(r.source(name), "reference", name),
                           r.render_pair(r.path("%s.%s.npf.exr" % (name, tag)), tag, name), heat)
        side_by_side(os.path.join(images, name + ".png"),
                     [r.picture(r.source(name), "reference", name),
                      r.picture(r.path("%s.%s.npf.exr" % (name, tag)), tag, name), heat],
                     ["reference", label, "relMSE 0..5 %"])
    return shown
