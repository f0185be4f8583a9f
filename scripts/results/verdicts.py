"""The accuracy ladder's verdicts in docs/results.md: which tiers meet the targets and beat the
Neural BRDF, computed from the measured figures (markdown lines)."""

from results.formatting import fmt_psnr, fmt_rms, fmt_size, fraction_label, listing, meets, short
from results.settings import BRDF_MAX_THETA, LIGHTS, NBRDF, TARGETS, TIERS


def ladder_verdicts(ladder):
    """A table, then a few sentences."""
    names = list(ladder)
    with_nbrdf = [n for n in names if ladder[n]["nbrdf"]]
    out = verdict_table(ladder, names, with_nbrdf)
    out.append("")
    out += smallest_tiers(ladder, names)
    if with_nbrdf:
        out += against_network(ladder, with_nbrdf)
    out += refusals_and_noise(ladder, names)
    return out


def verdict_table(ladder, names, with_nbrdf):
    """A row a tier: on which materials it meets each target, and is ahead of the network."""
    labels = [label for _, label, _ in TIERS] + ([NBRDF] if with_nbrdf else [])
    out = ["| tier | " + " | ".join("%g dB at <= %s of the input" % (p, fraction_label(f)) for p, f in TARGETS) +
           " | higher studio PSNR than Neural BRDF | and smaller | higher key-rim PSNR | higher directional PSNR "
           "| lower BRDF rel. RMS than Neural BRDF |",
           "|---|" + "---|" * (len(TARGETS) + 5)]
    for label in labels:
        pool = with_nbrdf if label == NBRDF else names
        cells = []
        for psnr, fraction in TARGETS:
            cells.append(listing([n for n in pool if meets(ladder[n]["by_label"].get(label), psnr, fraction,
                                                           ladder[n]["input_mb"])], len(pool)))
        if label == NBRDF:
            cells += ["", "", "", "", ""]
        else:
            cells += ahead_of_network(ladder, label, with_nbrdf)
        out.append("| %s | %s |" % (label, " | ".join(cells)))
    return out


def ahead_of_network(ladder, label, with_nbrdf):
    """The tier's cells against the network: studio PSNR, and smaller too, each light, BRDF space."""
    # A tier npf refused on a material counts as not ahead there.
    pool = [n for n in with_nbrdf if label in ladder[n]["by_label"]]
    better = [n for n in pool
              if ladder[n]["by_label"][label]["m"]["PSNR"] > ladder[n]["by_label"][NBRDF]["m"]["PSNR"]]
    smaller = [n for n in better if ladder[n]["by_label"][label]["mb"] <= ladder[n]["by_label"][NBRDF]["mb"]]
    cells = [listing(better, len(with_nbrdf)), listing(smaller, len(with_nbrdf))]
    for light in LIGHTS:
        cells.append(listing([n for n in pool if ladder[n]["by_label"][label]["lights"][light]["PSNR"] >
                              ladder[n]["by_label"][NBRDF]["lights"][light]["PSNR"]], len(with_nbrdf)))
    cells.append(listing([n for n in pool if ladder[n]["by_label"][label]["brdf"]["relative_rms"] <
                          ladder[n]["by_label"][NBRDF]["brdf"]["relative_rms"]], len(with_nbrdf)))
    return cells


def smallest_tiers(ladder, names):
    """Per material: the smallest tier that meets each target."""
    out = []
    for psnr, fraction in TARGETS:
        parts = []
        for n in names:
            ok = [row for row in ladder[n]["rows"] if meets(row, psnr, fraction, ladder[n]["input_mb"])]
            best = min(ok, key=lambda row: row["mb"]) if ok else None
            if best:
                parts.append("%s %s (%s dB, 1/%.0f)" % (short(n), best["tier"].split()[0], fmt_psnr(best["m"]["PSNR"]),
                                                       ladder[n]["input_mb"] / best["mb"]))
            else:
                parts.append("%s no tier" % short(n))
        out.append("- **%g dB at <= %s of the input**, the smallest file that does it: %s." %
                   (psnr, fraction_label(fraction), "; ".join(parts)))
    return out


def against_network(ladder, with_nbrdf):
    """The PSNR each tier gains over the network (studio, then key-rim / directional), and the BRDF
    error of both."""
    parts = []
    for n in with_nbrdf:
        nb = ladder[n]["by_label"][NBRDF]
        gains = ["%s %+.1f dB at %.1fx the size" % (row["tier"].split()[0], row["m"]["PSNR"] - nb["m"]["PSNR"],
                                                   row["mb"] / nb["mb"])
                 for row in ladder[n]["rows"] if row["tier"] != NBRDF]
        parts.append("%s (%s dB): %s" % (short(n), fmt_psnr(nb["m"]["PSNR"]), ", ".join(gains)))
    out = ["- **Against Neural BRDF** (studio PSNR of each tier minus the network's, and its size as a "
           "multiple of the network's %s): %s." % (fmt_size(ladder[with_nbrdf[0]]["by_label"][NBRDF]["mb"]),
                                                  "; ".join(parts))]
    parts = []
    for n in with_nbrdf:
        nb = ladder[n]["by_label"][NBRDF]
        cells = ["%s %+.1f / %+.1f" % (row["tier"].split()[0],
                                       *(row["lights"][light]["PSNR"] - nb["lights"][light]["PSNR"]
                                         for light in LIGHTS))
                 for row in ladder[n]["rows"] if row["tier"] != NBRDF]
        parts.append("%s (%s / %s dB): %s" % (short(n), *(fmt_psnr(nb["lights"][light]["PSNR"]) for light in LIGHTS),
                                              ", ".join(cells)))
    out.append("- **Against Neural BRDF under key-rim / directional** (each tier's PSNR minus the network's, "
               "in dB): %s." % "; ".join(parts))
    parts = []
    for n in with_nbrdf:
        nb = ladder[n]["by_label"][NBRDF]
        cells = ["%s %s" % (row["tier"].split()[0], fmt_rms(row["brdf"])) for row in ladder[n]["rows"]
                 if row["tier"] != NBRDF]
        parts.append("%s (network %s): %s" % (short(n), fmt_rms(nb["brdf"]), ", ".join(cells)))
    out.append("- **BRDF rel. RMS against Neural BRDF** (at the reference pairs within %g degrees): %s." % (
        BRDF_MAX_THETA, "; ".join(parts)))
    return out


def refusals_and_noise(ladder, names):
    """The conversions npf refused, and the PSNRs too close to their noise floor to judge."""
    out = []
    refused = ["%s %s" % (short(n), f["tier"]) for n in names for f in ladder[n]["failed"]]
    if refused:
        out.append("- **Refused.** `npf convert` refused these conversions (its error is in the tier's row of the "
                   "material's table): %s. They count as missing every target and as behind the network." %
                   ", ".join(refused))
    limited = ["%s %s (studio)" % (short(n), row["tier"]) for n in names for row in ladder[n]["rows"]
               if row["m"].get("noise_limited")]
    limited += ["%s %s (key-rim)" % (short(n), row["tier"]) for n in names for row in ladder[n]["rows"]
                if row["lights"]["key-rim"].get("noise_limited")]
    out.append("- **Noise.** %s" % (
        "Every studio and key-rim PSNR in the tables is more than 3 dB below its paired noise floor, so each "
        "measures the materials' difference, not the renders' noise (directional renders have none)." if not limited
        else "Within 3 dB of the noise floor (starred; their true PSNR is higher, so a target they meet holds, one "
        "they miss may not): %s. Directional renders have no noise." % ", ".join(limited)))
    return out
