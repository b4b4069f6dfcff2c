#!/usr/bin/python3
"""Write the viewers test's scene of near-camera and needle Gaussians (inria 3DGS PLY layout, SH degree 0).

  /usr/bin/python3 make_near_needles.py OUT.ply

Seen from (0, 0, 3) towards the origin (near plane 0.05): 120 needles (one axis
100 times the others) about the origin, 60 round Gaussians between z = 2.2 and
2.9 (0.1 to 0.8 in front of the camera: where the near planes, the tangent
clamp and the viewers' pixel caps differ), and 120 small ones behind as a
backdrop.  A fixed seed: the same file every run.
"""
import sys
import numpy as np


def main():
    out = sys.argv[1]
    rng = np.random.default_rng(20261203)
    pos, logs, rot, dc, op = [], [], [], [], []

    def add(p, s, q, c, o):
        pos.append(p), logs.append(np.log(s)), rot.append(q / np.linalg.norm(q)), dc.append((np.asarray(c) - 0.5) / 0.28209479177387814)
        op.append(np.log(o / (1.0 - o)))

    for _ in range(120):  # needles
        s = np.full(3, 0.004)
        s[rng.integers(3)] = 0.4
        add(rng.uniform(-1.2, 1.2, 3) * [1, 0.8, 0.5], s, rng.normal(size=4), rng.uniform(0.1, 0.95, 3), rng.uniform(0.3, 0.95))
    for _ in range(60):  # close to the camera
        z = rng.uniform(2.2, 2.9)
        xy = rng.uniform(-0.5, 0.5, 2) * (3.0 - z) * 1.2
        add(np.array([xy[0], xy[1], z]), np.full(3, rng.uniform(0.004, 0.04)) * [1, rng.uniform(0.3, 1), 1], rng.normal(size=4),
            rng.uniform(0.1, 0.95, 3), rng.uniform(0.05, 0.6))
    for _ in range(120):  # backdrop
        add(np.array([rng.uniform(-2, 2), rng.uniform(-1.5, 1.5), rng.uniform(-3, -1)]), np.full(3, rng.uniform(0.05, 0.2)), rng.normal(size=4),
            rng.uniform(0.1, 0.95, 3), rng.uniform(0.3, 0.99))
    n = len(pos)
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"] + [f"f_rest_{i}" for i in range(45)] + \
            ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    data = np.zeros((n, len(names)), np.float32)
    data[:, 0:3] = pos
    data[:, 6:9] = dc
    data[:, 54] = op
    data[:, 55:58] = logs
    data[:, 58:62] = rot
    with open(out, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % n).encode())
        for name in names:
            f.write(("property float %s\n" % name).encode())
        f.write(b"end_header\n")
        f.write(data.astype("<f4").tobytes())


if __name__ == "__main__":
    main()
