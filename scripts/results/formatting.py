"""How make-results.py writes its figures in docs/results.md: PSNR, sizes, albedo, BRDF error, and
the targets' tests."""

import math


def fmt_psnr(v):
    return "inf" if math.isinf(v) else "%.2f" % v


def fmt_psnr_judged(m):
    """The PSNR, starred when it is within 3 dB of its noise floor (it then measures noise)."""
    return fmt_psnr(m["PSNR"]) + (" *" if m.get("noise_limited") else "")


def metrics_cells(m):
    return ["%.2f %%" % (100 * m["MAPE"]), "%.5f" % m["relMSE"], fmt_psnr_judged(m), fmt_psnr(m["noise_floor_db"]),
            "%.4f" % m["SSIM"]]


FLOOR_NOTE = ("Floor: the PSNR's paired noise floor ([metrics.md](metrics.md), `npf compare --floor`), from the same "
              "two materials rendered again at seed 2; a PSNR within 3 dB of it (starred) measures Monte Carlo "
              "noise, not the fit.")


def short(name):
    return name[:-4] if name.endswith("_rgb") else name


def fmt_size(mb):
    return "%.1f KB" % (mb * 1e3) if mb < 1 else "%.2f MB" % mb


def fmt_albedo(worst):
    """The worst relative difference, with its standard error where that is not small beside it."""
    v, se = 100 * worst["relative_difference"], 100 * worst["standard_error"]
    text = "%+.1f %% (%g deg)" % (v, worst["theta_deg"])
    return text + (" +- %.1f" % se if se >= 0.5 else "")


def fmt_rms(b):
    return "%.2f %%" % (100 * b["relative_rms"])


def meets(row, psnr, fraction, input_mb):
    return row is not None and row["m"]["PSNR"] >= psnr and row["mb"] <= fraction * input_mb


def fraction_label(fraction):
    return "1/%d" % round(1 / fraction)


def listing(names, total):
    """'3 of 6: felt, paper_white, brushed_copper' (or 'none of 6', 'all 6')."""
    if not names:
        return "none of %d" % total
    if len(names) == total:
        return "all %d" % total
    return "%d of %d: %s" % (len(names), total, ", ".join(short(n) for n in names))
