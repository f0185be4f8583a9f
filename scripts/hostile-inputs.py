#!/usr/bin/env python3
"""Runs the npf tool on a catalogue of hostile inputs and outputs (damaged, absurd, sparse,
special files, a full disk) and prints what each gets as a Markdown table: the exit status, the
first line of the error, whether anything was left behind and, for outputs, whether the earlier
output survived. docs/reliability.md sec. 4 is this script's output.

    python3 scripts/hostile-inputs.py [--npf build/tools/npf/npf] [--rgl DIR_OF_RGL_FILES]

Every case states what a user should get; a row whose result breaks that is marked FAIL and the
script exits 1. Needs no root; sparse files cost no disk.
"""
import argparse
import os
import shutil
import stat
import struct
import subprocess
import sys
import tempfile

MAGIC = b"tensor_file\0"


def tensor_file(fields):
    """A tensor_file v1.0 with the given fields: (name, dtype code, shape, payload bytes or None,
    offset or None). Payloads are laid out after the descriptors unless an offset is given."""
    head = MAGIC + bytes([1, 0]) + struct.pack("<I", len(fields))
    desc_size = sum(2 + len(n) + 2 + 1 + 8 + 8 * len(shape) for n, _, shape, _, _ in fields)
    pos = len(head) + desc_size
    pos = (pos + 7) // 8 * 8
    descs, payloads = b"", []
    for name, code, shape, payload, offset in fields:
        off = offset if offset is not None else pos
        descs += struct.pack("<H", len(name)) + name.encode() + struct.pack("<HBQ", len(shape), code, off)
        descs += b"".join(struct.pack("<Q", e) for e in shape)
        if payload is not None and offset is None:
            payloads.append((off, payload))
            pos = (off + len(payload) + 7) // 8 * 8
    out = bytearray(head + descs)
    for off, payload in payloads:
        out.extend(b"\0" * (off - len(out)))
        out.extend(payload)
    return bytes(out)


DTYPE_SIZE = {1: 1, 2: 1, 3: 2, 4: 2, 5: 4, 6: 4, 7: 8, 8: 8, 9: 2, 10: 4, 11: 8}


def tensor_fields(data):
    """The fields of a tensor_file as tensor_file() takes them, payloads copied out."""
    count = struct.unpack_from("<I", data, 14)[0]
    pos, fields = 18, []
    for _ in range(count):
        n = struct.unpack_from("<H", data, pos)[0]
        name = data[pos + 2:pos + 2 + n].decode()
        rank, code, offset = struct.unpack_from("<HBQ", data, pos + 2 + n)
        shape = list(struct.unpack_from("<%dQ" % rank, data, pos + 2 + n + 11))
        pos += 2 + n + 11 + 8 * rank
        size = DTYPE_SIZE[code]
        for e in shape:
            size *= e
        fields.append([name, code, shape, data[offset:offset + size], None])
    return fields


def patched_rgl(data, edit):
    """A real RGL file's fields, changed by edit(fields), written again."""
    fields = tensor_fields(data)
    edit(fields)
    return tensor_file([tuple(f) for f in fields])


def field(fields, name):
    return next(f for f in fields if f[0] == name)


def first_line(text):
    for line in text.splitlines():
        if line.strip():
            return line.strip()
    return ""


