#!/usr/bin/python3
"""gauss_oracle.py — a second implementation of SPEC §10.3–10.4 (gauss3d) and
§10.7 (gauss-blend), written from ../shared/SPEC.md alone, in Python with
numpy: the geometry in float64, vectorised over pixels, the front-to-back
loop done with cumulative products instead of a loop; α, its cap, skip and
stop thresholds and T in float32, as SPEC 10.4 states them (the constants
0.99, 1/255 and 1e-4 are floats there, and the cap and the stop threshold
are made so that (1 − cap)² meets the threshold: float32 stops, float64
would not).  It shares no code and
no arithmetic order with splatref's C and GLSL, so agreement within 2/255
says the reference computes §10, not only itself.

    import gauss_oracle as go
    scene = go.read_3dgs_ply(path, sh_degree)
    img = go.render(scene, camera, W, H, background, algo)   # H x W x 3, row 0 the top
"""
import math

import numpy as np

SH_C0 = 0.28209479177387814
SH_C1 = 0.4886025119029199
SH_C2 = (1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792, 0.5462742152960396)
SH_C3 = (-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154, -0.4570457994644658,
         1.445305721320277, -0.5900435899266435)

F32 = np.float32
TYPES = {"float": "<f4", "float32": "<f4", "double": "<f8", "uchar": "u1", "uint8": "u1", "int": "<i4", "uint": "<u4"}


def ply_vertices(path):
    """The vertices of a binary little-endian PLY as a numpy structured array (its properties by name), and their
    names in file order."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    props, n = [], 0
    for line in data[:end].decode("ascii").splitlines():
        w = line.split()
        if w[:2] == ["element", "vertex"]:
            n = int(w[2])
        elif w and w[0] == "property":
            props.append((w[2], TYPES[w[1]]))
    return np.frombuffer(data, dtype=np.dtype(props), count=n, offset=end), props


def read_3dgs_ply(path, sh_degree=3):
    """The Gaussians of a binary little-endian 3DGS PLY (training code's layout)."""
    v, props = ply_vertices(path)
    n = len(v)
    g = {"n": n, "mu": np.stack([v["x"], v["y"], v["z"]], 1).astype(np.float64)}
    q = np.stack([v["rot_%d" % k] for k in range(4)], 1).astype(np.float64)
    g["q"] = q / np.linalg.norm(q, axis=1, keepdims=True)
    g["s"] = np.exp(np.stack([v["scale_%d" % k] for k in range(3)], 1).astype(np.float64))
    g["o"] = 1.0 / (1.0 + np.exp(-v["opacity"].astype(np.float64)))
    rest = sorted((p for p, _ in props if p.startswith("f_rest_")), key=lambda p: int(p[7:]))
    per = len(rest) // 3
    sh = np.zeros((n, 16, 3))
    for ch in range(3):
        sh[:, 0, ch] = v["f_dc_%d" % ch]
        for k in range(per):
            if k + 1 < 16:
                sh[:, k + 1, ch] = v[rest[ch * per + k]]
    keep = (sh_degree + 1) ** 2
    sh[:, keep:, :] = 0.0
    g["sh"] = sh
    return g


def sh_colour(g, eye):
    d = g["mu"] - eye
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    x, y, z = d[:, 0:1], d[:, 1:2], d[:, 2:3]
    sh = g["sh"]
    c = SH_C0 * sh[:, 0]
    c = c - SH_C1 * y * sh[:, 1] + SH_C1 * z * sh[:, 2] - SH_C1 * x * sh[:, 3]
    xx, yy, zz, xy, yz, xz = x * x, y * y, z * z, x * y, y * z, x * z
    c = c + SH_C2[0] * xy * sh[:, 4] + SH_C2[1] * yz * sh[:, 5] + SH_C2[2] * (2 * zz - xx - yy) * sh[:, 6] \
        + SH_C2[3] * xz * sh[:, 7] + SH_C2[4] * (xx - yy) * sh[:, 8]
    c = c + SH_C3[0] * y * (3 * xx - yy) * sh[:, 9] + SH_C3[1] * xy * z * sh[:, 10] + SH_C3[2] * y * (4 * zz - xx - yy) * sh[:, 11] \
        + SH_C3[3] * z * (2 * zz - 3 * xx - 3 * yy) * sh[:, 12] + SH_C3[4] * x * (4 * zz - xx - yy) * sh[:, 13] \
        + SH_C3[5] * z * (xx - yy) * sh[:, 14] + SH_C3[6] * x * (xx - 3 * yy) * sh[:, 15]
    return np.maximum(c + 0.5, 0.0)  # not clamped above 1 (SPEC 10.3 step 9)


def preprocess(g, cam, W, H):
    """SPEC 10.3 steps 1-9 for every Gaussian: a dict of arrays, `kept` the survivors of the near test and det."""
    R, T = np.asarray(cam["R"], float).reshape(3, 3), np.asarray(cam["t"], float)
    fx, fy, cx, cy = cam["fx"], cam["fy"], cam["cx"] - 0.5, cam["cy"] - 0.5  # pixel-index coordinates
    t = g["mu"] @ R.T + T
    kept = t[:, 2] > 0.2
    w, x, y, z = g["q"].T
    Rq = np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], 1).reshape(-1, 3, 3)
    L = Rq * g["s"][:, None, :]
    Sigma = L @ L.transpose(0, 2, 1)
    tz = np.where(kept, t[:, 2], 1.0)
    lx, ly = 1.3 * (0.5 * W / fx), 1.3 * (0.5 * H / fy)
    u = np.clip(t[:, 0] / tz, -lx, lx) * tz
    v = np.clip(t[:, 1] / tz, -ly, ly) * tz
    J = np.zeros((g["n"], 2, 3))
    J[:, 0, 0], J[:, 0, 2] = fx / tz, -fx * u / (tz * tz)
    J[:, 1, 1], J[:, 1, 2] = fy / tz, -fy * v / (tz * tz)
    M = J @ R
    S2 = M @ Sigma @ M.transpose(0, 2, 1)
    a, b, c = S2[:, 0, 0] + 0.3, S2[:, 0, 1], S2[:, 1, 1] + 0.3
    det = a * c - b * b
    kept &= det != 0.0
    det = np.where(kept, det, 1.0)
    mid = 0.5 * (a + c)
    lam = mid + np.sqrt(np.maximum(0.1, mid * mid - det))
    r = np.ceil(3.0 * np.sqrt(lam))
    m = np.stack([fx * t[:, 0] / tz + cx, fy * t[:, 1] / tz + cy], 1)
    gx, gy = (W + 15) // 16, (H + 15) // 16
    rect = np.stack([np.clip(np.trunc((m[:, 0] - r) / 16), 0, gx), np.clip(np.trunc((m[:, 1] - r) / 16), 0, gy),
                     np.clip(np.trunc((m[:, 0] + r + 15) / 16), 0, gx), np.clip(np.trunc((m[:, 1] + r + 15) / 16), 0, gy)], 1)
    eye = -R.T @ T
    return {"kept": kept, "m": m, "conic": np.stack([c / det, -b / det, a / det], 1), "o": g["o"], "depth": t[:, 2], "r": r,
            "rect": rect.astype(int), "colour": sh_colour(g, eye), "dist": np.linalg.norm(g["mu"] - eye, axis=1), "gx": gx, "gy": gy}


