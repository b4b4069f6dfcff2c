#!/usr/bin/python3
"""grad_oracle.py — an independent float64 finite-difference oracle for the
gradients of the gauss3d training rasterizer (SPEC §10.3–10.4, §10.9 rows
`inria` and `gsplat`, §10.10; issue 43 item 4), and CTest's `grad_oracle`.

The loss is L(θ) = Σ over pixels and channels of G·C(θ), C the gauss3d image
(C = Σ c α T + T_f·bg) and G a fixed upstream-gradient image (float32
[H, W, 3], row 0 the top row), so ∂L/∂θ is the gradient with ∂L/∂C = G.  The
forward pass below is written from SPEC.md alone, entirely in float64: the
α floor 1/255, the cap 0.99 and the stop 1e-4 are float64 decisions, never
float32 thresholds.  The gradient of every parameter of every Gaussian is a
central difference, Richardson-extrapolated from the steps h and h/2:
means (3), quats (4, the quaternion as given, before normalisation), scales
(3, linear σ), opacities (1, the value in [0, 1]), sh0 (3), shN (3 per
coefficient).

The forward is piecewise smooth.  An entry is "smooth" only when
  - no decision differs between θ − h, θ − h/2, θ, θ + h/2 and θ + h: per
    pixel, each Gaussian of its tile skipped (power > 0, α < 1/255),
    blended, blended at the cap, the loop's stop; each tile's list and its
    order; per Gaussian, the culls, the tile rectangle, the tangent clamp
    and the colour's clamp at 0;
  - the differences at h and h/2 agree (Richardson: within 1e-6 relative
    plus the rounding bound; a decision crossed between samples shows there);
  - the Gaussian is not "fragile": a decision taken within 1e-5 (relative)
    of its threshold at θ, where the reference's float32 may decide the other
    way (α at 1/255 or at the stop: every Gaussian of that pixel's tile; the
    cap, the tangent clamp, the colour clamp: that Gaussian; the tile
    rectangle, the near cull, equal depths in a tile: every Gaussian of the
    tiles concerned).

    /usr/bin/python3 tests/oracle/grad_oracle.py --cli build/splatref --work build/grad-oracle
    /usr/bin/python3 tests/oracle/grad_oracle.py --self-check            (no splatref needed)
    import grad_oracle as gro; fd = gro.fd_gradients(params, cam, "gsplat", G)

`--break` flips the sign of the reference's sh0 before comparing (to see the
test fail).  Exit status: 0 all agree, 1 a disagreement, 77 (CTest's skip)
when the CLI has no `grad` command yet.
"""
import argparse
import math
import os
import subprocess
import sys
import time

try:
    import numpy as np
except ImportError:
    sys.exit("grad_oracle: numpy is missing (Debian's python3-numpy: tools/install-deps.sh installs it)")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gauss_oracle as go  # noqa: E402  (the SH constants; an independent implementation itself)
from run_oracle import write_ply, look_from  # noqa: E402  (the PLY the way the forward oracle writes it)

EPS32 = 2.0 ** -24  # unit roundoff of float32
EPS64 = 2.0 ** -53
MARGIN = 1e-5  # "fragile": a decision within this relative distance of its threshold (float32 decides within ~1e-6)

# SPEC §10.9, the rows `inria` and `gsplat` (core/algo/gauss_profile.c; the tangent limits of core/algo/gauss.c
# spr__gauss_frame), every constant a float64 here
PROFILES = {
    "inria": dict(near=0.2, near_lt=False, det_le=False, tan="symmetric", ext="square", k=3.0, lam_floor=0.1,
                  cap=0.99, floor=1.0 / 255.0, t_min=1e-4, stop_le=False),
    "gsplat": dict(near=0.01, near_lt=True, det_le=True, tan="principal", ext="axes", k=3.33, lam_floor=0.0,
                   cap=0.99, floor=1.0 / 255.0, t_min=1e-4, stop_le=True),
}
NAMES = ("means", "quats", "scales", "opacities", "sh0", "shN")


# ---------------------------------------------------------------- forward, float64

def sh_basis(d):
    """The real SH basis up to degree 3 at unit directions d [n, 3] (SPEC §1's SH path, gauss_oracle's constants): [n, 16]."""
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    xx, yy, zz, xy, yz, xz = x * x, y * y, z * z, x * y, y * z, x * z
    C1, C2, C3 = go.SH_C1, go.SH_C2, go.SH_C3
    return np.stack([np.full_like(x, go.SH_C0), -C1 * y, C1 * z, -C1 * x,
                     C2[0] * xy, C2[1] * yz, C2[2] * (2 * zz - xx - yy), C2[3] * xz, C2[4] * (xx - yy),
                     C3[0] * y * (3 * xx - yy), C3[1] * xy * z, C3[2] * y * (4 * zz - xx - yy), C3[3] * z * (2 * zz - 3 * xx - 3 * yy),
                     C3[4] * x * (4 * zz - xx - yy), C3[5] * z * (xx - yy), C3[6] * x * (xx - 3 * yy)], 1)


def tan_limits(cam, pf):
    """Profile rule 2: the clamp of t.x/t.z to [−lxn, lx] (and y), spr__gauss_frame's formulas in float64."""
    tanx, tany = 0.5 * cam["W"] / cam["fx"], 0.5 * cam["H"] / cam["fy"]
    if pf["tan"] == "symmetric":  # the training code: ±1.3·tan(fov/2)
        return 1.3 * tanx, 1.3 * tanx, 1.3 * tany, 1.3 * tany
    # gsplat: from the principal point (continuous): (W − cx)/fx + 0.3·tan on the right, cx/fx + 0.3·tan on the left
    return ((cam["W"] - cam["cx"]) / cam["fx"] + 0.3 * tanx, cam["cx"] / cam["fx"] + 0.3 * tanx,
            (cam["H"] - cam["cy"]) / cam["fy"] + 0.3 * tany, cam["cy"] / cam["fy"] + 0.3 * tany)


def tile_rects(m, rx, ry, pf, gx, gy):
    """SPEC §10.3 step 8 under rule 4: [x0, y0, x1, y1) in tiles, int [n, 4]."""
    out = []
    for c, r, gn in ((m[:, 0], rx, gx), (m[:, 1], ry, gy)):
        if pf["ext"] == "square":  # [trunc((m − r)/16), trunc((m + r + 15)/16)) clamped to [0, gn]
            lo = np.floor(np.clip((c - r) / 16.0, 0.0, gn))
            hi = np.floor(np.clip((c + r + 15.0) / 16.0, 0.0, gn))
        else:  # gsplat: [floor((m' − r)/16), ceil((m' + r)/16)), m' = m + 0.5 the continuous centre, clamped
            lo = np.clip(np.floor((c + 0.5 - r) / 16.0), 0.0, gn)
            hi = np.clip(np.ceil((c + 0.5 + r) / 16.0), 0.0, gn)
        out.append((lo, hi))
    return np.stack([out[0][0], out[1][0], out[0][1], out[1][1]], 1).astype(int)