class Catalogue:
    def __init__(self, npf, work, baseline=None):
        self.npf, self.work, self.rows, self.failed, self.baseline = npf, work, [], 0, baseline

    def path(self, name):
        return os.path.join(self.work, name)

    def run(self, args, fsize_kib=None, timeout=600, npf=None, stdin=None, memory_gib=None):
        import resource
        import signal

        def pre():
            if fsize_kib is not None:
                signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
                resource.setrlimit(resource.RLIMIT_FSIZE, (fsize_kib * 1024, fsize_kib * 1024))
            if memory_gib is not None:
                resource.setrlimit(resource.RLIMIT_AS, (memory_gib << 30, memory_gib << 30))
        try:
            with open(stdin, "rb") if stdin else open(os.devnull, "rb") as source:
                p = subprocess.run([npf or self.npf] + args, capture_output=True, text=True, errors="replace", preexec_fn=pre,
                                   timeout=timeout, stdin=source)
        except subprocess.TimeoutExpired:
            return -1, "still running after %d s: stopped" % timeout
        if p.returncode < 0:
            return p.returncode, "killed by signal %d%s" % (-p.returncode, (": " + first_line(p.stderr)) if p.stderr.strip() else "")
        return p.returncode, first_line(p.stderr) or first_line(p.stdout)

    def case(self, what, shown_command, setup, args, expect, check=None, **run_options):
        """One case run on the baseline binary (when given: what main did before) and on this
        build, each from a fresh setup(); check(status) says whether what is left is right."""
        before = ""
        if self.baseline:
            setup()
            b_status, b_msg = self.run(args, npf=self.baseline, **run_options)
            b_ok = (b_status == expect) and (check is None or check(b_status))
            before = "%d: %s" % (b_status, b_msg.replace(self.work + "/", "").replace("|", "\\|")[:120])
            if not b_ok:
                before += " (broken)"
        setup()
        status, msg = self.run(args, **run_options)
        self.row(what, shown_command, expect, status, msg, check is None or check(status), before)

    def row(self, what, shown_command, expect, status, message, extra_ok=True, extra=""):
        ok = (status == expect if isinstance(expect, int) else status in expect) and extra_ok
        if not ok:
            self.failed += 1
        message = message.replace(self.work + "/", "").replace("|", "\\|")
        if len(message) > 200:
            message = message[:200] + " ..."
        self.rows.append("| %s | `%s` | %d%s | %s | %s |" % (what, shown_command, status, "" if ok else " **FAIL**",
                                                           message, extra))

    def leftovers(self, folder, keep):
        return sorted(set(os.listdir(folder)) - set(keep))


def nothing():
    return None


def bounded_text_cases(c, p, good, raw, small):
    """Bounded text: inputs far larger than any material. Returns a small factor texture the later cases use."""
    # Bounded text.
    zeros = p("zeros.txt")
    open(zeros, "wb").close()
    os.truncate(zeros, 3 << 30)
    small = p("m33.exr")
    subprocess.run([c.npf, "convert", good, "-o", small, "--preset", "preview", "--no-predict", "--quiet"], check=True)
    c.case("3 GB of zeros on standard input (/dev/zero)", "npf eval m.exr < zeros", nothing, ["eval", small], 1,
           stdin=zeros, timeout=60, memory_gib=2)
    big_recipe = p("big.yaml")
    c.case("a 2 MiB recipe of zeros", "npf info big.yaml",
           lambda: (open(big_recipe, "wb").close(), os.truncate(big_recipe, 2 << 20)), ["info", big_recipe], 1, timeout=60)
    return small