def power_at(p, idx, px, py):
    """power of Gaussians idx at pixels (px, py) (arrays), SPEC 10.4: a matrix pixels x Gaussians."""
    dx = p["m"][idx, 0][None, :] - px[:, None]
    dy = p["m"][idx, 1][None, :] - py[:, None]
    A, B, C = (p["conic"][idx, k][None, :] for k in range(3))
    return -0.5 * (A * dx * dx + C * dy * dy) - B * dx * dy


def tiles(p, W, H):
    """Per 16x16 tile: its Gaussians sorted by depth (stable: ties in file order) and its pixels (rows js, columns is_
    as 2-D index arrays; px, py the same flattened, as floats)."""
    idx_all = np.nonzero(p["kept"] & (p["rect"][:, 2] > p["rect"][:, 0]) & (p["rect"][:, 3] > p["rect"][:, 1]))[0]
    for ty in range(p["gy"]):
        for tx in range(p["gx"]):
            rc = p["rect"][idx_all]
            inside = (rc[:, 0] <= tx) & (tx < rc[:, 2]) & (rc[:, 1] <= ty) & (ty < rc[:, 3])
            idx = idx_all[inside]
            idx = idx[np.argsort(p["depth"][idx], kind="stable")]
            js, is_ = np.meshgrid(np.arange(16 * ty, min(16 * ty + 16, H)), np.arange(16 * tx, min(16 * tx + 16, W)), indexing="ij")
            yield idx, js, is_, is_.ravel().astype(float), js.ravel().astype(float)


def render_gauss3d(p, W, H, bg):
    """SPEC 10.4, per tile (tiles()), every pixel's loop as cumulative products."""
    img = np.zeros((H, W, 3))
    trans = np.ones((H, W))
    for idx, js, is_, px, py in tiles(p, W, H):
        if len(idx) == 0:
            img[js, is_] = bg
            continue
        pw = power_at(p, idx, px, py)
        # alpha, its thresholds and T in float32, as SPEC 10.4 has them: the cap and the stop are made so that two
        # Gaussians at the cap reach the stop exactly — (1 - 0.99f)^2 < 1e-4f in float32, not in float64
        alpha = np.minimum(F32(0.99), (p["o"][idx][None, :] * np.exp(np.minimum(pw, 0.0))).astype(np.float32))
        valid = (pw <= 0.0) & (alpha >= F32(1.0) / F32(255.0))
        a = np.where(valid, alpha, F32(0.0))
        after = np.cumprod(F32(1.0) - a, axis=1, dtype=np.float32)
        before = np.concatenate([np.ones((len(px), 1), np.float32), after[:, :-1]], axis=1)
        stop = valid & (after < F32(0.0001))
        first = np.where(stop.any(axis=1), stop.argmax(axis=1), len(idx))  # the first Gaussian that would cross 1e-4
        allowed = np.arange(len(idx))[None, :] < first[:, None]
        wgt = np.where(allowed, a.astype(np.float64) * before, 0.0)
        T = np.prod(np.where(allowed, F32(1.0) - a, F32(1.0)), axis=1, dtype=np.float32).astype(np.float64)
        col = wgt @ p["colour"][idx] + T[:, None] * np.asarray(bg)[None, :]
        img[js.ravel(), is_.ravel()] = col
        trans[js.ravel(), is_.ravel()] = T
    return img, trans


