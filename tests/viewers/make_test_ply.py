#!/usr/bin/python3
"""Write a small asymmetric 3DGS test scene (inria PLY layout) plus a camera for it.

  /usr/bin/python3 make_test_ply.py OUTDIR [--size WxH] [--sh-amp A] [--seed S]

Writes OUTDIR/test.ply, OUTDIR/camera.json and OUTDIR/markers.json (where some
solid markers must land in the image, computed here with an OpenGL look-at +
perspective projection, so an image that is mirrored or flipped fails check).

Scene (right-handed, y-up world; the camera looks at the origin from +z):
  - a light grey letter "F" in the z=0 plane (mirroring/flipping is obvious),
  - a red row of splats along +x, a green column along +y, blue splats stepping
    towards the camera along +z,
  - three elongated yellow splats rotated 30 degrees about z (quaternion check),
  - a translucent magenta splat behind a translucent cyan one (sort-order check),
  - ~200 random small splats behind everything.
"""
import json
import sys
import numpy as np

C0 = 0.28209479177387814  # SH band-0 constant: colour = 0.5 + C0 * f_dc


def look_at(eye, target, up):
    eye, target, up = (np.asarray(v, np.float64) for v in (eye, target, up))
    f = target - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def perspective(fovy_deg, aspect, near, far):
    t = 1.0 / np.tan(np.radians(fovy_deg) / 2)
    return np.array([[t / aspect, 0, 0, 0], [0, t, 0, 0],
                     [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
                     [0, 0, -1, 0]])


def project(cam, p):
    """World point -> (column, row) in pixels, row 0 at the top of the image."""
    v = perspective(cam["fovy_deg"], cam["width"] / cam["height"], cam["near"], cam["far"]) \
        @ look_at(cam["eye"], cam["target"], cam["up"]) @ np.append(p, 1.0)
    ndc = v[:3] / v[3]
    return (ndc[0] + 1) / 2 * cam["width"], (1 - ndc[1]) / 2 * cam["height"]


def main():
    args = sys.argv[1:]
    out = args[0]
    sh_amp = float(args[args.index("--sh-amp") + 1]) if "--sh-amp" in args else 0.0
    seed = int(args[args.index("--seed") + 1]) if "--seed" in args else 1
    width, height = (int(v) for v in (args[args.index("--size") + 1] if "--size" in args else "256x256").split("x"))
    rng = np.random.default_rng(seed)

    pos, rgb, sigma, alpha, quat = [], [], [], [], []

    def add(p, c, s, a=0.95, q=(1.0, 0.0, 0.0, 0.0)):
        pos.append(p); rgb.append(c); alpha.append(a); quat.append(q)
        sigma.append([s] * 3 if np.isscalar(s) else s)

    grey = (0.85, 0.85, 0.85)
    for y in np.linspace(-1.0, 1.0, 21):          # F: vertical bar
        add((-1.0, y, 0.0), grey, 0.04)
    for x in np.linspace(-0.9, 0.2, 12):          # F: top bar
        add((x, 1.0, 0.0), grey, 0.04)
    for x in np.linspace(-0.9, -0.2, 8):          # F: middle bar
        add((x, 0.2, 0.0), grey, 0.04)
    for x in np.linspace(0.6, 1.6, 11):           # +x: red
        add((x, -1.0, 0.0), (0.9, 0.1, 0.1), 0.05)
    for y in np.linspace(-0.5, 1.2, 18):          # +y: green
        add((1.2, y, 0.0), (0.1, 0.8, 0.1), 0.05)
    for z in np.linspace(0.0, 1.4, 8):            # +z: blue, towards the camera
        add((0.4, -0.5, z), (0.15, 0.25, 0.95), 0.05)
    h = np.radians(30) / 2                        # yellow ellipses, 30 deg about +z
    for dy in (0.0, 0.25, 0.5):
        add((0.55, 0.1 + dy, 0.3), (0.95, 0.85, 0.1), [0.18, 0.03, 0.03], 0.9,
            (np.cos(h), 0.0, 0.0, np.sin(h)))
    add((-0.35, -0.55, -0.4), (0.9, 0.1, 0.9), 0.25, 0.6)  # magenta, behind
    add((-0.15, -0.45, 0.4), (0.1, 0.9, 0.9), 0.2, 0.6)    # cyan, in front
    n_fixed = len(pos)
    for _ in range(200):                          # random background cloud
        add(rng.uniform((-2.5, -2.0, -3.0), (2.5, 2.0, -1.5)), rng.uniform(0.05, 0.95, 3),
            rng.uniform(0.02, 0.08), rng.uniform(0.3, 0.9))

    n = len(pos)
    q = np.asarray(quat, np.float64)
    fields = {
        "xyz": np.asarray(pos, np.float32),
        "normal": np.zeros((n, 3), np.float32),
        "f_dc": ((np.asarray(rgb) - 0.5) / C0).astype(np.float32),
        # f_rest is channel-major in the inria layout: 15 R coeffs, 15 G, 15 B.
        "f_rest": (sh_amp * rng.standard_normal((n, 45))).astype(np.float32),
        "opacity": np.log(np.asarray(alpha) / (1 - np.asarray(alpha)))[:, None].astype(np.float32),
        "scale": np.log(np.asarray(sigma)).astype(np.float32),
        "rot": (q / np.linalg.norm(q, axis=1, keepdims=True)).astype(np.float32),  # w x y z
    }
    names = ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"] \
        + [f"f_rest_{i}" for i in range(45)] + ["opacity", "scale_0", "scale_1", "scale_2"] \
        + [f"rot_{i}" for i in range(4)]
    data = np.concatenate(list(fields.values()), axis=1).astype("<f4")
    assert data.shape == (n, len(names)) == (n, 62)
    header = "ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % n \
        + "".join(f"property float {k}\n" for k in names) + "end_header\n"
    with open(f"{out}/test.ply", "wb") as f:
        f.write(header.encode("ascii"))
        f.write(data.tobytes())

    cam = {"width": width, "height": height, "eye": [0.8, 0.5, 5.0], "target": [0.1, 0.0, 0.0],
           "up": [0.0, 1.0, 0.0], "fovy_deg": 45.0, "near": 0.1, "far": 100.0,
           "background": [0.05, 0.1, 0.2]}
    with open(f"{out}/camera.json", "w") as f:
        json.dump(cam, f, indent=1)

    # Pixels that must show a given colour if the geometry/orientation is right.
    markers = [("F top-left corner (grey)", (-1.0, 1.0, 0.0), "grey"),
               ("F bottom of bar (grey)", (-1.0, -1.0, 0.0), "grey"),
               ("red row, +x end", (1.6, -1.0, 0.0), "red"),
               ("green column, +y end", (1.2, 1.2, 0.0), "green"),
               ("blue, nearest to camera", (0.4, -0.5, 1.4), "blue")]
    with open(f"{out}/markers.json", "w") as f:
        json.dump([{"name": m, "px": [round(c, 2) for c in project(cam, np.array(p))], "colour": c}
                   for m, p, c in markers], f)
    print(f"wrote {out}/test.ply ({n} splats, {n_fixed} structured), camera.json, markers.json")


if __name__ == "__main__":
    main()