def material_product_cases(c, p, good, raw, small):
    """What a material can produce: products of tables each under the value cap, needles, huge grids."""
    # What a material can produce: products of tables each under the 1e12 cap.
    copper = p("copper.exr")
    subprocess.run([c.npf, "convert", "configs/materials/brushed_copper.yaml", "-o", copper, "--preset", "preview",
                    "--no-predict", "--quiet"], check=True)
    huge = p("huge.exr")
    made = subprocess.run(["oiiotool", "-a", copper, "--mulc", "1e4", "--eraseattrib", "npf:tables_checksum", "-d", "float",
                           "-o", huge], capture_output=True)
    if made.returncode == 0:
        c.case("a factor texture with every table times 1e4 (each value under the cap, no checksum)", "npf info --check huge.exr",
               nothing, ["info", "--check", huge], 1)
        c.case("the same, evaluated", "npf eval huge.exr --dirs probe_dirs.txt", nothing,
               ["eval", huge, "--dirs", "data/materials/probe_dirs.txt"], 1)
        out = p("from_huge.exr")
        c.case("the same, converted", "npf convert huge.exr -o out.exr", lambda: os.path.exists(out) and os.remove(out),
               ["convert", huge, "-o", out, "--preset", "preview", "--no-predict"], 1, lambda s: not os.path.exists(out))
        c.case("the same, capped at albedo 1", "npf edit huge.exr -o out.exr --limit-albedo 1",
               lambda: os.path.exists(out) and os.remove(out), ["edit", huge, "-o", out, "--limit-albedo", "1"], 1,
               lambda s: not os.path.exists(out))

    def tiny_sigma(fields):
        f = field(fields, "sigma")
        f[3] = struct.pack("<f", 1e-40) + f[3][4:]
    sigma = p("sigma.bsdf")
    c.case("an RGL file whose projected area sigma is 1e-40 at one node", "npf render sigma.bsdf -o r.exr",
           lambda: open(sigma, "wb").write(patched_rgl(raw, tiny_sigma)),
           ["render", sigma, "-o", p("r.exr"), "--size", "16", "--spp", "4", "--quiet"], 1)
    needle = p("needle.yaml")
    c.case("an analytic lobe of roughness 1e-4 and weight 1e6", "npf info needle.yaml",
           lambda: open(needle, "w").write("lobes:\n  - {distribution: ggx, alpha: 0.0001, weight: 1000000}\n"),
           ["info", needle], 1)

    griddy = p("griddy.yaml")
    c.case("a recipe whose grid is 4096 on every axis", "npf synth --recipe griddy.yaml -o g.bsdf",
           lambda: open(griddy, "w").write("lobes:\n  - {distribution: ggx, alpha: 0.3}\n"
                                           "grid: {phi: 4096, theta: 4096, data: 4096, vndf: 4096}\nanisotropy: anisotropic\n"),
           ["synth", "--recipe", griddy, "-o", p("g.bsdf")], 1, lambda s: not os.path.exists(p("g.bsdf")), timeout=120,
           memory_gib=8)


def aliased_output_cases(c, p, good, raw, small):
    """Outputs against each other and the inputs."""
    # Outputs against each other and the inputs.
    m = p("alias.exr")
    def fresh_alias():
        shutil.copy(small, m)
        for f in ("hard.exr", "x"):
            if os.path.lexists(p(f)):
                os.remove(p(f))
        os.link(m, p("hard.exr"))
    intact = lambda s: open(m, "rb").read() == open(small, "rb").read()  # noqa: E731
    c.case("a render over its own material", "npf render m.exr -o m.exr", fresh_alias,
           ["render", m, "-o", m, "--size", "8", "--spp", "1", "--quiet"], 1, intact)
    c.case("-o and --png naming one file", "npf render m.exr -o x --png x", fresh_alias,
           ["render", m, "-o", p("x"), "--png", p("x"), "--size", "8", "--spp", "1", "--quiet"], 1,
           lambda s: not os.path.exists(p("x")))
    c.case("a conversion onto a hard link of its input", "npf convert m.exr -o hard.exr", fresh_alias,
           ["convert", m, "-o", p("hard.exr"), "--preset", "preview", "--no-predict"], 1, intact)


def strict_validation_cases(c, p, good, raw, small):
    """Loose validation made strict: RGL fields out of their contract."""
    # Loose validation made strict.
    def set_u8(name, value):
        def edit(fields):
            field(fields, name)[3] = bytes([value])
        return edit

    def short_valid(fields):
        f = field(fields, "valid")
        f[2], f[3] = [3], f[3][:3]

    def version_9_9(fields):
        field(fields, "version")[3] = struct.pack("<II", 9, 9)

    def rgb_and_spectra(fields):
        rgb = field(fields, "rgb")
        fields.append(["spectra", rgb[1], list(rgb[2]), rgb[3], None])
        fields.append(["wavelengths", 10, [3], struct.pack("<3f", 450, 550, 650), None])
    for what, name, edit in [("an RGL file with jacobian = 7", "jacobian7.bsdf", set_u8("jacobian", 7)),
                             ("an RGL file with a 3-byte valid mask", "valid3.bsdf", short_valid),
                             ("an RGL file of version 9.9", "version.bsdf", version_9_9),
                             ("an RGL file with both rgb and spectra", "both.bsdf", rgb_and_spectra)]:
        f = p(name)
        c.case(what, "npf info " + name, lambda f=f, edit=edit: open(f, "wb").write(patched_rgl(raw, edit)), ["info", f], 1)


