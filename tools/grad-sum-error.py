#!/usr/bin/python3
"""grad-sum-error.py: how much float32 loses in each way of computing a pixel's dC/dalpha_k (docs/gradients.md,
"Measured: the colour behind a Gaussian").  For every pixel of a scene, the Gaussians the forward blends (alpha,
its skip, cap and stop in float32, as SPEC 10.4 and tests/oracle/gauss_oracle.py compute them), then

  exact    float64 over the same float32 alphas:  c_k T_k - S_{k+1} / (1 - a_k),  S_{k+1} = sum_{j>k} c_j a_j T_j
  replay   float32, front to back, the forward's own T, S = C - (contributions so far)       (brush's shape)
  stored   float32, back to front, the forward's own T, the recurrence acc = a c + (1 - a) acc  (inria's acc, exact T)
  divided  float32, back to front, T recovered by division from T_final, the same recurrence   (inria, gsplat)

and prints, per method, the largest and the 99.9th-percentile absolute error against exact (one colour channel,
background 0).  Measurement only: no test depends on it.

    /usr/bin/python3 tools/grad-sum-error.py CAPTURE.ply --cameras F.json --camera ID [--size WxH]
    /usr/bin/python3 tools/grad-sum-error.py --opaque N     N random pixels of near-opaque lists (alpha in [0.5, 0.99])
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "oracle"))
import gauss_oracle as go  # noqa: E402

F32 = np.float32


def pixel_lists(p, W, H):
    """Per pixel (front to back) the blended Gaussians' float32 alphas and colours (channel 0)."""
    out = []
    for idx, _, _, px, py in go.tiles(p, W, H):
        if len(idx) == 0:
            continue
        pw = go.power_at(p, idx, px, py)
        alpha = np.minimum(F32(0.99), (p["o"][idx][None, :] * np.exp(np.minimum(pw, 0.0))).astype(np.float32))
        valid = (pw <= 0.0) & (alpha >= F32(1.0) / F32(255.0))
        col = p["colour"][idx][:, 0].astype(np.float32)
        for r in range(len(px)):
            T, a_list, c_list = F32(1.0), [], []
            for k in np.nonzero(valid[r])[0]:
                a = alpha[r, k]
                Tn = F32(T * (F32(1.0) - a))
                if Tn < F32(0.0001):
                    break
                a_list.append(a)
                c_list.append(col[k])
                T = Tn
            if a_list:
                out.append((np.array(a_list, np.float32), np.array(c_list, np.float32)))
    return out


def methods(a, c):
    n = len(a)
    # exact, float64 over the float32 alphas
    a64, c64 = a.astype(np.float64), c.astype(np.float64)
    T64 = np.concatenate([[1.0], np.cumprod(1.0 - a64)[:-1]])
    w64 = c64 * a64 * T64
    S64 = np.concatenate([np.cumsum(w64[::-1])[::-1][1:], [0.0]])
    exact = c64 * T64 - S64 / (1.0 - a64)
    # the forward in float32: T and C as the reference accumulates them
    T32 = np.empty(n, np.float32)
    T, C = F32(1.0), F32(0.0)
    for k in range(n):
        T32[k] = T
        C = F32(C + F32(F32(c[k] * a[k]) * T))
        T = F32(T * F32(F32(1.0) - a[k]))
    Tf = T
    # replay: front to back, S = C minus the contributions so far
    rep = np.empty(n)
    S = C
    for k in range(n):
        w = F32(a[k] * T32[k])
        S = F32(S - F32(c[k] * w))
        r = F32(F32(1.0) / F32(F32(1.0) - a[k]))
        rep[k] = F32(F32(c[k] * T32[k]) - F32(S * r))
    # stored / divided: back to front, acc = colour behind k divided by T_{k+1}
    sto, div = np.empty(n), np.empty(n)
    acc, Td = F32(0.0), Tf
    last_a, last_c = F32(0.0), F32(0.0)
    for k in range(n - 1, -1, -1):
        Td = F32(Td / F32(F32(1.0) - a[k]))
        acc = F32(F32(last_a * last_c) + F32(F32(F32(1.0) - last_a) * acc))
        sto[k] = F32(T32[k] * F32(c[k] - acc))
        div[k] = F32(Td * F32(c[k] - acc))
        last_a, last_c = a[k], c[k]
    return exact, {"replay": rep, "stored": sto, "divided": div}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("capture", nargs="?")
    ap.add_argument("--cameras")
    ap.add_argument("--camera", type=int)
    ap.add_argument("--size", default="")
    ap.add_argument("--opaque", type=int, default=0)
    a = ap.parse_args()
    if a.opaque:
        rng = np.random.default_rng(43)
        lists = []
        for _ in range(a.opaque):  # the forward's stop ends them: at most a handful of such Gaussians
            al, T = [], F32(1.0)
            while True:
                x = F32(rng.uniform(0.5, 0.99))
                if F32(T * F32(F32(1.0) - x)) < F32(0.0001):
                    break
                al.append(x)
                T = F32(T * F32(F32(1.0) - x))
            lists.append((np.array(al, np.float32), rng.uniform(0, 1, len(al)).astype(np.float32)))
        report("near-opaque lists", lists)
        return
    g = go.read_3dgs_ply(a.capture, 3)
    cam, W, H = go.camera_of_json(a.cameras, a.camera)
    if a.size:
        w2, h2 = (int(v) for v in a.size.split("x"))
        for k, s in (("fx", w2 / W), ("cx", w2 / W), ("fy", h2 / H), ("cy", h2 / H)):
            cam[k] *= s
        W, H = w2, h2
    p = go.preprocess(g, cam, W, H)
    lists = pixel_lists(p, W, H)
    report("%s camera %d at %dx%d" % (os.path.basename(a.capture), a.camera, W, H), lists)


def report(what, lists):
    errs = {"replay": [], "stored": [], "divided": []}
    for al, cl in lists:
        exact, got = methods(al, cl)
        for m, v in got.items():
            errs[m].append(np.abs(v - exact))
    n = sum(len(al) for al, _ in lists)
    print("%s: %d pixels, %d (pixel, Gaussian) terms, longest list %d" % (what, len(lists), n, max(len(al) for al, _ in lists)))
    for m, e in errs.items():
        e = np.concatenate(e)
        print("  %-8s max |error| %.3g, 99.9%% %.3g, mean %.3g" % (m, e.max(), np.quantile(e, 0.999), e.mean()))


if __name__ == "__main__":
    main()