def render_blend(p, W, H, bg):
    """SPEC 10.7: every kept Gaussian once over its box, farthest first (ties in file order), premultiplied over;
    evaluated front to back: C = sum alpha_i c_i prod_{nearer} (1 - alpha_j) + bg prod (1 - alpha)."""
    idx = np.nonzero(p["kept"])[0]
    order = idx[np.lexsort((idx, -p["dist"][idx]))]  # farthest first, then index
    js, is_ = np.meshgrid(np.arange(H), np.arange(W), indexing="ij")
    px, py = is_.ravel().astype(float), js.ravel().astype(float)
    img = np.zeros((H * W, 3))
    T = np.ones(H * W)
    for k in order[::-1]:  # nearest first
        r = p["r"][k]
        box = (np.abs(px - p["m"][k, 0]) <= r) & (np.abs(py - p["m"][k, 1]) <= r) \
            & (px >= np.ceil(p["m"][k, 0] - r)) & (px <= np.floor(p["m"][k, 0] + r)) \
            & (py >= np.ceil(p["m"][k, 1] - r)) & (py <= np.floor(p["m"][k, 1] + r))
        pw = power_at(p, np.array([k]), px, py)[:, 0]
        a = np.minimum(F32(0.99), (p["o"][k] * np.exp(np.minimum(pw, 0.0))).astype(np.float32)).astype(np.float64)
        ok = box & (pw >= -4.5) & (pw <= 0.0) & (a >= float(F32(1.0) / F32(255.0)))
        a = np.where(ok, a, 0.0)
        img += (a * T)[:, None] * p["colour"][k][None, :]
        T *= 1.0 - a
    img += T[:, None] * np.asarray(bg)[None, :]
    return img.reshape(H, W, 3), T.reshape(H, W)


def render(g, cam, W, H, bg=(0.0, 0.0, 0.0), algo="gauss3d"):
    p = preprocess(g, cam, W, H)
    return render_gauss3d(p, W, H, bg) if algo == "gauss3d" else render_blend(p, W, H, bg)


def camera_of_json(path, cam_id):
    """A camera of the training code's cameras.json (SPEC 10.8): rotation camera-to-world, position the centre."""
    import json
    with open(path) as f:
        entries = json.load(f)
    for e in entries:
        if e["id"] == cam_id:
            c2w = np.asarray(e["rotation"], float)
            R = c2w.T
            return {"R": R.ravel(), "t": -R @ np.asarray(e["position"], float), "fx": float(e["fx"]), "fy": float(e["fy"]),
                    "cx": e["width"] / 2.0, "cy": e["height"] / 2.0}, int(e["width"]), int(e["height"])
    raise SystemExit("gauss_oracle: %s: no camera with id %d" % (path, cam_id))


def write_image(path, img):
    """PFM (float, bottom row first) or 8-bit PNG (row 0 the top, round(255 v) of v clamped to [0, 1])."""
    import struct
    import zlib
    H, W, _ = img.shape
    if path.endswith(".pfm"):
        with open(path, "wb") as f:
            f.write(b"PF\n%d %d\n-1\n" % (W, H))
            f.write(np.ascontiguousarray(img[::-1], dtype="<f4").tobytes())
        return
    q = np.floor(np.clip(img, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)
    raw = b"".join(b"\x00" + q[j].tobytes() for j in range(H))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)) + chunk(b"IDAT", zlib.compress(raw, 9))
                + chunk(b"IEND", b""))


def main():
    """`gauss_oracle.py CAPTURE.ply --cameras F.json --camera ID --out F.png|F.pfm`: a second renderer to check
    (docs/tutorial.md, "Validate your 3DGS renderer")."""
    import argparse
    ap = argparse.ArgumentParser(description=main.__doc__)
    ap.add_argument("capture")
    ap.add_argument("--cameras", required=True)
    ap.add_argument("--camera", type=int, required=True)
    ap.add_argument("--sh-degree", type=int, default=3)
    ap.add_argument("--algo", choices=("gauss3d", "gauss-blend"), default="gauss3d")
    ap.add_argument("--background", default="0,0,0")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    cam, W, H = camera_of_json(a.cameras, a.camera)
    bg = tuple(float(v) for v in a.background.split(","))
    img, _ = render(read_3dgs_ply(a.capture, a.sh_degree), cam, W, H, bg, a.algo)
    write_image(a.out, img)
    print("gauss_oracle: %s, %s, camera %d (%dx%d) -> %s" % (a.capture, a.algo, a.camera, W, H, a.out))


if __name__ == "__main__":
    main()
