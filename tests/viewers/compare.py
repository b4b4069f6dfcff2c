#!/usr/bin/python3
"""Compare viewer PNGs: pairwise differences, background and marker checks.

  /usr/bin/python3 compare.py CAMERA.json MARKERS.json A.png B.png [C.png ...]

Exits non-zero if an image has the wrong size, its corner pixel is not the camera's
background colour, or a marker from make_test_ply.py does not show its colour
(which catches mirrored, flipped or misplaced renders).
"""
import json
import sys
import zlib
import numpy as np


def read_png(path):
    """Minimal PNG reader: 8-bit greyscale/RGB/RGBA, not interlaced. Returns HxWx4 uint8."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat = 8, b""
    while pos < len(data):
        n = int.from_bytes(data[pos:pos + 4], "big")
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = np.frombuffer(body[:8], ">u4").tolist() + list(body[8:13])
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    assert depth == 8 and interlace == 0 and ctype in (0, 2, 6), (path, depth, ctype, interlace)
    bpp = {0: 1, 2: 3, 6: 4}[ctype]
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + w * bpp)
    out, prev = np.zeros((h, w * bpp), np.uint8), np.zeros(w * bpp, np.int32)
    for y in range(h):
        f, line = raw[y, 0], raw[y, 1:].astype(np.int32)
        if f == 2:
            line = (line + prev) & 255
        elif f in (1, 3, 4):   # sub / average / paeth depend on the pixel to the left
            for x in range(w * bpp):
                a = line[x - bpp] if x >= bpp else 0
                b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
                if f == 1:
                    p = a
                elif f == 3:
                    p = (a + b) // 2
                else:
                    pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                    p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + p) & 255
        out[y], prev = line, line
    img = out.reshape(h, w, bpp)
    if bpp == 1:
        img = np.repeat(img, 3, axis=2)
    if img.shape[2] == 3:
        img = np.concatenate([img, np.full((h, w, 1), 255, np.uint8)], axis=2)
    return img


def colour_ok(px, name):
    r, g, b = (int(v) for v in px[:3])
    return {"grey": min(r, g, b) > 120 and max(r, g, b) - min(r, g, b) < 60,
            "red": r > 120 and r > 2 * g and r > 2 * b,
            "green": g > 120 and g > 2 * r and g > 2 * b,
            "blue": b > 120 and b > 1.5 * r and b > 1.5 * g}[name]


def main():
    cam, markers = (json.load(open(p)) for p in sys.argv[1:3])
    paths = sys.argv[3:]
    imgs = [read_png(p) for p in paths]
    bg = np.round(np.asarray(cam["background"]) * 255).astype(int)
    ok = True
    for p, im in zip(paths, imgs):
        problems = []
        if im.shape[:2] != (cam["height"], cam["width"]):
            problems.append(f"size {im.shape[1]}x{im.shape[0]}")
        if np.abs(im[0, 0, :3].astype(int) - bg).max() > 1:
            problems.append(f"corner {im[0, 0, :3].tolist()} != background {bg.tolist()}")
        for m in markers:
            x, y = (int(round(v)) for v in m["px"])
            if not colour_ok(im[y, x], m["colour"]):
                problems.append(f"{m['name']} at ({x},{y}) is {im[y, x, :3].tolist()}")
        alpha = sorted(set(im[..., 3].ravel().tolist()))
        print(f"{p}: {'OK' if not problems else 'FAIL'}; alpha values {alpha[:4]}"
              + "".join(f"\n    {s}" for s in problems))
        ok &= not problems
    for i in range(len(imgs)):
        for j in range(i + 1, len(imgs)):
            if imgs[i].shape != imgs[j].shape:
                continue
            d = np.abs(imgs[i][..., :3].astype(int) - imgs[j][..., :3].astype(int))
            print(f"{paths[i]} vs {paths[j]}: mean |diff| {d.mean():.2f}, max {d.max()}, "
                  f"pixels differing >8: {(d.max(axis=2) > 8).mean() * 100:.1f}%, identical: {not d.any()}")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