def image_name_cases(c, p, good, raw, small):
    """Images npf reads as data: regular files of a format known by its first bytes."""
    # Images npf reads as data: regular files of a format known by its first bytes.
    fifo_env = p("env_fifo.exr")
    c.case("a FIFO as the environment map", "npf render m.exr --env fifo.exr",
           lambda: os.path.exists(fifo_env) or os.mkfifo(fifo_env),
           ["render", small, "-o", p("e.exr"), "--env", fifo_env, "--size", "8", "--spp", "1", "--quiet"], 1, timeout=20)
    null_env = p("x.null?RES=20000x20000")
    c.case("an environment map whose name OpenImageIO takes parameters from", "npf render m.exr --env 'x.null?RES=20000x20000'",
           lambda: open(null_env, "wb").close(),
           ["render", small, "-o", p("e.exr"), "--env", null_env, "--size", "8", "--spp", "1", "--quiet"], 1, timeout=60,
           memory_gib=8)


def nbrdf_link_cases(c, p, good, raw, small):
    """Neural BRDF files that would make npf read other files (fuzz/corpus/nbrdf/, made with HDF5)."""
    # Neural BRDF files that would make npf read other files (fuzz/corpus/nbrdf/, made with HDF5).
    corpus = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fuzz", "corpus", "nbrdf")
    for what, name in [("a Neural BRDF file whose kernel is stored in ../../etc/hostname (external storage)", "external_storage.h5"),
                       ("a Neural BRDF file whose layer is an external link to another file", "external_link.h5"),
                       ("a Neural BRDF file with a soft link", "soft_link.h5"),
                       ("a Neural BRDF file with a link loop", "link_loop.h5"),
                       ("a Neural BRDF file with a virtual dataset", "virtual_dataset.h5")]:
        f = p(name)
        c.case(what, "npf info " + name, lambda f=f, name=name: shutil.copy(os.path.join(corpus, name), f), ["info", f], 1,
               timeout=30)


def colour_config_cases(c, p, good, raw, small):
    """Colour configurations: refused, not crashed or hung on."""
    # Colour configurations: refused, not crashed or hung on.
    scene = p("scene.exr")
    subprocess.run([c.npf, "render", small, "-o", scene, "--size", "8", "--spp", "1", "--quiet"], check=True)
    png = p("shown.png")
    no_png = lambda s: not os.path.exists(png)  # noqa: E731

    def ocio_config(name, spaces, lut=None, lut_data=None):
        folder = p(name)
        shutil.rmtree(folder, ignore_errors=True)
        os.makedirs(os.path.join(folder, "luts"))
        view = "lut" if lut else "scene"
        with open(os.path.join(folder, "config.ocio"), "w") as out:
            out.write("ocio_profile_version: 2.1\nsearch_path: \"luts\"\nroles: {default: scene, scene_linear: scene}\n"
                      "file_rules:\n  - !<Rule> {name: Default, colorspace: default}\n"
                      "displays:\n  d:\n    - !<View> {name: v, colorspace: %s}\ncolorspaces:\n"
                      "  - !<ColorSpace> {name: scene}\n%s" % (view, spaces))
            if lut:
                out.write("  - !<ColorSpace> {name: lut, from_scene_reference: !<FileTransform> {src: %s}}\n" % lut)
        if lut_data:
            lut_data(folder)
        if os.path.exists(png):
            os.remove(png)
        return os.path.join(folder, "config.ocio")
    cycle_config = p("cycle.ocio")

    def write_cycle():
        with open(cycle_config, "w") as out:
            out.write("ocio_profile_version: 2.1\nroles: {default: A, scene_linear: A}\n"
                      "file_rules:\n  - !<Rule> {name: Default, colorspace: default}\n"
                      "displays:\n  d:\n    - !<View> {name: v, colorspace: out}\ncolorspaces:\n  - !<ColorSpace> {name: out}\n"
                      "  - !<ColorSpace> {name: A, to_scene_reference: !<ColorSpaceTransform> {src: B, dst: out}}\n"
                      "  - !<ColorSpace> {name: B, to_scene_reference: !<ColorSpaceTransform> {src: A, dst: out}}\n")
        if os.path.exists(png):
            os.remove(png)
    c.case("an OCIO config whose colour spaces refer to each other", "npf display scene.exr --config cycle.ocio", write_cycle,
           ["display", scene, "-o", png, "--config", cycle_config], 1, no_png, timeout=60)
    fifo_config = p("fifo.ocio")
    c.case("an OCIO config that is a FIFO", "npf display scene.exr --config fifo.ocio",
           lambda: os.path.exists(fifo_config) or os.mkfifo(fifo_config),
           ["display", scene, "-o", png, "--config", fifo_config], 1, no_png, timeout=30)
    fifo_lut = p("fifolut/config.ocio")
    c.case("an OCIO config whose LUT is a FIFO", "npf display scene.exr --config fifolut.ocio",
           lambda: ocio_config("fifolut", "", "fifo.cube", lambda f: os.mkfifo(os.path.join(f, "luts", "fifo.cube"))),
           ["display", scene, "-o", png, "--config", fifo_lut], 1, no_png, timeout=30)
    outside = p("outside/config.ocio")

    def outside_lut(folder):
        with open(os.path.join(folder, "secret.cube"), "w") as out:
            out.write("LUT_1D_SIZE 2\n0 0 0\n1 1 1\n")
    c.case("an OCIO config whose LUT lies outside its search path", "npf display scene.exr --config outside.ocio",
           lambda: ocio_config("outside", "", "../secret.cube", outside_lut),
           ["display", scene, "-o", png, "--config", outside], 1, no_png, timeout=30)


