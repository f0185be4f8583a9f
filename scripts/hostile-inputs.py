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


def first_line(text):
    for line in text.splitlines():
        if line.strip():
            return line.strip()
    return ""


class Catalogue:
    def __init__(self, npf, work):
        self.npf, self.work, self.rows, self.failed = npf, work, [], 0

    def path(self, name):
        return os.path.join(self.work, name)

    def run(self, args, fsize_kib=None, timeout=600):
        pre = None
        if fsize_kib is not None:
            import resource
            import signal

            def pre():
                signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
                resource.setrlimit(resource.RLIMIT_FSIZE, (fsize_kib * 1024, fsize_kib * 1024))
        p = subprocess.run([self.npf] + args, capture_output=True, text=True, preexec_fn=pre, timeout=timeout)
        return p.returncode, first_line(p.stderr) or first_line(p.stdout)

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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--npf", default="build/tools/npf/npf")
    ap.add_argument("--rgl", default="../shared/data/rgl")
    a = ap.parse_args()
    npf = os.path.abspath(a.npf)
    work = tempfile.mkdtemp(prefix="npf-hostile-")
    c = Catalogue(npf, work)
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
    left = c.leftovers(work, os.listdir(work))
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

    print("| input or output | command | exit | what it gets (first line) | also |")
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