def preprocess(P, cam, pf, margins=False, lim_scale=None):
    """SPEC §10.3 steps 1–9 in float64 for the Gaussians of P (dict: mu [n,3], q [n,4] as given, s [n,3] linear,
    o [n], sh [n,K,3]): the per-Gaussian record, its decisions and (margins=True) how near each is to its threshold."""
    R, T = cam["R"], cam["t"]
    W, H, fx, fy = cam["W"], cam["H"], cam["fx"], cam["fy"]
    gx, gy = (W + 15) // 16, (H + 15) // 16
    n = len(P["o"])
    t = P["mu"] @ R.T + T
    tz = t[:, 2]
    kept = tz >= pf["near"] if pf["near_lt"] else tz > pf["near"]
    tzs = np.where(kept, tz, 1.0)
    q = P["q"] / np.linalg.norm(P["q"], axis=1, keepdims=True)  # the quaternion as given, normalised here
    w, x, y, z = q.T
    Rq = np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], 1).reshape(n, 3, 3)
    L = Rq * P["s"][:, None, :]
    Sigma = L @ L.transpose(0, 2, 1)
    lx, lxn, ly, lyn = tan_limits(cam, pf)
    if lim_scale is not None:  # finding 1's prediction only (inria_predicted): per-Gaussian limits
        lx, lxn, ly, lyn = (v * lim_scale for v in (lx, lxn, ly, lyn))
    rx_, ry_ = t[:, 0] / tzs, t[:, 1] / tzs
    ux, uy = np.clip(rx_, -lxn, lx), np.clip(ry_, -lyn, ly)
    clamp = np.stack([np.sign(rx_ - ux), np.sign(ry_ - uy)], 1).astype(int)
    J = np.zeros((n, 2, 3))
    J[:, 0, 0], J[:, 0, 2] = fx / tzs, -fx * (ux * tzs) / (tzs * tzs)
    J[:, 1, 1], J[:, 1, 2] = fy / tzs, -fy * (uy * tzs) / (tzs * tzs)
    M = J @ R
    S2 = M @ Sigma @ M.transpose(0, 2, 1)
    a, b, c = S2[:, 0, 0] + 0.3, S2[:, 0, 1], S2[:, 1, 1] + 0.3
    det = a * c - b * b
    kept &= det > 0.0 if pf["det_le"] else det != 0.0
    dets = np.where(kept, det, 1.0)
    if pf["ext"] == "square":  # ceil(3·√λmax), λ from mid ± √max(0.1, mid² − det)
        mid = 0.5 * (a + c)
        e = np.sqrt(np.maximum(pf["lam_floor"], mid * mid - dets))
        rpre_x = rpre_y = pf["k"] * np.sqrt(np.maximum(mid + e, mid - e))
    else:  # per axis: ceil(3.33·√Σ'_aa) of the dilated covariance
        rpre_x, rpre_y = pf["k"] * np.sqrt(np.maximum(a, 0.0)), pf["k"] * np.sqrt(np.maximum(c, 0.0))
    m = np.stack([fx * (t[:, 0] / tzs) + (cam["cx"] - 0.5), fy * (t[:, 1] / tzs) + (cam["cy"] - 0.5)], 1)
    rect = tile_rects(m, np.ceil(rpre_x), np.ceil(rpre_y), pf, gx, gy)
    kept &= (rect[:, 2] > rect[:, 0]) & (rect[:, 3] > rect[:, 1])
    eye = -R.T @ T
    d = P["mu"] - eye
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    K = P["sh"].shape[1]
    raw = np.einsum("nk,nkc->nc", sh_basis(d)[:, :K], P["sh"]) + 0.5
    rec = {"kept": kept, "m": m, "conic": np.stack([c / dets, -b / dets, a / dets], 1), "o": P["o"].astype(float),
           "depth": tz, "colour": np.maximum(raw, 0.0), "rect": np.where(kept[:, None], rect, 0), "clamp": clamp,
           "cclamp": raw < 0.0}
    if margins:  # fragility at θ (module docstring): per Gaussian
        rel = lambda v, thr: np.abs(v / thr - 1.0)  # noqa: E731
        kink = (rel(rx_, lx) < MARGIN) | (rel(rx_, -lxn) < MARGIN) | (rel(ry_, ly) < MARGIN) | (rel(ry_, -lyn) < MARGIN) \
            | (np.abs(raw) < MARGIN).any(1)
        tiles_of = [set() for _ in range(n)]
        for i in range(n):  # rectangles within the margin: the near cull, the radius before its ceil, the centre
            near = rel(tz[i], pf["near"]) < MARGIN
            rects = []
            for fr in (1 - MARGIN, 1 + MARGIN):
                for dm in (-1e-4, 1e-4):
                    for ax in (0, 1):
                        mm = m[i:i + 1].copy()
                        mm[0, ax] += dm
                        rects.append(tile_rects(mm, np.ceil(rpre_x[i:i + 1] * fr), np.ceil(rpre_y[i:i + 1] * fr), pf, gx, gy)[0])
            if near or any((r != rect[i]).any() for r in rects):
                for r in rects + [rect[i]]:
                    tiles_of[i] |= {(tx, ty) for tx in range(r[0], r[2]) for ty in range(r[1], r[3])}
        rec["kink"] = kink
        rec["fragile_tiles"] = set().union(*tiles_of) if n else set()
    return rec