def batch_place_cases(c, p, good, raw, small):
    """The batch's own places, and its outputs against its inputs; a name that splits lines."""
    # The batch's own places, and its outputs against its inputs.
    def batch_folder(name, output_link=False):
        root = p(name)
        shutil.rmtree(root, ignore_errors=True)
        for d in ("in", "out/.npf-batch", "victim/sub"):
            os.makedirs(os.path.join(root, d))
        shutil.copy(good, os.path.join(root, "in", "m.bsdf"))
        for f in ("victim/keep.txt", "victim/sub/keep.txt"):
            with open(os.path.join(root, f), "w") as out:
                out.write("precious\n")
        with open(os.path.join(root, "b.yaml"), "w") as out:
            out.write("version: 1\noutput_dir: out\ninputs: [\"in/*.bsdf\"]\n"
                      "defaults: {preset: preview, threads: 2, error_pairs: 0}\n")
        if output_link:
            os.symlink("../in/m.bsdf", os.path.join(root, "out", "m.exr"))
        else:
            os.symlink("../../victim", os.path.join(root, "out", ".npf-batch", "shard-0-of-1"))
        return root
    victim_intact = lambda s: sorted(os.listdir(p("linked/victim"))) == ["keep.txt", "sub"]  # noqa: E731
    c.case("a link at the batch's shard folder to a folder outside", "npf batch b.yaml",
           lambda: batch_folder("linked"), ["batch", p("linked/b.yaml"), "--quiet"], 1, victim_intact)
    input_intact = lambda s: open(p("aliased/in/m.bsdf"), "rb").read() == raw  # noqa: E731
    c.case("a batch output that is a link to its input", "npf batch b.yaml",
           lambda: batch_folder("aliased", output_link=True), ["batch", p("aliased/b.yaml"), "--quiet"], 1, input_intact)
    odd = p("two\nlines.bsdf")
    c.case("a newline in a file name", "npf info 'two\\nlines.bsdf'", lambda: open(odd, "wb").write(b"junk"), ["info", odd], 1)


