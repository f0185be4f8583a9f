"""make-results.py's pictures, drawn with oiiotool (OpenImageIO's tool, already a dependency) and
the DejaVu font: line plots and side-by-side strips."""

import math
import os
import subprocess

from results.settings import FONT

COLOURS = ["0.1,0.6,0.2", "0.95,0.55,0.0", "0.5,0.2,0.7", "0.1,0.35,0.85", "0.85,0.1,0.1", "0.55,0.3,0.1",
           "0.0,0.6,0.6", "0.4,0.4,0.4"]


def plot(path, panels, width=1000, height=420):
    """panels: list of dicts with title, xlabel, ylabel, logx, series [(label, colour, [(x, y)])
    or (label, colour, [(x, y)], style)], and optional hlines [(y, label)] (dashed guides) and
    legend ("right", default, or "left"). style: {"line": False} draws points only, {"marker":
    "ring"} hollow squares, {"marker": "cross"} crosses, {"in_order": True} joins the points in the
    order given (else by x), {"legend": False} leaves the series out of the legend. Drawn with
    oiiotool: axes, ticks, polylines, points, labels."""
    n = len(panels)
    pw = width // n
    cmd = ["oiiotool", "--create", "%dx%d" % (width, height), "3", "--fill:color=1,1,1", "%dx%d" % (width, height)]

    def text(x, y, s, size=14, color="0,0,0"):
        cmd.extend(["--text:x=%d:y=%d:size=%d:color=%s:font=%s" % (x, y, size, color, FONT), s])

    def marker(kind, colour, px, py):
        if kind == "cross":
            cmd.extend(["--line:color=%s" % colour, "%d,%d,%d,%d" % (px - 5, py - 5, px + 5, py + 5),
                        "--line:color=%s" % colour, "%d,%d,%d,%d" % (px - 5, py + 5, px + 5, py - 5)])
        elif kind == "ring":
            cmd.extend(["--box:color=%s" % colour, "%d,%d,%d,%d" % (px - 5, py - 5, px + 5, py + 5)])
        else:
            cmd.extend(["--box:color=%s:fill=1" % colour, "%d,%d,%d,%d" % (px - 3, py - 3, px + 3, py + 3)])

    for i, p in enumerate(panels):
        x0, x1 = i * pw + 70, (i + 1) * pw - 20
        y0, y1 = height - 60, 40  # y grows downwards
        series = [tuple(s) + ({},) if len(s) == 3 else tuple(s) for s in p["series"]]
        pts = [pt for s in series for pt in s[2]]
        fx = (lambda v: math.log10(v)) if p.get("logx") else (lambda v: v)
        xs = [fx(x) for x, _ in pts]
        ys = [y for _, y in pts] + [y for y, _ in p.get("hlines", [])]
        xlo, xhi = min(xs), max(xs)
        ylo, yhi = min(ys), max(ys)
        padx = (xhi - xlo) * 0.08 or 1.0
        pady = (yhi - ylo) * 0.1 or 1.0
        xlo, xhi, ylo, yhi = xlo - padx, xhi + padx, ylo - pady, yhi + pady

        def to_px(x, y):
            return (x0 + (fx(x) - xlo) / (xhi - xlo) * (x1 - x0), y0 - (y - ylo) / (yhi - ylo) * (y0 - y1))

        cmd.extend(["--line:color=0,0,0", "%d,%d,%d,%d,%d,%d" % (x0, y1, x0, y0, x1, y0)])
        for k in range(5):  # ticks
            vy = ylo + (yhi - ylo) * k / 4
            py = y0 - (y0 - y1) * k / 4
            cmd.extend(["--line:color=0.8,0.8,0.8", "%d,%d,%d,%d" % (x0 + 1, py, x1, py)])
            text(x0 - 62, int(py) + 5, "%.4g" % vy, 12)
            vx = xlo + (xhi - xlo) * k / 4
            px = x0 + (x1 - x0) * k / 4
            text(int(px) - 18, y0 + 18, "%.3g" % (10 ** vx if p.get("logx") else vx), 12)
        for y, label in p.get("hlines", []):  # dashed guides
            _, py = to_px(10 ** xlo if p.get("logx") else xlo, y)
            for xa in range(x0 + 2, x1, 12):
                cmd.extend(["--line:color=0.5,0.5,0.5", "%d,%d,%d,%d" % (xa, py, min(xa + 6, x1), py)])
            text(x0 + 6, int(py) - 4, label, 12, "0.4,0.4,0.4")
        text(x0, y1 - 16, p["title"], 16)
        text((x0 + x1) // 2 - 60, height - 15, p["xlabel"], 13)
        text(x0 + 5, y1 + 14, p["ylabel"], 13)
        legend_x = x0 + 110 if p.get("legend") == "left" else x1 - 190
        j = 0
        for label, colour, points, style in series:
            if len(points) > 1 and style.get("line", True):
                coords = []
                for x, y in (points if style.get("in_order") else sorted(points)):
                    px, py = to_px(x, y)
                    coords += [int(px), int(py)]
                cmd.extend(["--line:color=%s" % colour, ",".join(map(str, coords))])
            for x, y in points:
                px, py = to_px(x, y)
                marker(style.get("marker", "box"), colour, int(px), int(py))
            if style.get("legend", True):
                text(legend_x, y1 + 20 + 18 * j, label, 13, colour)
                j += 1
    tmp = path + ".tmp.png"
    subprocess.run(cmd + ["-d", "uint8", "-o", tmp], check=True, stdout=subprocess.DEVNULL)
    os.replace(tmp, path)


def side_by_side(path, images, labels):
    cmd = ["oiiotool"]
    for img, label in zip(images, labels):
        cmd += [img, "--ch", "R,G,B", "--text:x=8:y=22:size=16:color=1,1,1:font=%s" % FONT, label]
    cmd += ["--mosaic", "%dx1" % len(images), "-d", "uint8", "-o", path + ".tmp.png"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    os.replace(path + ".tmp.png", path)
