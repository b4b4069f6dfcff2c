#!/usr/bin/env python3
"""make_captures.py — writes the small capture files of tests/data/captures/
that no current writer makes (issue 15; since issue 23 the formats a real
converter writes — 3DGS PLY, compressed PLY, .spz 3 and 4, .glb — come from
splat-transform itself, tests/data/captures/splat-transform/): the hand
sheet as 3DGS PLY (the reference the others are compared with, and one with
an unnormalised quaternion), 2DGS PLY, .splat and .spz version 2, each built
to its published layout (../shared/FORMATS.md, docs/formats.md), plus the
exporters' text files.  The files are committed; this script documents how
they were made and remakes them: python3 tests/data/make_captures.py.

One scene, "the sheet": 24 x 24 Gaussians on a plane through (0.25, -0.5,
0.75), 0.05 apart, all with the rotation q0 (60 degrees about (1, 2, 0.5)),
log-scales (-3.5, -4.0, -6.25) along the local axes (so the sheet spans
local x and y and its normal is local z), colour (204, 102, 51)/255 and
opacity 0.75 (logit ln 3).  The scales are multiples of 1/16 (exact in
.spz) and the colours exact in bytes, so the formats differ only where
their layouts quantise: positions (.spz 12 fractional bits), rotations
(.splat 8 bits, .spz 9 bits), colour and opacity (8 bits).  The .spz holds
the format's own RUB frame (Niantic's README): y and z reversed.
"""
import gzip
import json
import math
import os
import struct

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "captures")
C0 = 0.28209479177387814
N, SPACING = 24, 0.05
CENTRE = (0.25, -0.5, 0.75)
LOG_SCALE = (-3.5, -4.0, -6.25)
COLOUR = (204 / 255, 102 / 255, 51 / 255)
OPACITY = math.log(3.0)  # sigmoid -> 0.75


def quat_axis_angle(axis, deg):
    l = math.sqrt(sum(a * a for a in axis))
    s = math.sin(math.radians(deg) / 2)
    return (math.cos(math.radians(deg) / 2), axis[0] / l * s, axis[1] / l * s, axis[2] / l * s)


Q0 = quat_axis_angle((1.0, 2.0, 0.5), 60.0)  # w x y z


def rot_cols(q):
    w, x, y, z = q
    return ((1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)),
            (2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)),
            (2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)))


def sheet():
    u, v, _ = rot_cols(Q0)
    pts = []
    for j in range(N):
        for i in range(N):
            a, b = (i - (N - 1) / 2) * SPACING, (j - (N - 1) / 2) * SPACING
            pts.append(tuple(struct.unpack("<f", struct.pack("<f", CENTRE[k] + a * u[k] + b * v[k]))[0] for k in range(3)))
    return pts


def ply_header(n, props, extra=""):
    return ("ply\nformat binary_little_endian 1.0\ncomment made by tests/data/make_captures.py\nelement vertex %d\n" % n +
            "".join("property %s %s\n" % (t, p) for t, p in props) + extra + "end_header\n").encode()


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def gs_ply(name, q_scale=1.0, two_d=False):
    pts = sheet()
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"] + ["f_rest_%d" % k for k in range(45)] + \
            ["opacity", "scale_0", "scale_1"] + ([] if two_d else ["scale_2"]) + ["rot_0", "rot_1", "rot_2", "rot_3"]
    body = b""
    fdc = [(c - 0.5) / C0 for c in COLOUR]
    for p in pts:
        vals = list(p) + [0, 0, 0] + fdc + [0.0] * 45 + [OPACITY] + list(LOG_SCALE[:2 if two_d else 3]) + [q * q_scale for q in Q0]
        body += struct.pack("<%df" % len(vals), *vals)
    write(name, ply_header(len(pts), [("float", n) for n in names]) + body)


def splat_file():
    out = b""
    for p in sheet():
        sc = [math.exp(s) for s in LOG_SCALE]
        rgba = [round(c * 255) for c in COLOUR] + [round(0.75 * 255)]
        rot = [max(0, min(255, round(q * 128 + 128))) for q in Q0]
        out += struct.pack("<3f3f4B4B", *p, *sc, *rgba, *rot)
    write("sheet.splat", out)