def make_tiles(W, H):
    """Each 16×16 tile: (tx, ty), flat pixel indices, pixel x and y (pixel-index coordinates: centre of (i, j) at (i, j))."""
    out = []
    for ty in range((H + 15) // 16):
        for tx in range((W + 15) // 16):
            js, is_ = np.meshgrid(np.arange(16 * ty, min(16 * ty + 16, H)), np.arange(16 * tx, min(16 * tx + 16, W)), indexing="ij")
            out.append(((tx, ty), (js * W + is_).ravel(), is_.ravel().astype(float), js.ravel().astype(float)))
    return out


def tile_list(rec, tx, ty):
    """The tile's Gaussians sorted by t.z ascending, ties in file order (SPEC §10.4)."""
    r = rec["rect"]
    idx = np.nonzero(rec["kept"] & (r[:, 0] <= tx) & (tx < r[:, 2]) & (r[:, 1] <= ty) & (ty < r[:, 3]))[0]
    return idx[np.lexsort((idx, rec["depth"][idx]))]


def raster_tile(rec, idx, px, py, Gt, bg, pf, margins=False, parts=False):
    """SPEC §10.4 for the pixels (px, py) of one tile over its list idx, float64: per pixel the loss Σ_ch G·C, the
    decision matrix (pixels × list: 0 not reached, 1 power > 0, 2 α < 1/255, 3 blended, 4 blended at the cap,
    5 the stop) and with margins the fragile pixels and the Gaussians near the cap; with parts the blend weights
    α·T [pixels, list] and T_f, from which the image is wgt @ colour + T_f·bg."""
    npx, n = len(px), len(idx)
    if n == 0:
        loss = Gt @ bg
        if parts:
            return loss, np.zeros((npx, 0), np.int8), np.zeros((npx, 0)), np.ones(npx)
        return (loss, np.zeros((npx, 0), np.int8)) + ((np.zeros(npx, bool), idx) if margins else ())
    dx = rec["m"][idx, 0][None, :] - px[:, None]
    dy = rec["m"][idx, 1][None, :] - py[:, None]
    A, B, Cc = (rec["conic"][idx, k][None, :] for k in range(3))
    power = -0.5 * ((A * dx) * dx + (Cc * dy) * dy) - (B * dx) * dy
    oe = rec["o"][idx][None, :] * np.exp(np.minimum(power, 0.0))
    alpha = np.minimum(pf["cap"], oe)
    if "cap_slope" in rec:  # finding 2's prediction only (inria_predicted): capped α made to follow o
        alpha = np.where(oe > pf["cap"], pf["cap"] * rec["cap_slope"][idx][None, :], alpha)
    valid = (power <= 0.0) & (alpha >= pf["floor"])
    om = np.where(valid, 1.0 - alpha, 1.0)
    after = np.cumprod(om, axis=1)  # sequential: T·(1 − α) at each blended position, T carried over the skipped
    before = np.concatenate([np.ones((npx, 1)), after[:, :-1]], 1)
    stop = valid & ((after < pf["t_min"]) | ((after == pf["t_min"]) if pf["stop_le"] else False))
    first = np.where(stop.any(1), stop.argmax(1), n)
    pos = np.arange(n)[None, :]
    blended = valid & (pos < first[:, None])
    wgt = np.where(blended, alpha * before, 0.0)
    rows = np.arange(npx)
    Tf = np.where(first < n, before[rows, np.minimum(first, n - 1)], after[:, -1])
    C = wgt @ rec["colour"][idx] + Tf[:, None] * bg[None, :]
    loss = (Gt * C).sum(1)
    st = np.where(power > 0.0, 1, np.where(alpha < pf["floor"], 2, np.where(oe > pf["cap"], 4, 3))).astype(np.int8)
    st[pos > first[:, None]] = 0
    st[rows[first < n], first[first < n]] = 5
    if parts:
        return loss, st, wgt, Tf
    if not margins:
        return loss, st
    reached = pos <= first[:, None]
    rel = lambda v, thr: np.abs(v / thr - 1.0)  # noqa: E731
    near_floor = reached & (power <= 0.0) & (rel(oe, pf["floor"]) < MARGIN)
    near_stop = reached & valid & (rel(after, pf["t_min"]) < MARGIN)
    near_cap = reached & (power <= 0.0) & (rel(oe, pf["cap"]) < MARGIN)
    return loss, st, near_floor.any(1) | near_stop.any(1), idx[near_cap.any(0)]


def loss_image(rec, cam, pf, G, tiles):
    """The whole image's per-pixel loss (float64 [H·W]) and decisions, for the self-checks."""
    out = np.zeros(cam["W"] * cam["H"])
    for (tx, ty), flat, px, py in tiles:
        out[flat] = raster_tile(rec, tile_list(rec, tx, ty), px, py, G[flat], cam["bg"], pf)[0]
    return out


# ---------------------------------------------------------------- finite differences

def entries(P, k, fx, depth):
    """The parameter entries of Gaussian k: (array name, index within it, getter/setter path, step h).

    Steps (float64 loss: rounding ≈ 1e-16·Σ|terms| per pixel, an error ≈ 1e-16·S/h in the difference; truncation
    ≈ (h/ℓ)²·|L'| before Richardson's extrapolation, (h/ℓ)⁴ after, ℓ the length over which the loss changes):
      means   h = 1e-5·ℓ, ℓ = max(smallest σ, one pixel's footprint t.z/fx): the dilation keeps every screen
              footprint ≥ 0.55 px, so the loss varies over no less than ℓ; truncation ≈ 1e-10 relative before
              extrapolation, rounding ≈ 1e-16·S/(1e-5·ℓ) ≈ 1e-8 absolute for S ≈ 1e2, ℓ ≈ 0.05;
      quats   h = 1e-5·|q| (the normalised rotation changes on the scale |q|);
      scales  h = 1e-5·max(σ_j, t.z/fx): relative, floored at the pixel footprint as for means;
      opacities h = 1e-5: the loss is a polynomial of low degree in o (truncation ≈ 1e-10·|L''|), rounding 1e-11·S;
      sh0, shN h = 1e-3: the loss is linear in an SH coefficient away from the colour's clamp (no truncation),
              so the larger step only lowers the rounding (≈ 1e-13·S); a clamp crossing is a decision.
    A step small enough to keep the decisions of almost every pixel: α moves by ≈ 1e-5 relative, so a pixel's α
    must lie within 1e-5 of 1/255, the cap or the stop for a decision to cross (and is then marked)."""
    foot = abs(depth) / fx if depth > 0 else 0.0
    hm = 1e-5 * max(P["s"][k].min(), foot)
    out = [("means", (j,), ("mu", j), hm) for j in range(3)]
    out += [("quats", (j,), ("q", j), 1e-5 * np.linalg.norm(P["q"][k])) for j in range(4)]
    out += [("scales", (j,), ("s", j), 1e-5 * max(P["s"][k, j], foot)) for j in range(3)]
    out += [("opacities", (), ("o", None), 1e-5)]
    out += [("sh0", (0, c), ("sh", (0, c)), 1e-3) for c in range(3)]
    out += [("shN", (i - 1, c), ("sh", (i, c)), 1e-3) for i in range(1, P["sh"].shape[1]) for c in range(3)]
    return out


def row_of(P, k):
    return {key: P[key][k:k + 1].copy() for key in ("mu", "q", "s", "o", "sh")}


def perturbed(P, k, path, dh):
    row = row_of(P, k)
    key, j = path
    if key == "o":
        row["o"][0] += dh
    elif key == "sh":
        row["sh"][0, j[0], j[1]] += dh
    else:
        row[key][0, j] += dh
    return row


def with_row(base, k, r1):
    out = dict(base)
    for key in ("kept", "m", "conic", "o", "depth", "colour", "rect", "clamp", "cclamp"):
        a = base[key].copy()
        a[k] = r1[key][0]
        out[key] = a
    return out


def tiles_covered(rec, k):
    if not rec["kept"][k]:
        return set()
    r = rec["rect"][k]
    return {(tx, ty) for tx in range(r[0], r[2]) for ty in range(r[1], r[3])}


def fd_gradients(P, cam, profile, G, log=None):
    """Every parameter's central difference (module docstring): dict with the arrays of NAMES (float64), their
    masks "smooth_<name>", "abs_<name>" (Σ over pixels of |∂L_p/∂θ|, the magnitude of the terms summed) and
    "fderr_<name>" (the difference's own error bound)."""
    pf = PROFILES[profile]
    W, H = cam["W"], cam["H"]
    G = np.asarray(G, float).reshape(H * W, 3)
    n, K = len(P["o"]), P["sh"].shape[1]
    shapes = {"means": (n, 3), "quats": (n, 4), "scales": (n, 3), "opacities": (n,), "sh0": (n, 1, 3), "shN": (n, K - 1, 3)}
    out = {}
    for nm, shp in shapes.items():
        out[nm], out["abs_" + nm], out["fderr_" + nm] = np.zeros(shp), np.zeros(shp), np.zeros(shp)
        out["smooth_" + nm] = np.zeros(shp, bool)
    tiles = make_tiles(W, H)
    tile_at = {t[0]: t for t in tiles}
    base = preprocess(P, cam, pf, margins=True)
    base_list, base_sig = {}, {}
    fragile = base["kink"].copy()
    base_parts, base_mag = {}, {}
    for key, flat, px, py in tiles:
        idx = tile_list(base, *key)
        loss, st, frag_px, near_cap = raster_tile(base, idx, px, py, G[flat], cam["bg"], pf, margins=True)
        base_list[key], base_sig[key] = idx, (tuple(idx), st.tobytes())
        base_parts[key] = wgt, Tf = raster_tile(base, idx, px, py, G[flat], cam["bg"], pf, parts=True)[2:]
        # Σ over the tile's pixels and channels of |G|·C: the magnitude of the loss's terms (C's are all ≥ 0)
        base_mag[key] = (np.abs(G[flat]) * (wgt @ base["colour"][idx] + Tf[:, None] * cam["bg"][None, :])).sum()
        fragile[near_cap] = True
        dz = np.diff(base["depth"][idx])
        if frag_px.any() or key in base["fragile_tiles"] or (len(idx) > 1 and (dz <= MARGIN * base["depth"][idx][1:]).any()):
            fragile[idx] = True
    for key in base["fragile_tiles"]:  # a Gaussian that may enter a tile it is not in: every Gaussian there
        fragile[base_list[key]] = True
    reason = {"decision": 0, "richardson": 0, "fragile": 0}
    t0 = time.time()
    for k in range(n):
        for name, ix, path, h in entries(P, k, cam["fx"], base["depth"][k]):
            recs = [with_row(base, k, preprocess(perturbed(P, k, path, dh), cam, pf)) for dh in (h, -h, h / 2, -h / 2)]
            cover = tiles_covered(base, k).union(*(tiles_covered(r, k) for r in recs))
            same = all(r["kept"][k] == base["kept"][k] and (r["rect"][k] == base["rect"][k]).all() and (r["clamp"][k] == base["clamp"][k]).all()
                       and (r["cclamp"][k] == base["cclamp"][k]).all() for r in recs)
            # an SH coefficient moves the colour alone: the tiles' geometry (lists, decisions, weights α·T and T_f)
            # is then bit for bit the base's, and the forward is C = wgt @ colour + T_f·bg with the base's weights
            colour_only = path[0] == "sh" and all((r[key][k] == base[key][k]).all() for r in recs
                                                  for key in ("kept", "m", "conic", "o", "depth", "rect", "clamp"))
            lp = [[], [], [], []]
            mag = 0.0
            for key in sorted(cover):
                _, flat, px, py = tile_at[key]
                for e, r in enumerate(recs):
                    if colour_only:
                        wgt, Tf = base_parts[key]
                        idx = base_list[key]
                        loss = (G[flat] * (wgt @ r["colour"][idx] + Tf[:, None] * cam["bg"][None, :])).sum(1)
                    else:
                        idx = tile_list(r, *key)
                        loss, st = raster_tile(r, idx, px, py, G[flat], cam["bg"], pf)
                        same = same and (tuple(idx), st.tobytes()) == base_sig[key]
                    lp[e].append(loss)
                mag += base_mag[key]
            lp = [np.concatenate(v) if v else np.zeros(0) for v in lp]
            d1 = (lp[0] - lp[1]).sum() / (2 * h)
            dp2 = (lp[2] - lp[3]) / h
            d2 = dp2.sum()
            rb = 64 * EPS64 * mag / h  # the loss's float64 rounding (≤ 64 terms a pixel) over the difference
            rich = abs(d1 - d2) <= 1e-6 * abs(d2) + 8 * rb
            at = (k,) + ix
            out[name][at] = (4 * d2 - d1) / 3
            out["abs_" + name][at] = np.abs(dp2).sum()
            out["fderr_" + name][at] = abs(d1 - d2) / 3 + 3 * rb
            ok = same and rich and not fragile[k]
            out["smooth_" + name][at] = ok
            if not ok:
                reason["fragile" if fragile[k] else "decision" if not same else "richardson"] += 1
        if log and (k + 1) % 10 == 0:
            log("  fd %s: %d/%d Gaussians (%.0f s)" % (profile, k + 1, n, time.time() - t0))
    out["reasons"] = reason
    return out


# ---------------------------------------------------------------- scenes and the CLI

def read_params(path, sh_degree=3):
    """A 3DGS PLY (binary little endian) as the oracle's parameters: quaternions as stored (not normalised),
    σ = exp(scale_*), o = sigmoid(opacity), SH coefficient-major [n, K, 3]."""
    v, props = go.ply_vertices(path)
    n = len(v)
    K = (sh_degree + 1) ** 2
    rest = sorted((p for p, _ in props if p.startswith("f_rest_")), key=lambda p: int(p[7:]))
    per = len(rest) // 3
    sh = np.zeros((n, K, 3))
    for ch in range(3):
        sh[:, 0, ch] = v["f_dc_%d" % ch]
        for i in range(min(per, K - 1)):
            sh[:, i + 1, ch] = v[rest[ch * per + i]]
    f = lambda names: np.stack([v[p].astype(np.float64) for p in names], 1)  # noqa: E731
    return {"mu": f(["x", "y", "z"]), "q": f(["rot_%d" % i for i in range(4)]), "s": np.exp(f(["scale_%d" % i for i in range(3)])),
            "o": 1.0 / (1.0 + np.exp(-v["opacity"].astype(np.float64))), "sh": sh}


def camera(eye, W, H, fov_deg=45.0, target=(0.0, 0.0, 0.0), bg=(0.2, 0.3, 0.4)):
    """A pinhole looking at target, every number rounded to float32 first: the reference rounds the camera to
    float (SPEC §10.2), the oracle then computes with the same values in float64."""
    R, t = look_from(eye, target)
    fx = 0.5 * H / math.tan(math.radians(fov_deg) / 2)
    r32 = lambda v: np.asarray(v, np.float32).astype(np.float64)  # noqa: E731
    return {"R": r32(R), "t": r32(t), "fx": float(r32(fx)), "fy": float(r32(fx)), "cx": W / 2.0, "cy": H / 2.0, "W": W, "H": H,
            "bg": r32(bg)}


def random_quats(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True) * rng.uniform(0.5, 2.0, size=(n, 1))  # not unit: the projection


def scene_mixed(rng, n=40, half=0.7, s_min=0.02, size=(64, 48)):
    """n anisotropic Gaussians of every size (σ from s_min to 0.25, centres in a box of half-width half), SH degree 3,
    o ≤ 0.92 (no cap), every centre inside the clamp; 40 at 64x48 here, python/tests/test_grad.py's 16 at 48x32."""
    mu = rng.uniform(-half, half, size=(n, 3))
    log_s = np.log(rng.uniform(s_min, 0.25, size=(n, 3)))
    sh = np.zeros((n, 16, 3))
    sh[:, 0] = rng.uniform(-1.5, 1.5, size=(n, 3))
    sh[:, 1:] = rng.uniform(-0.3, 0.3, size=(n, 15, 3))
    return mu, log_s, random_quats(rng, n), rng.uniform(-2.0, 2.4, size=n), sh, camera((1.1, 0.7, -3.3), *size), None, {}


def scene_stack(rng):
    """Five large o = 0.95 Gaussians stacked in depth before 20 small ones: T falls below 1e-4 at the fourth
    near the centre, so the loop stops there (and later Gaussians get no gradient)."""
    n0, n1 = 5, 20
    mu = np.concatenate([np.stack([rng.uniform(-0.1, 0.1, n0), rng.uniform(-0.1, 0.1, n0), np.linspace(-0.6, 0.4, n0)], 1),
                         rng.uniform(-0.8, 0.8, size=(n1, 3))])
    log_s = np.log(np.concatenate([rng.uniform(0.25, 0.4, size=(n0, 3)), rng.uniform(0.03, 0.15, size=(n1, 3))]))
    sh = np.zeros((n0 + n1, 16, 3))
    sh[:, 0] = rng.uniform(-1.5, 1.5, size=(n0 + n1, 3))
    sh[:, 1:] = rng.uniform(-0.2, 0.2, size=(n0 + n1, 15, 3))
    logit = np.concatenate([np.full(n0, math.log(0.95 / 0.05)), rng.uniform(-1.0, 2.0, n1)])
    return mu, log_s, random_quats(rng, n0 + n1), logit, sh, camera((0.3, -0.2, -3.0), 64, 48), None, {}


def scene_cap(rng):
    """Finding 2 (docs/gradients.md): Gaussian 0, o = sigmoid(8) ≈ 0.99966 and σ ≈ 18 px on screen, has
    o·e^power > 0.99 within ≈ 2.5 px of its centre; G is 30 there (sign of c − bg per channel), random elsewhere,
    so those pixels dominate its opacity gradient: inria passes ∂α/∂o = G there, gsplat (and the derivative) 0."""
    n = 6
    mu = np.concatenate([[[0.02, -0.03, 0.0]], rng.uniform(-0.6, 0.6, size=(n - 1, 3)) * [1, 1, 0.5] + [0, 0, 0.8]])
    log_s = np.log(np.concatenate([[[0.9, 0.75, 0.5]], rng.uniform(0.05, 0.2, size=(n - 1, 3))]))
    sh = np.zeros((n, 16, 3))
    sh[0, 0] = (np.array([0.9, 0.1, 0.15]) - 0.5) / go.SH_C0
    sh[1:, 0] = rng.uniform(-1.5, 1.5, size=(n - 1, 3))
    sh[1:, 1:] = rng.uniform(-0.2, 0.2, size=(n - 1, 15, 3))
    q = random_quats(rng, n)
    q[0] = [1.3, 0.1, -0.05, 0.2]
    logit = np.concatenate([[8.0], rng.uniform(-1.0, 1.5, n - 1)])
    return mu, log_s, q, logit, sh, camera((0.0, 0.0, -3.0), 48, 32), "cap", {"gaussian": 0, "array": "opacities"}


def scene_side(rng):
    """Finding 1: Gaussian 0 sits at t.x/t.z ≈ 1.6·tan(fovx/2), beyond the clamp 1.3·tan (both profiles clamp
    there: gsplat's limit from the centred principal point is the same 1.3·tan), elongated along the viewing axis
    (σ_z = 1.2) so that J02 = −fx·u/t.z², and so its t.z term, carries its screen width into the image;
    inria's backward doubles that t.z term (means, z)."""
    n = 5
    cam = camera((0.0, 0.0, -3.0), 48, 32)
    tanx = 0.5 * cam["W"] / cam["fx"]
    # camera R = diag(−1, −1, 1) here (look_from with up +y): world x = −camera x; t.z = 3 + μ.z
    mu = np.concatenate([[[-1.6 * tanx * 3.2, 0.15, 0.2]], rng.uniform(-0.5, 0.5, size=(n - 1, 3))])
    log_s = np.log(np.concatenate([[[0.35, 0.3, 1.2]], rng.uniform(0.05, 0.2, size=(n - 1, 3))]))
    sh = np.zeros((n, 16, 3))
    sh[:, 0] = rng.uniform(-1.5, 1.5, size=(n, 3))
    sh[0, 0] = (np.array([0.95, 0.85, 0.1]) - 0.5) / go.SH_C0
    sh[1:, 1:] = rng.uniform(-0.2, 0.2, size=(n - 1, 15, 3))
    q = random_quats(rng, n)
    q[0] = [0.9, 0.05, 0.12, -0.03]
    logit = np.concatenate([[1.5], rng.uniform(-1.0, 1.5, n - 1)])
    return mu, log_s, q, logit, sh, cam, "side", {"gaussian": 0, "array": "means"}


def upstream(rng, cam, special=None):
    """G: float32 [H, W, 3], row 0 the top row."""
    return rng.normal(size=(cam["H"], cam["W"], 3)).astype(np.float32)


def cli_args(cam, ply, profile):
    m12 = ",".join("%.9g" % v for v in np.concatenate([cam["R"], cam["t"][:, None]], 1).ravel())
    return ["--model", ply, "--algo", "gauss3d", "--sh-degree", "3", "--size", "%dx%d" % (cam["W"], cam["H"]),
            "--intrinsics", "%.9g,%.9g,%.9g,%.9g" % (cam["fx"], cam["fy"], cam["cx"], cam["cy"]), "--world-to-camera", m12,
            "--background", "%.9g,%.9g,%.9g" % tuple(cam["bg"]), "--gauss-profile", profile]


# Tolerance of the reference (float32) against the oracle, per entry:
#   |ref − fd| ≤ 512·2⁻²⁴·M + 3·fderr
# M: the magnitude of the terms the reference sums, Σ over pixels of |∂L_p/∂θ| (the oracle's per-pixel
# differences); for means, quats and scales the largest of the Gaussian's components (they come out of one
# chain, ∂L/∂m2d and ∂L/∂conic through J, W, Σ and Rq, whose float32 error scales with the largest of them, not
# with a component that cancels to near 0).  512 ulps: a pixel's term carries ≲ 150 roundings (power 6, exp
# 1 ulp, α and T over a list of ≤ 60 Gaussians ≤ 60, the colour behind by the recurrence ≤ 60, its chain to
# conic and means2d ≈ 10, the float32 inputs — σ, o, the rotation — ≈ 5); the per-tile sum over ≤ 256 pixels in
# a fixed order errs by at most 255 ulps of Σ|terms|, the sum over ≤ 12 tiles 11 more; the per-Gaussian chain
# (Σ' → Σ → Rq, q̂ → q, SH → means) ≈ 30; 150 + 266 + 30 < 512.  fderr: the difference's own error bound
# (Richardson's |D(h) − D(h/2)|/3 and the float64 rounding of the loss over the step), 3× as a margin.
KULP = 512


def compare(fd, ref, names=NAMES, group=("means", "quats", "scales")):
    """Per array: (compared, not smooth, max |Δ|/M, max |Δ|/tol, list of failing entries (index, ref, fd, Δ/tol))."""
    res = {}
    for nm in names:
        a, b = np.asarray(ref[nm], float), fd[nm]
        if a.shape != b.shape:
            res[nm] = (0, 0, float("inf"), float("inf"), [("shape", a.shape, b.shape, float("inf"))])
            continue
        M = fd["abs_" + nm]
        if nm in group:
            M = np.broadcast_to(M.max(axis=1, keepdims=True), M.shape)
        tol = KULP * EPS32 * M + 3 * fd["fderr_" + nm] + 1e-30
        mask = fd["smooth_" + nm]
        d = np.abs(a - b)
        bad = mask & ~(d <= tol)
        relM = (d / np.maximum(M, 1e-30))[mask]
        ratio = (d / tol)[mask]
        fails = [(tuple(int(v) for v in i), float(a[tuple(i)]), float(b[tuple(i)]), float((d / tol)[tuple(i)])) for i in np.argwhere(bad)]
        res[nm] = (int(mask.sum()), int((~mask).sum()), float(relM.max()) if relM.size else 0.0,
                   float(ratio.max()) if ratio.size else 0.0, fails)
    return res


def run_grad(cli, cam, ply, profile, gpath, out):
    cmd = [cli, "grad"] + cli_args(cam, ply, profile) + ["--dl-dimage", gpath, "--out", out]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode:
        raise RuntimeError("splatref grad failed (%d): %s\n  %s" % (r.returncode, r.stderr.strip(), " ".join(cmd)))
    with np.load(out) as z:
        return {k: z[k] for k in z.files}


def has_grad(cli):
    r = subprocess.run([cli, "grad", "--help"], capture_output=True, text=True)
    return r.returncode == 0


def build_scenes(work, rng):
    scenes = []
    for make in (scene_mixed, scene_stack, scene_cap, scene_side):
        mu, log_s, q, logit, sh, cam, finding, fdesc = make(rng)
        name = make.__name__[6:]
        ply = os.path.join(work, name + ".ply")
        write_ply(ply, mu, log_s, q, logit, sh)
        P = read_params(ply, 3)  # the float32 values written are the oracle's θ
        G = upstream(rng, cam)
        if finding == "cap":  # the capped pixels dominate: 30·sign(c − bg) there
            pre = preprocess(P, cam, PROFILES["gsplat"])
            js, is_ = np.mgrid[0:cam["H"], 0:cam["W"]]
            dx, dy = pre["m"][0, 0] - is_, pre["m"][0, 1] - js
            A, B, C = pre["conic"][0]
            capped = P["o"][0] * np.exp(-0.5 * (A * dx * dx + C * dy * dy) - B * dx * dy) > 0.99
            G[capped] = (30.0 * np.sign(pre["colour"][0] - cam["bg"])).astype(np.float32)
            fdesc["capped_pixels"] = int(capped.sum())
        gpath = os.path.join(work, name + "-G.npy")
        np.save(gpath, G)
        scenes.append((name, ply, P, cam, G, gpath, finding, fdesc))
    return scenes


def scene_facts(P, cam):
    """How many Gaussians are capped somewhere, tangent-clamped, culled (under each profile), for the log."""
    out = []
    for prof, pf in PROFILES.items():
        pre = preprocess(P, cam, pf)
        js, is_ = np.mgrid[0:cam["H"], 0:cam["W"]]
        capped = []
        for k in np.nonzero(pre["kept"])[0]:
            dx, dy = pre["m"][k, 0] - is_, pre["m"][k, 1] - js
            A, B, C = pre["conic"][k]
            if (P["o"][k] * np.exp(-0.5 * (A * dx * dx + C * dy * dy) - B * dx * dy) > pf["cap"]).any():
                capped.append(int(k))
        stops = 0
        for (tx, ty), flat, px, py in make_tiles(cam["W"], cam["H"]):
            st = raster_tile(pre, tile_list(pre, tx, ty), px, py, np.zeros((len(px), 3)), cam["bg"], pf)[1]
            stops += int((st == 5).any(1).sum())
        out.append("%s: %d kept, capped %s, tangent-clamped %s, %d pixels stop" % (
            prof, int(pre["kept"].sum()), capped, [int(k) for k in np.nonzero(pre["clamp"].any(1) & pre["kept"])[0]], stops))
    return "; ".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli")
    ap.add_argument("--work", default="grad-oracle")
    ap.add_argument("--self-check", action="store_true", help="the oracle's own checks (no splatref)")
    ap.add_argument("--break", dest="brk", action="store_true", help="flip the sign of the reference's sh0 (the test must fail)")
    ap.add_argument("--scenes", default="mixed,stack,cap,side")
    a = ap.parse_args()
    if a.self_check:
        return self_check()
    if not a.cli:
        ap.error("--cli or --self-check")
    if not has_grad(a.cli):
        print("grad_oracle: %s has no `grad` command yet: skipped (the oracle's own checks: --self-check)" % a.cli)
        return 77
    os.makedirs(a.work, exist_ok=True)
    rng = np.random.default_rng(20261207)
    failed = 0
    want = a.scenes.split(",")
    for name, ply, P, cam, G, gpath, finding, fdesc in build_scenes(a.work, rng):
        if name not in want:
            continue
        print("grad_oracle: scene %s: %d Gaussians, %dx%d; %s" % (name, len(P["o"]), cam["W"], cam["H"], scene_facts(P, cam)))
        for profile in ("gsplat", "inria"):
            t0 = time.time()
            fd = fd_gradients(P, cam, profile, G)
            np.savez(os.path.join(a.work, "%s-%s-fd.npz" % (name, profile)), **{k: v for k, v in fd.items() if k != "reasons"})
            try:
                ref = run_grad(a.cli, cam, ply, profile, gpath, os.path.join(a.work, "%s-%s-ref.npz" % (name, profile)))
            except RuntimeError as e:
                print("grad_oracle:   %s: %s  FAIL" % (profile, e))
                failed += 1
                continue
            if a.brk:
                ref["sh0"] = -ref["sh0"]
            res = compare(fd, ref)
            print("grad_oracle:   %s (fd %.0f s; not smooth: %s)" % (profile, time.time() - t0,
                                                                     ", ".join("%s %d" % kv for kv in fd["reasons"].items())))
            expected = set()
            if finding and profile == "inria":  # the finding Gaussian's entries are inria's own (docs/gradients.md)
                kf = fdesc["gaussian"]
                expected = {(nm, kf) for nm in ("means", "quats", "scales", "opacities")}
            for nm in NAMES:
                comp, ns, relM, ratio, fails = res[nm]
                fails_other = [f for f in fails if f[0] == "shape" or (nm, f[0][0]) not in expected]
                print("grad_oracle:     %-9s compared %5d  not smooth %4d  max |Δ|/M %.2e  max |Δ|/tol %.3g%s" % (
                    nm, comp, ns, relM, ratio, "" if not fails_other else "  FAIL (%d)" % len(fails_other)))
                for f in fails_other[:6]:
                    print("grad_oracle:       %s%s: ref %.9g, oracle %.9g, |Δ|/tol %.3g" % (nm, list(f[0]) if f[0] != "shape" else "", f[1], f[2], f[3]))
                failed += bool(fails_other)
            if finding:
                failed += report_finding(finding, fdesc, fd, ref, profile, P, cam, G)
    print("grad_oracle: %s" % ("every array agrees" if not failed else "%d disagreements" % failed))
    return 1 if failed else 0


def inria_predicted(finding, k, P, cam, G):
    """What inria's backward gives for the finding's Gaussian k, from the oracle's forward:
    side: the derivative plus the clamped t.z term of J once more.  J02 = −fx·lim/t.z when clamped, so the t.z
      term alone is the derivative of L in a factor s on k's limits (J02 ∝ lim·s/t.z): X = −∂L/∂s / t.z at s = 1,
      and inria's means = derivative + Rᵀ·(0, 0, X) (∂t/∂μ = R);
    cap: the derivative plus, at the capped pixels, ∂L/∂α·e^power.  Approximated by making the capped α follow
      o as 0.99·o/o₀ (slope 0.99/o₀ in place of e^power ∈ (0.99/o₀, 1]): within 1% of the ungated term."""
    pf = PROFILES["inria"]
    tiles = make_tiles(cam["W"], cam["H"])
    Gf = np.asarray(G, float).reshape(-1, 3)
    n = len(P["o"])
    if finding == "side":
        tz = (cam["R"] @ P["mu"][k] + cam["t"])[2]

        def L(e):
            sc = np.ones(n)
            sc[k] += e
            return loss_image(preprocess(P, cam, pf, lim_scale=sc), cam, pf, Gf, tiles).sum()
        X = -(L(1e-6) - L(-1e-6)) / 2e-6 / tz
        return cam["R"][2] * X  # Rᵀ·(0, 0, X)
    o0 = P["o"][k]

    def L(e):
        Q = dict(P, o=P["o"].copy())
        Q["o"][k] += e
        rec = preprocess(Q, cam, pf)
        rec["cap_slope"] = np.ones(n)
        rec["cap_slope"][k] = Q["o"][k] / o0
        return loss_image(rec, cam, pf, Gf, tiles).sum()
    return np.array([(L(1e-6) - L(-1e-6)) / 2e-6])


def report_finding(finding, fdesc, fd, ref, profile, P=None, cam=None, G=None):
    """The finding's Gaussian: gsplat must match the finite difference, inria must not (by how much)."""
    k, nm = fdesc["gaussian"], fdesc["array"]
    M = fd["abs_" + nm][k]
    if nm == "means":
        M = np.full_like(M, M.max())
    tol = KULP * EPS32 * M + 3 * fd["fderr_" + nm][k]
    r, o, sm = np.atleast_1d(np.asarray(ref[nm][k], float)), np.atleast_1d(fd[nm][k]), np.atleast_1d(fd["smooth_" + nm][k])
    tol = np.atleast_1d(tol)
    what = {"cap": "α cap (o·e^power > 0.99 at %d pixels)" % fdesc.get("capped_pixels", 0),
            "side": "tangent clamp (t.z term of the Jacobian)"}[finding]
    for i in range(len(r)):
        print("grad_oracle:     finding %s, %s[%d]%s: %s %.9g, oracle %.9g (Δ %.3g = %.3g tol, ratio %.4f)%s" % (
            what, nm, k, "" if len(r) == 1 else "[%d]" % i, profile, r[i], o[i], r[i] - o[i], abs(r[i] - o[i]) / tol[i],
            r[i] / o[i] if o[i] else float("nan"), "" if sm[i] else " (not smooth)"))
    if profile == "inria" and P is not None:
        pred = inria_predicted(finding, k, P, cam, G)
        if finding == "side":
            pred = o + pred
        print("grad_oracle:     finding %s: inria predicted from the forward (%s): %s; inria gives %s" % (
            finding, "the derivative + the clamped t.z term again" if finding == "side" else "the ungated cap, within 1%",
            np.array2string(pred, precision=6), np.array2string(r, precision=6)))
    if not sm.all():
        print("grad_oracle:     finding %s: the entries are not smooth: FAIL (the scene must be remade)" % finding)
        return 1
    off = np.abs(r - o) > tol
    if profile == "inria" and not off.any():
        print("grad_oracle:     finding %s: inria's gradient matches the derivative: FAIL (the finding is not shown)" % finding)
        return 1
    if profile != "inria" and off.any():
        return 1  # already counted by compare() as a failing entry
    return 0


# ---------------------------------------------------------------- self-checks (no splatref)

def self_check():
    """The oracle against hand derivations, without the reference:
    1. one Gaussian alone, background 0: ∂L/∂c = Σ_p G·α (through sh0: ∂c/∂sh0 = C0);
    2. the opacity of a two-Gaussian stack: ∂L/∂o = Σ_p ⟨c T − S_behind/(1 − α) − T_f·bg/(1 − α), G⟩·e^power
       (the formula of docs/gradients.md), with α, T, S from the oracle's own forward at θ;
    3. a Gaussian at the cap: its opacity's difference is 0 at the capped pixels (only outside the cap counts);
    4. the tangent clamp: a clamped Gaussian's means gradient against the float64 difference of a forward with
       the clamp's J02 = −fx·lim/t.z written out by hand (the same loss, another arithmetic path)."""
    rng = np.random.default_rng(7)
    ok = True
    cam = camera((0.0, 0.0, -3.0), 48, 32, bg=(0.0, 0.0, 0.0))
    pf = PROFILES["gsplat"]
    tiles = make_tiles(cam["W"], cam["H"])
    G = rng.normal(size=(cam["H"], cam["W"], 3))
    Gf = G.reshape(-1, 3)
    js, is_ = np.mgrid[0:cam["H"], 0:cam["W"]]

    def alpha_of(pre, k):
        dx, dy = pre["m"][k, 0] - is_, pre["m"][k, 1] - js
        A, B, C = pre["conic"][k]
        pw = -0.5 * (A * dx * dx + C * dy * dy) - B * dx * dy
        return np.minimum(0.99, P["o"][k] * np.exp(pw)), np.exp(pw)

    # 1
    P = {"mu": np.array([[0.05, -0.02, 0.1]]), "q": np.array([[1.0, 0.2, -0.1, 0.3]]), "s": np.array([[0.2, 0.12, 0.3]]),
         "o": np.array([0.7]), "sh": np.zeros((1, 16, 3))}
    P["sh"][0, 0] = [0.5, -0.2, 0.9]
    fd = fd_gradients(P, cam, "gsplat", G)
    pre = preprocess(P, cam, pf)
    al, _ = alpha_of(pre, 0)
    al = np.where(al >= 1.0 / 255.0, al, 0.0)
    inside = np.zeros((cam["H"], cam["W"]), bool)
    r = pre["rect"][0]
    inside[16 * r[1]:16 * r[3], 16 * r[0]:16 * r[2]] = True
    hand = go.SH_C0 * (G * (al * inside)[:, :, None]).sum((0, 1))
    err = np.abs(fd["sh0"][0, 0] - hand).max() / np.abs(hand).max()
    print("self-check 1: ∂L/∂sh0 of one Gaussian: oracle %s, hand %s, rel err %.2e" % (fd["sh0"][0, 0], hand, err))
    ok &= err < 1e-9 and fd["smooth_sh0"].all()
    # 2
    cam2 = dict(cam, bg=np.array([0.2, 0.3, 0.4]))
    P = {"mu": np.array([[0.05, -0.02, -0.2], [-0.1, 0.05, 0.3]]), "q": np.array([[1.0, 0.2, -0.1, 0.3], [0.8, -0.3, 0.1, 0.0]]),
         "s": np.array([[0.2, 0.12, 0.3], [0.25, 0.3, 0.2]]), "o": np.array([0.6, 0.8]), "sh": np.zeros((2, 16, 3))}
    P["sh"][:, 0] = [[0.5, -0.2, 0.9], [-0.4, 0.7, 0.1]]
    fd = fd_gradients(P, cam2, "gsplat", G)
    pre = preprocess(P, cam2, pf)
    a0, e0 = alpha_of(pre, 0)
    a1, _ = alpha_of(pre, 1)
    in_ = []
    for k in range(2):
        r = pre["rect"][k]
        m = np.zeros((cam["H"], cam["W"]), bool)
        m[16 * r[1]:16 * r[3], 16 * r[0]:16 * r[2]] = True
        in_.append(m)
    a0 = np.where((a0 >= 1 / 255) & in_[0], a0, 0.0)
    a1 = np.where((a1 >= 1 / 255) & in_[1], a1, 0.0)
    assert pre["depth"][0] < pre["depth"][1]
    c0, c1, bg = pre["colour"][0], pre["colour"][1], cam2["bg"]
    T1 = 1 - a0
    Tf = T1 * (1 - a1)
    S1 = (c1[None, None, :] * (a1 * T1)[:, :, None])
    dC_da0 = c0[None, None, :] - S1 / (1 - a0)[:, :, None] - (Tf / (1 - a0))[:, :, None] * bg[None, None, :]  # T0 = 1
    hand = ((dC_da0 * G).sum(2) * np.where(a0 > 0, e0, 0.0)).sum()
    err = abs(fd["opacities"][0] - hand) / abs(hand)
    print("self-check 2: ∂L/∂o of the front of two: oracle %.12g, hand %.12g, rel err %.2e" % (fd["opacities"][0], hand, err))
    ok &= err < 1e-8 and fd["smooth_opacities"][0]
    # 3: a capped Gaussian: the derivative ignores its capped pixels
    P = {"mu": np.array([[0.0, 0.0, 0.0]]), "q": np.array([[1.0, 0.0, 0.0, 0.0]]), "s": np.array([[0.6, 0.5, 0.4]]),
         "o": np.array([0.9997]), "sh": np.zeros((1, 16, 3))}
    P["sh"][0, 0] = [0.9, 0.1, 0.2]
    fd = fd_gradients(P, cam2, "gsplat", G)
    pre = preprocess(P, cam2, pf)
    a0, e0 = alpha_of(pre, 0)
    capped = P["o"][0] * e0 > 0.99
    live = (a0 >= 1 / 255) & ~capped
    dC = pre["colour"][0][None, None, :] - cam2["bg"][None, None, :]
    hand = ((dC * G).sum(2) * e0 * live).sum()
    ungated = ((dC * G).sum(2) * e0 * (a0 >= 1 / 255)).sum()
    err = abs(fd["opacities"][0] - hand) / abs(hand)
    print("self-check 3: ∂L/∂o at the cap (%d capped pixels): oracle %.12g, hand (gated) %.12g, rel err %.2e; ungated %.12g"
          % (capped.sum(), fd["opacities"][0], hand, err, ungated))
    ok &= err < 1e-8 and capped.sum() > 0 and fd["smooth_opacities"][0]
    # 4: a tangent-clamped Gaussian, the loss by another path: a direct per-pixel loop written out with u = lim·t.z
    tanx = 0.5 * cam["W"] / cam["fx"]
    P = {"mu": np.array([[-1.6 * tanx * 3.2, 0.1, 0.2]]), "q": np.array([[0.9, 0.05, 0.12, -0.03]]), "s": np.array([[0.35, 0.3, 1.2]]),
         "o": np.array([0.8]), "sh": np.zeros((1, 16, 3))}
    P["sh"][0, 0] = [0.9, 0.8, 0.1]
    fd = fd_gradients(P, cam2, "gsplat", G)
    pre = preprocess(P, cam2, pf)
    assert pre["clamp"][0, 0] == 1, pre["clamp"]

    def loss_direct(mu):
        R, t = cam2["R"], cam2["t"]
        tc = R @ mu + t
        lim = (cam["W"] - cam["cx"]) / cam["fx"] + 0.3 * tanx
        q = P["q"][0] / np.linalg.norm(P["q"][0])
        w, x, y, z = q
        Rq = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                       [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        Sg = Rq @ np.diag(P["s"][0] ** 2) @ Rq.T
        J = np.array([[cam["fx"] / tc[2], 0, -cam["fx"] * lim / tc[2]], [0, cam["fy"] / tc[2], -cam["fy"] * tc[1] / tc[2] ** 2]])
        S2 = J @ R @ Sg @ R.T @ J.T + 0.3 * np.eye(2)
        Ci = np.linalg.inv(S2)
        m = np.array([cam["fx"] * tc[0] / tc[2] + cam["cx"] - 0.5, cam["fy"] * tc[1] / tc[2] + cam["cy"] - 0.5])
        d = np.stack([m[0] - is_, m[1] - js], -1)
        pw = -0.5 * np.einsum("hwi,ij,hwj->hw", d, Ci, d)
        al = np.minimum(0.99, P["o"][0] * np.exp(pw))
        al = np.where((al >= 1 / 255) & in_r, al, 0.0)
        eye = -R.T @ t
        dd = (mu - eye) / np.linalg.norm(mu - eye)
        col = np.maximum(sh_basis(dd[None])[0] @ P["sh"][0] + 0.5, 0)
        C = al[:, :, None] * col + (1 - al)[:, :, None] * cam2["bg"]
        return (G * C).sum()
    r = pre["rect"][0]
    in_r = np.zeros((cam["H"], cam["W"]), bool)
    in_r[16 * r[1]:16 * r[3], 16 * r[0]:16 * r[2]] = True
    hand = np.zeros(3)
    for j in range(3):
        e = np.zeros(3)
        e[j] = 1e-6
        hand[j] = (loss_direct(P["mu"][0] + e) - loss_direct(P["mu"][0] - e)) / 2e-6
    err = np.abs(fd["means"][0] - hand).max() / np.abs(hand).max()
    print("self-check 4: ∂L/∂means of a tangent-clamped Gaussian: oracle %s, direct %s, rel err %.2e" % (fd["means"][0], hand, err))
    ok &= err < 1e-6 and fd["smooth_means"][0].all()
    print("self-check: %s" % ("passed" if ok else "FAILED"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
