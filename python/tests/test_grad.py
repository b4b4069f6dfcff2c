"""Scene.grad (issue 43 item 3): gauss3d's gradients from Python against the independent float64
finite-difference oracle (tests/oracle/grad_oracle.py: its scene writer, its differences, its tolerance rule)
and against `splatref grad`'s .npz, bit for bit."""
import os
import subprocess
import sys

import numpy as np
import pytest
import splatref as sr

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "oracle"))
import grad_oracle as gro  # noqa: E402
from run_oracle import write_ply  # noqa: E402

CLI = os.environ.get("SPLATREF_CLI")
NAMES = ("means", "quats", "scales", "opacities", "sh0", "shN", "means2d", "conics", "colors", "absgrad", "counts")


def scene_small(rng):
    """16 anisotropic Gaussians of SH degree 3 at 48x32, o <= 0.92 (no cap), centres inside the tangent clamp."""
    return gro.scene_mixed(rng, n=16, half=0.6, s_min=0.04, size=(48, 32))[:6]


def options(args):
    """The oracle's command-line options (gro.cli_args) as Scene keywords."""
    assert len(args) % 2 == 0
    return {args[i][2:].replace("-", "_"): args[i + 1] for i in range(0, len(args), 2)}


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    work = tmp_path_factory.mktemp("grad")
    rng = np.random.default_rng(43)
    mu, log_s, q, logit, sh, cam = scene_small(rng)
    ply = str(work / "small.ply")
    write_ply(ply, mu, log_s, q, logit, sh)
    P = gro.read_params(ply, 3)  # the float32 values written are the oracle's parameters
    G = gro.upstream(rng, cam)  # float32 [H, W, 3], row 0 the top row
    args = gro.cli_args(cam, ply, "gsplat")
    with sr.Scene(**options(args)) as s:
        yield dict(work=work, ply=ply, P=P, cam=cam, G=G, args=args, scene=s, rng=rng)