def spz_file(version):
    pts = sheet()
    n = len(pts)
    frac = 12
    hdr = struct.pack("<IIIBBBB", 0x5053474E, version, n, 0, frac, 0, 0)
    pos = b""
    for p in pts:
        for c in (p[0], -p[1], -p[2]):  # the format's RUB frame: y and z of the PLY (RDF) frame reversed
            f = int(round(c * (1 << frac))) & 0xFFFFFF
            pos += bytes((f & 255, f >> 8 & 255, f >> 16 & 255))
    alpha = bytes([round(0.75 * 255)] * n)
    col = bytes([max(0, min(255, round(((c - 0.5) / C0) * 0.15 * 255 + 127.5))) for c in COLOUR] * n)
    scale = bytes([round((s + 10) * 16) for s in LOG_SCALE] * n)
    w, x, y, z = Q0
    y, z = -y, -z  # the same rotation seen in RUB: conjugated by diag(1, -1, -1)
    if version >= 3:  # smallest three, (x y z w) order
        q = [x, y, z, w]
        big = max(range(4), key=lambda k: abs(q[k]))
        neg = q[big] < 0
        comp = big
        for k in range(4):
            if k != big:
                negbit = (q[k] < 0) ^ neg
                mag = int(511 * (abs(q[k]) / math.sqrt(0.5)) + 0.5)
                comp = (comp << 10) | (negbit << 9) | mag
        rot = struct.pack("<I", comp) * n
    else:  # first three (x y z), w >= 0
        s = -1 if w < 0 else 1
        rot = bytes([max(0, min(255, round(s * c * 127.5 + 127.5))) for c in (x, y, z)]) * n
    write("sheet-v%d.spz" % version, gzip.compress(hdr + pos + alpha + col + scale + rot, mtime=0))


def text_files():
    # CloudCompare's ASCII export: a header naming every column (X Y Z R G B,
    # a scalar field, Nx Ny Nz), colours 0..255; the same without the header.
    rows = []
    for j in range(12):
        for i in range(12):
            x, y = i * 0.1, j * 0.1
            rows.append((x, y, 0.0, 200, 100, 50, 0.5, 0.0, 0.0, 1.0))
    body = "".join("%.6f %.6f %.6f %d %d %d %.6f %.6f %.6f %.6f\n" % r for r in rows)
    write("cloudcompare.asc", ("//X Y Z R G B Volume_density_(r=0.05) Nx Ny Nz\n" + body).encode())
    write("cloudcompare-noheader.txt", body.encode())
    write("cloudcompare-xyzn.asc", ("//X Y Z Nx Ny Nz\n" + "".join("%.6f %.6f %.6f %.6f %.6f %.6f\n" % (r[0], r[1], r[2], r[7], r[8], r[9])
                                                                    for r in rows)).encode())
    write("points.csv", ("x,y,z,nx,ny,nz\n" + "".join("%.6f,%.6f,%.6f,0,0,1\n" % r[:3] for r in rows)).encode())
    write("points-semicolon.txt", ("# x;y;z\n" + "".join("%.6f;%.6f;%.6f\n" % r[:3] for r in rows)).encode())