def issue_33_cases(c, good, raw):
    """Issue 33's classes: what a material can produce, bounded text, outputs that alias inputs,
    loose validation, names that split lines (docs/reliability.md sec. 4)."""
    small = bounded_text_cases(c, c.path, good, raw, None)
    material_product_cases(c, c.path, good, raw, small)
    aliased_output_cases(c, c.path, good, raw, small)
    strict_validation_cases(c, c.path, good, raw, small)
    image_name_cases(c, c.path, good, raw, small)
    nbrdf_link_cases(c, c.path, good, raw, small)
    colour_config_cases(c, c.path, good, raw, small)
    batch_place_cases(c, c.path, good, raw, small)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--npf", default="build/tools/npf/npf")
    ap.add_argument("--rgl", default="../shared/data/rgl")
    ap.add_argument("--baseline", help="another npf (an earlier build): its result beside each issue 33 case")
    a = ap.parse_args()
    npf = os.path.abspath(a.npf)
    work = tempfile.mkdtemp(prefix="npf-hostile-")
    c = Catalogue(npf, work, os.path.abspath(a.baseline) if a.baseline else None)
    p = c.path
    good = os.path.join(a.rgl, "ilm_l3_37_metallic_rgb.bsdf")
    if not os.path.exists(good):
        good = p("good.bsdf")
        subprocess.run([npf, "synth", "--recipe", "configs/materials/red_plastic.yaml", "-o", good,
                        "--preset", "preview"], check=False, capture_output=True)
    raw = open(good, "rb").read()

    # ---- Inputs: one line, exit 1, nothing written -------------------------------------------
    def reject(what, name, data=None, command="info", sparse_to=None, setup=None):
        f = p(name)
        if setup:
            setup(f)
        elif data is not None:
            with open(f, "wb") as out:
                out.write(data)
        if sparse_to:
            os.truncate(f, sparse_to)
        status, msg = c.run([command, f] + (["-o", p("never.exr")] if command == "convert" else []))
        c.row(what, "npf %s %s" % (command, name), 1, status, msg, not os.path.exists(p("never.exr")))

    reject("random bytes", "garbage.bsdf", os.urandom(4096))
    reject("an empty file", "empty.bsdf", b"")
    reject("a folder", "folder.bsdf", setup=lambda f: os.mkdir(f))
    reject("a missing file", "missing.bsdf", setup=lambda f: None)
    reject("a FIFO", "fifo.bsdf", setup=lambda f: os.mkfifo(f))
    reject("a link to itself", "loop.bsdf", setup=lambda f: os.symlink(f, f))
    reject("an RGL file cut at 300 kB", "cut.bsdf", raw[:300000], "convert")
    reject("an RGL file with one byte flipped in a header count", "flipped.bsdf", raw[:14] + bytes([raw[14] ^ 0x40]) + raw[15:])
    reject("an RGL field claiming 8 GiB, in a sparse 8 GiB file", "claims.bsdf",
           tensor_file([("data", 10, [1 << 31], None, 64)]), sparse_to=(8 << 30) + 4096)
    reject("an RGL field of rank 65535", "rank.bsdf", tensor_file([("data", 10, [1] * 65535, b"\0" * 4, None)]))
    reject("an RGL field of rank 3 whose extents overflow 64 bits", "overflow.bsdf",
           tensor_file([("data", 10, [1 << 40, 1 << 40, 1 << 40], b"", None)]))
    reject("tensor_file magic, then nothing", "magic.bsdf", MAGIC)
    reject("a MERL header (90 x 90 x 180) and a truncated table", "cut.binary",
           struct.pack("<iii", 90, 90, 180) + b"\0" * 100000)
    reject("a MERL file with a trailing byte, named .dat", "padded.dat",
           struct.pack("<iii", 2, 3, 4) + struct.pack("<72d", *([0.1] * 72)) + b"\0")
    reject("a MERL header claiming 24 GB, in a sparse file of that size", "huge.binary",
           struct.pack("<iii", 1000, 1000, 1000), sparse_to=12 + 1000 ** 3 * 24)
    reject("a MERL table holding 1e300", "big.binary",
           struct.pack("<iii", 1, 1, 2) + struct.pack("<6d", 1e300, 1, 1, 1, 1, 1))
    reject("a text file named .exr", "text.exr", b"not an image\n")
    reject("an OpenEXR magic number and nothing else", "magic.exr", bytes([0x76, 0x2f, 0x31, 0x01]))
    reject("a YAML recipe that is not YAML", "bad.yaml", b"model: [unclosed\n", "convert")
    reject("a YAML recipe nested 100,000 deep", "deep.yaml", b"model: " + b"[" * 100000 + b"\n", "convert")
    reject("/dev/zero as a material", "zero", setup=lambda f: os.symlink("/dev/zero", f))

    # ---- Outputs ------------------------------------------------------------------------------
    small = p("small.exr")
    status, msg = c.run(["convert", good, "-o", small, "--preset", "preview", "--no-predict"])
    c.row("a first good output", "npf convert ILM -o small.exr --preset preview", 0, status, msg)
    before = open(small, "rb").read() if os.path.exists(small) else b""
    status, msg = c.run(["convert", good, "-o", small, "--preset", "production", "--no-predict"], fsize_kib=16)
    after = open(small, "rb").read() if os.path.exists(small) else b""
    c.row("a full disk (writes beyond 16 KiB fail) over an earlier output", "npf convert ILM -o small.exr", 1, status, msg,
          after == before and before != b"", "earlier output %s" % ("intact" if after == before else "LOST"))
    status, msg = c.run(["convert", good, "-o", "/dev/null", "--preset", "preview", "--no-predict"])
    c.row("-o /dev/null", "npf convert ILM -o /dev/null", 0, status, msg,
          stat.S_ISCHR(os.stat("/dev/null").st_mode), "/dev/null %s" % ("still a device" if stat.S_ISCHR(os.stat("/dev/null").st_mode) else "REPLACED"))
    os.mkdir(p("outdir"))
    status, msg = c.run(["convert", good, "-o", p("outdir"), "--preset", "preview", "--no-predict"])
    c.row("-o a folder", "npf convert ILM -o outdir", 1, status, msg, os.path.isdir(p("outdir")))
    status, msg = c.run(["convert", good, "-o", p("no/such/folder/x.exr"), "--preset", "preview", "--no-predict"])
    c.row("-o into a missing folder", "npf convert ILM -o no/such/folder/x.exr", 1, status, msg)

    # ---- Small ones ---------------------------------------------------------------------------
    dirs = p("dirs.txt")
    with open(dirs, "w") as f:
        f.write("0.3 0 1 -0.2 0.1 1\n3e307 0 1e308 -2e307 1e307 1e308\n")
    proc = subprocess.run([npf, "eval", good, "--dirs", dirs], capture_output=True, text=True)
    values = [l for l in proc.stdout.splitlines() if l and not l.startswith("#")]
    same = len(values) == 2 and values[0] == values[1]
    c.row("direction components of 1e308", "npf eval ILM --dirs dirs.txt", 0, proc.returncode,
          "the same values as the unit direction" if same else "DIFFERENT values", same)

    # ---- A batch whose inputs glob covers its own output folder ------------------------------
    lib = p("lib")
    os.mkdir(lib)
    shutil.copy(good, os.path.join(lib, "m.bsdf"))
    with open(os.path.join(lib, "batch.yaml"), "w") as f:
        f.write("version: 1\noutput_dir: .\nnaming: \"{name}_npf.exr\"\ninputs: [\"*\"]\n"
                "defaults: {preset: preview, threads: 2}\n")
    runs = []
    for _ in range(3):
        status, msg = c.run(["batch", os.path.join(lib, "batch.yaml"), "--quiet"])
        runs.append(status)
    files = sorted(f for f in os.listdir(lib) if f.endswith(".exr"))
    c.row("a batch whose input glob covers its own output folder, run three times", "npf batch batch.yaml",
          0, max(runs), "outputs after three runs: " + ", ".join(files), files == ["m_npf.exr"])

    issue_33_cases(c, good, raw)

    print("| input or output | command | exit | what it gets (first line) | also%s |" %
          (" / main 2821a5e: exit, first line" if c.baseline else ""))
    print("|---|---|---|---|---|")
    for r in c.rows:
        print(r)
    shutil.rmtree(work, ignore_errors=True)
    if c.failed:
        print("\n%d case(s) FAILED" % c.failed, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
