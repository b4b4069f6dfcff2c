#!/usr/bin/python3
"""run_oracle.py — CTest's oracle test (issue 23): scenes made here (their
3DGS PLY written with numpy) and the real converter's captures, rendered by
splatref (gauss3d and gauss-blend, PFM) and by gauss_oracle.py; every scene
must agree within 2/255 on at least 99.5% of its pixels.

    /usr/bin/python3 tests/oracle/run_oracle.py --cli build/splatref --work build/oracle

The generated scenes each test something a wrong rasterizer gets wrong:
  mixed     anisotropic Gaussians of every size, some below a pixel (the
            dilation), SH degree 3, a tilted camera;
  layers    two coincident opaque white Gaussians before a red one: near
            their centre T falls to 0.01 at the first and the second stops
            the loop — a rasterizer that stops one Gaussian late adds 0.0099
            of white there;
  ties      pairs at exactly the same depth, red and blue: the tie order
            (file order) decides the colour.
"""
import argparse
import math
import os
import subprocess
import sys

try:
    import numpy as np
except ImportError:
    sys.exit("run_oracle: numpy is missing (Debian's python3-numpy: tools/install-deps.sh installs it)")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gauss_oracle as go  # noqa: E402

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def write_ply(path, mu, log_s, rot, logit, sh):
    n, k = len(mu), sh.shape[1]
    names = ["x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2"] + ["f_rest_%d" % i for i in range(3 * (k - 1))] + \
        ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    rest = np.concatenate([sh[:, 1:, ch] for ch in range(3)], axis=1)  # channel-major, as the training code
    cols = np.concatenate([mu, sh[:, 0, :], rest, logit[:, None], log_s, rot], axis=1).astype("<f4")
    head = "ply\nformat binary_little_endian 1.0\ncomment made by tests/oracle/run_oracle.py\nelement vertex %d\n" % n
    head += "".join("property float %s\n" % p for p in names) + "end_header\n"
    with open(path, "wb") as f:
        f.write(head.encode("ascii"))
        f.write(cols.tobytes())


def random_rotations(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def scene_mixed(rng, n=1500):
    mu = rng.uniform(-1, 1, size=(n, 3))
    log_s = np.log(rng.uniform(0.003, 0.15, size=(n, 3)))
    sh = np.zeros((n, 16, 3))
    sh[:, 0] = rng.uniform(-1.5, 1.5, size=(n, 3))
    sh[:, 1:] = rng.uniform(-0.3, 0.3, size=(n, 15, 3))
    return mu, log_s, random_rotations(rng, n), rng.uniform(-3, 4, size=n), sh


def scene_layers(rng):
    # two coincident opaque white Gaussians, a red one behind: within 0.14 sigma of the centre the first has
    # alpha = 0.99 (the cap), T = 0.01, and the second stops the loop (T*(1 - 0.99) < 1e-4) — about 3% of the image
    mu = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.5]])
    log_s = np.log(np.full((3, 3), 1.5))
    sh = np.zeros((3, 1, 3))
    sh[:2, 0] = (1.0 - 0.5) / go.SH_C0
    sh[2, 0] = np.array([0.5, -0.5, -0.5]) / go.SH_C0
    return mu, log_s, np.tile([1.0, 0.0, 0.0, 0.0], (3, 1)), np.full(3, 12.0), sh


def scene_ties(rng, n=400):
    base = np.stack([rng.uniform(-0.8, 0.8, n), rng.uniform(-0.8, 0.8, n), np.zeros(n)], 1)
    mu = np.repeat(base, 2, axis=0)  # pairs at one position: one depth
    log_s = np.log(np.repeat(rng.uniform(0.05, 0.15, size=(n, 3)), 2, axis=0))
    sh = np.zeros((2 * n, 1, 3))
    sh[0::2, 0] = np.array([0.5, -0.5, -0.5]) / go.SH_C0
    sh[1::2, 0] = np.array([-0.5, -0.5, 0.5]) / go.SH_C0
    return mu, log_s, np.repeat(random_rotations(rng, n), 2, axis=0), np.full(2 * n, 0.4), sh


def look_from(eye, target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0)):
    z = np.asarray(target, float) - np.asarray(eye, float)
    z /= np.linalg.norm(z)
    y = -np.asarray(up, float)
    y -= y.dot(z) * z
    y /= np.linalg.norm(y)
    x = np.cross(y, z)
    R = np.stack([x, y, z])
    return R, -R @ np.asarray(eye, float)


def pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts = data.split(b"\n", 3)
    w, h = map(int, parts[1].split())
    img = np.frombuffer(parts[3], dtype="<f4" if float(parts[2]) < 0 else ">f4").reshape(h, w, 3)
    return img[::-1].astype(np.float64)  # PFM holds the bottom row first; the oracle's row 0 is the top


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cli", required=True)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    rng = np.random.default_rng(20261201)
    W, H = 160, 120
    scenes = []
    for name, make, eye in (("mixed", scene_mixed, (1.1, 0.7, -3.3)), ("layers", scene_layers, (0.0, 0.0, -2.2)),
                            ("ties", scene_ties, (0.0, 0.0, -2.5))):
        path = os.path.join(args.work, name + ".ply")
        write_ply(path, *make(rng))
        scenes.append((name, path, eye, (0.05, 0.1, 0.15)))
    for f in ("2.7.1/sphere.ply", "3.7.0/sheet.ply"):
        scenes.append((f, os.path.join(SRC, "tests/data/captures/splat-transform", f), (0.6, -0.5, 3.2), (0.0, 0.0, 0.0)))
    failed = 0
    for name, path, eye, bg in scenes:
        R, t = look_from(eye)
        fx = 0.5 * H / math.tan(math.radians(45.0) / 2)
        cam = {"R": R.ravel(), "t": t, "fx": fx, "fy": fx, "cx": W / 2, "cy": H / 2}
        g = go.read_3dgs_ply(path, 3)
        for algo in ("gauss3d", "gauss-blend"):
            out = os.path.join(args.work, "%s-%s.pfm" % (name.replace("/", "_"), algo))
            m12 = ",".join("%.17g" % v for v in np.concatenate([R, t[:, None]], 1).ravel())
            cmd = [args.cli, "render", "--model", path, "--algo", algo, "--sh-degree", "3", "--size", "%dx%d" % (W, H),
                   "--intrinsics", "%.17g,%.17g,%.17g,%.17g" % (fx, fx, W / 2, H / 2), "--world-to-camera", m12,
                   "--background", "%g,%g,%g" % bg, "--float", out, "--out", out[:-4] + ".png", "--quiet"]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode:
                print("oracle: %s %s: splatref failed: %s" % (name, algo, r.stderr.strip()))
                failed += 1
                continue
            ours = pfm(out)
            theirs, _ = go.render(g, cam, W, H, bg, algo)
            d = np.abs(ours - theirs).max(axis=2)
            within = float((d <= 2.0 / 255.0).mean())
            ok = within >= 0.995
            print("oracle: %-18s %-11s %6.2f%% of pixels within 2/255 (worst %.4f, mean %.2e)%s" % (name, algo, 100 * within, d.max(), d.mean(),
                                                                                                   "" if ok else "  FAIL"))
            failed += not ok
    print("oracle: %s" % ("every scene agrees" if not failed else "%d renders disagree" % failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