def capture_from(src, dst, seed=15):
    """A capture-like 3DGS PLY from one of our PLY files (x y z nx ny nz red
    green blue alpha radius, as `splatref sample` writes): every splat an
    anisotropic Gaussian in its tangent plane (axis ratio 0.35..1, turned at
    random about the normal), σ = r/3 along its major axis, opacity 0.55..1,
    colour from its height: the picture of docs/formats.md."""
    import random
    rnd = random.Random(seed)
    b = open(src, "rb").read()
    i = b.index(b"end_header\n") + 11
    n = int([l for l in b[:i].decode().split("\n") if l.startswith("element vertex")][0].split()[2])
    recs = [struct.unpack_from("<6f4Bf", b, i + 32 * k) for k in range(n)]
    ys = [r[1] for r in recs]
    lo, hi = min(ys), max(ys)
    out = []
    for r in recs:
        p, nv, rad = r[:3], r[3:6], r[10]
        t = (nv[1], -nv[0], 0.0) if abs(nv[2]) < 0.9 else (0.0, nv[2], -nv[1])
        l = math.sqrt(sum(x * x for x in t))
        t = [x / l for x in t]
        w = [nv[1] * t[2] - nv[2] * t[1], nv[2] * t[0] - nv[0] * t[2], nv[0] * t[1] - nv[1] * t[0]]
        a = rnd.uniform(0, math.pi)
        u = [math.cos(a) * t[k] + math.sin(a) * w[k] for k in range(3)]
        v = [nv[1] * u[2] - nv[2] * u[1], nv[2] * u[0] - nv[0] * u[2], nv[0] * u[1] - nv[1] * u[0]]
        # quaternion of the rotation with columns u, v, n
        m = [[u[0], v[0], nv[0]], [u[1], v[1], nv[1]], [u[2], v[2], nv[2]]]
        tr = m[0][0] + m[1][1] + m[2][2]
        if tr > 0:
            S = math.sqrt(tr + 1) * 2
            q = (S / 4, (m[2][1] - m[1][2]) / S, (m[0][2] - m[2][0]) / S, (m[1][0] - m[0][1]) / S)
        elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
            S = math.sqrt(1 + m[0][0] - m[1][1] - m[2][2]) * 2
            q = ((m[2][1] - m[1][2]) / S, S / 4, (m[0][1] + m[1][0]) / S, (m[0][2] + m[2][0]) / S)
        elif m[1][1] > m[2][2]:
            S = math.sqrt(1 + m[1][1] - m[0][0] - m[2][2]) * 2
            q = ((m[0][2] - m[2][0]) / S, (m[0][1] + m[1][0]) / S, S / 4, (m[1][2] + m[2][1]) / S)
        else:
            S = math.sqrt(1 + m[2][2] - m[0][0] - m[1][1]) * 2
            q = ((m[1][0] - m[0][1]) / S, (m[0][2] + m[2][0]) / S, (m[1][2] + m[2][1]) / S, S / 4)
        h = (p[1] - lo) / (hi - lo)
        col = (0.25 + 0.7 * h, 0.35 + 0.3 * (1 - abs(2 * h - 1)), 0.9 - 0.7 * h)
        alpha = rnd.uniform(0.55, 1.0)
        sig = rad / 3 * 1.3
        vals = list(p) + [0, 0, 0] + [(c - 0.5) / C0 for c in col] + [0.0] * 45 + \
            [math.log(alpha / (1 - alpha)) if alpha < 1 else 8.0, math.log(sig), math.log(sig * rnd.uniform(0.35, 1.0)),
             math.log(sig / 50)] + list(q)
        out.append(struct.pack("<62f", *vals))
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"] + ["f_rest_%d" % k for k in range(45)] + \
            ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    with open(dst, "wb") as f:
        f.write(ply_header(n, [("float", x) for x in names]) + b"".join(out))


def blender247():
    # Blender 2.47's PLY export: its "Created by" line lacks `comment`; a small
    # tetrahedron with vertex normals and faces, ascii as Blender wrote it.
    v = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    n = [(-0.577, -0.577, -0.577), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    f = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    txt = ("ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: 'tetra.blend'\n"
           "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
           "property float nx\nproperty float ny\nproperty float nz\nelement face 4\n"
           "property list uchar uint vertex_indices\nend_header\n")
    txt += "".join("%g %g %g %g %g %g\n" % (a + b) for a, b in zip(v, n))
    txt += "".join("3 %d %d %d\n" % t for t in f)
    write("blender247.ply", txt.encode())


if __name__ == "__main__":
    import sys
    if len(sys.argv) == 4 and sys.argv[1] == "--capture-from":
        capture_from(sys.argv[2], sys.argv[3])
        sys.exit(0)
    os.makedirs(HERE, exist_ok=True)
    gs_ply("sheet.ply")
    gs_ply("sheet-unnormalised.ply", q_scale=1.7)
    gs_ply("sheet-2dgs.ply", two_d=True)
    splat_file()
    spz_file(2)
    text_files()
    blender247()
