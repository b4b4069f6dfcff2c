#!/usr/bin/env python3
"""check-cost.py — what `splatref check` costs for each image it is handed.

For every file of the given folders (fuzz_image's corpus format: the first byte
picks PNG (even) or PFM (odd), the rest is the file; with --plain the files are
images as they are, their extension naming the format), of at most --max-bytes,
runs

    splatref check --scene S --image FILE --out DIR --quiet

and measures the child's own peak resident memory and wall time (os.wait4: the
rusage of that one process).  Prints the worst of each, with the file, and the
same for the same check with the scene's own reference image (the cost of the
scene alone), so the cost the input adds can be read off.  Exits 1 when an
input takes more than --max-mb or --max-s, or when check's exit status is not
0, 1 or 2 (a crash).

    python3 tools/check-cost.py --cli build/splatref --scene s.json build/fuzz-corpus-image tests/fuzz/corpus/image

Written in Python rather than a shell loop over /usr/bin/time: wait4 gives each
child's rusage without parsing, and the timing is taken around the process only.
"""
import argparse
import os
import shutil
import subprocess
import sys
import struct
import tempfile
import time
import zlib


def png(w, h, depth, colour, rows, interlace=0, idat_cut=None):
    """A PNG of the given header whose image data is `rows` (raw scanlines, filter bytes included), deflated;
    idat_cut keeps only that many bytes of the deflated data."""
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    z = zlib.compress(rows, 9)
    if idat_cut is not None:
        z = z[:idat_cut]
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, colour, 0, 0, interlace))
            + chunk(b"IDAT", z) + chunk(b"IEND", b""))


def crafted(w, h, into, max_bytes):
    """Inputs of at most 64 KiB that make a reader of the scene's size W x H work hardest: the largest raw image
    (16-bit RGBA, zeros, which deflate stretches about 1000:1), interlaced, its data cut short, a PFM of that size
    whose data is cut short, and a PNG of one more row (refused by its header)."""
    row16 = b"\x00" + b"\x00" * (8 * w)
    made = {
        "rgba16.png": png(w, h, 16, 6, row16 * h),
        "rgba16-interlaced.png": png(w, h, 16, 6, b"\x00" * (h * (1 + 8 * w) + 8 * h), interlace=1),
        "rgba16-cut.png": png(w, h, 16, 6, row16 * h, idat_cut=200),
        "rgb8-random-rows.png": png(w, h, 8, 2, b"".join(b"\x04" + bytes((x * 7 + y) & 255 for x in range(3 * w)) for y in range(h))),
        "tall.png": png(w, h + 1, 16, 6, row16 * (h + 1)),
        "cut.pfm": b"PF\n%d %d\n-1.0\n" % (w, h) + b"\x00" * 60000,
    }
    for name, data in made.items():
        with open(os.path.join(into, name), "wb") as f:
            f.write(data)
    return [os.path.join(into, n) for n in made if len(made[n]) <= max_bytes]


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    return struct.unpack(">II", head[16:24])


def run(cli, scene, image, out):
    t0 = time.monotonic()
    p = subprocess.Popen([cli, "check", "--scene", scene, "--image", image, "--out", out, "--quiet"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    err = p.stderr.read()
    _, status, ru = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)  # reaped here: Popen must not wait for it again
    p.stderr.close()
    return p.returncode, ru.ru_maxrss / 1024.0, time.monotonic() - t0, err.decode(errors="replace")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cli", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--baseline", help="an image the scene passes (default: render the scene's own)")
    ap.add_argument("--plain", action="store_true", help="the files are images as they are")
    ap.add_argument("--crafted", action="store_true", help="also the worst cases made here for the scene's size (see crafted())")
    ap.add_argument("--max-bytes", type=int, default=65536)
    ap.add_argument("--max-mb", type=float, default=200.0)
    ap.add_argument("--max-s", type=float, default=1.0)
    ap.add_argument("dirs", nargs="+")
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="check-cost-")
    try:
        own_png = os.path.join(work, "own.png")
        subprocess.run([a.cli, "render", "--scene", a.scene, "--float", os.path.join(work, "own.pfm"), "--out", own_png, "--quiet"],
                       check=True, stdout=subprocess.DEVNULL)
        base = a.baseline or os.path.join(work, "own.pfm")
        rc, mb, s, err = run(a.cli, a.scene, base, os.path.join(work, "r"))
        if rc != 0:
            sys.exit(f"check-cost: the scene's own image does not pass (rc {rc}): {err.strip()}")
        print(f"check-cost: the scene with its own image: {mb:.1f} MB, {s:.3f} s")
        files = sorted(os.path.join(d, f) for d in a.dirs for f in os.listdir(d))
        files = [(f, a.plain) for f in files if os.path.isfile(f) and os.path.getsize(f) <= a.max_bytes + (0 if a.plain else 1)
                 and not f.endswith(".md")]
        if a.crafted:
            w, h = png_size(own_png)
            os.mkdir(os.path.join(work, "crafted"))
            files += [(f, True) for f in crafted(w, h, os.path.join(work, "crafted"), a.max_bytes)]
        worst_mb, worst_s, bad, codes = (0.0, ""), (0.0, ""), [], {}
        tty = sys.stderr.isatty()
        for k, (f, plain) in enumerate(files):
            if plain:
                img = f
            else:
                data = open(f, "rb").read()
                if not data:
                    continue
                img = os.path.join(work, "in." + ("pfm" if data[0] & 1 else "png"))
                with open(img, "wb") as o:
                    o.write(data[1:])
            out = os.path.join(work, "r")
            shutil.rmtree(out, ignore_errors=True)
            rc, mb, s, err = run(a.cli, a.scene, img, out)
            codes[rc] = codes.get(rc, 0) + 1
            if mb > worst_mb[0]:
                worst_mb = (mb, f)
            if s > worst_s[0]:
                worst_s = (s, f)
            if rc not in (0, 1, 2) or mb > a.max_mb or s > a.max_s:
                bad.append(f"{f}: rc {rc}, {mb:.1f} MB, {s:.3f} s: {err.strip()[:200]}")
            if tty and (k % 50 == 0 or k + 1 == len(files)):
                sys.stderr.write(f"\rcheck-cost: {k + 1} of {len(files)}")
        if tty:
            sys.stderr.write("\n")
        print(f"check-cost: {len(files)} inputs of at most {a.max_bytes} bytes; exit codes "
              + ", ".join(f"{c}: {n}" for c, n in sorted(codes.items())))
        print(f"check-cost: peak memory {worst_mb[0]:.1f} MB ({worst_mb[1]}), longest {worst_s[0]:.3f} s ({worst_s[1]})")
        for b in bad:
            print("check-cost: over the bound or crashed: " + b)
        print(f"check-cost: {'FAIL' if bad else 'PASS'} (bounds {a.max_mb:g} MB, {a.max_s:g} s)")
        return 1 if bad else 0
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