def cli_grad(args, out, *more):
    if not CLI:
        pytest.skip("SPLATREF_CLI not set")
    p = subprocess.run([CLI, "grad", *args, "--out", str(out), *more], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    with np.load(out) as z:
        return {k: z[k] for k in z.files}


def same_bits(got, want):
    assert list(got) == list(want)
    for k in want:
        assert got[k].dtype == want[k].dtype and got[k].shape == want[k].shape, k
        assert got[k].tobytes() == want[k].tobytes(), "%s differs at %s" % (k, np.argwhere(got[k] != want[k])[:4].tolist())


def test_names_shapes_and_the_fd_oracle(small):
    """Under the gsplat profile, every smooth entry of means, quats, scales, opacities, sh0 and shN within the
    oracle's tolerance (gro.compare: 512 float32 ulps of the summed terms' magnitude plus the difference's error)."""
    s, cam = small["scene"], small["cam"]
    g = s.grad(dl_dimage=small["G"])
    n, H, W = len(small["P"]["o"]), cam["H"], cam["W"]
    assert list(g) == list(NAMES)
    shapes = dict(means=(n, 3), quats=(n, 4), scales=(n, 3), opacities=(n,), sh0=(n, 1, 3), shN=(n, 15, 3), means2d=(n, 2),
                  conics=(n, 3), colors=(n, 3), absgrad=(n, 2), counts=(n,))
    for k, shp in shapes.items():
        assert g[k].shape == shp and g[k].dtype == (np.int32 if k == "counts" else np.float32), (k, g[k].shape, g[k].dtype)
    assert g.means is g["means"] and g.profile == "gsplat" and g.loss is None and g.loss_value == 0
    assert g.image.shape == (H, W, 4) and (g.width, g.height, g.sh_k) == (W, H, 16)
    assert (g.counts > 0).sum() >= n - 2, g.counts  # the scene's Gaussians reach the image
    # the forward's image is render's, row 0 the top
    assert g.image.tobytes() == s.render().image.tobytes()

    fd = gro.fd_gradients(small["P"], cam, "gsplat", small["G"])
    res = gro.compare(fd, g)
    lines = []
    for nm in gro.NAMES:
        compared, not_smooth, relM, ratio, fails = res[nm]
        assert compared >= 0.9 * fd[nm].size, (nm, compared, not_smooth)
        lines += ["%s%s: Scene.grad %.9g, oracle %.9g, |d|/tol %.3g" % ((nm,) + f) for f in fails[:4]]
    assert not lines, "\n".join(lines)


def grad_option_names():
    """`splatref grad`'s name for a loss's target (--loss-target; --target before it)."""
    if not CLI:
        pytest.skip("SPLATREF_CLI not set")
    h = subprocess.run([CLI, "grad", "--help"], capture_output=True, text=True)
    return "--loss-target" if "--loss-target" in h.stdout + h.stderr else "--target"


def test_equals_the_command_lines_npz(small):
    """dl_dimage, dl_dalpha and dl_ddepth (.npy, row 0 the top) and l1 / l2 against a target image (PFM) or black:
    every array as `splatref grad` writes it, bit for bit."""
    s, cam, work, rng = small["scene"], small["cam"], small["work"], small["rng"]
    H, W = cam["H"], cam["W"]
    G = small["G"]
    da = rng.normal(size=(H, W)).astype(np.float32)
    dd = rng.normal(size=(H, W)).astype(np.float32)
    for name, a in (("G", G), ("A", da), ("D", dd)):
        np.save(str(work / (name + ".npy")), a)
    want = cli_grad(small["args"], work / "given.npz", "--dl-dimage", str(work / "G.npy"), "--dl-dalpha", str(work / "A.npy"),
                    "--dl-ddepth", str(work / "D.npy"))
    same_bits(s.grad(dl_dimage=G, dl_dalpha=da, dl_ddepth=dd), want)
    # a top-bottom asymmetric target: the image itself shifted, so every pixel's C − target is small and signed
    target = np.clip(s.render().image[:, :, :3] + rng.uniform(-0.1, 0.1, size=(H, W, 3)), 0, 1).astype(np.float32)
    target[: H // 3] = 0.9
    pfm = str(work / "target.pfm")
    sr.write_image(pfm, target)
    opt = grad_option_names()
    for loss in ("l1", "l2"):
        want = cli_grad(small["args"], work / (loss + ".npz"), "--loss", loss, opt, pfm)
        got = s.grad(loss=loss, target=target)
        same_bits(got, want)
        assert got.loss == loss
        C = got.image[:, :, :3].astype(np.float64) - target
        assert got.loss_value == pytest.approx(np.abs(C).mean() if loss == "l1" else (C * C).mean(), rel=1e-12)
        same_bits(s.grad(loss=loss), cli_grad(small["args"], work / (loss + "-black.npz"), "--loss", loss))


def test_a_loss_is_its_dl_dimage(small):
    """l2 against a target is dl_dimage = 2 (C − target) / (3WH), in double rounded once (spr_grad_desc)."""
    s, cam, rng = small["scene"], small["cam"], small["rng"]
    H, W = cam["H"], cam["W"]
    target = rng.uniform(0, 1, size=(H, W, 3)).astype(np.float32)
    a = s.grad(loss="l2", target=target)
    dl = (2.0 * (a.image[:, :, :3].astype(np.float64) - target) / (3.0 * W * H)).astype(np.float32)
    same_bits(s.grad(dl_dimage=dl), {k: v for k, v in a.items()})


def test_errors_are_one_line(small):
    s, cam = small["scene"], small["cam"]
    H, W = cam["H"], cam["W"]
    cases = [
        (dict(), "give the upstream gradient"),
        (dict(loss="l2", dl_dimage=np.zeros((H, W, 3), np.float32)), "give one"),
        (dict(loss="l3"), "'l3' is not l1 or l2"),
        (dict(dl_dimage=np.zeros((W, H, 3), np.float32)), r"dl_dimage has shape \(48, 32, 3\); the scene needs \(32, 48, 3\)"),
        (dict(dl_dimage=np.zeros((H, W, 3), np.float32), target=np.zeros((H, W, 3))), "a target goes with a loss"),
        (dict(loss="l1", dl_dalpha=np.zeros((H, W, 2))), r"dl_dalpha has shape \(32, 48, 2\); the scene needs \(32, 48\)"),
    ]
    for kw, match in cases:
        with pytest.raises(sr.Error, match=match) as e:
            s.grad(**kw)
        assert "\n" not in str(e.value)
    with sr.Scene(model=small["ply"], algo="gauss2d", size=(48, 32)) as other:
        with pytest.raises(sr.Error, match="gauss3d") as e:
            other.grad(loss="l2")
        assert "\n" not in str(e.value)
