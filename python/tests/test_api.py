"""The Python interface against the command line and the library (CTest: python)."""
import json
import math
import os
import subprocess

import numpy as np
import pytest
import splatref as sr

CLI = os.environ.get("SPLATREF_CLI")
SCENE = dict(model="builtin:torus", points=5000, size=(80, 64), algo="deferred", voronoi=True, groups="mgc")


def cli(*args, cwd=None):
    if not CLI:
        pytest.skip("SPLATREF_CLI not set")
    return subprocess.run([CLI, *args], cwd=cwd, capture_output=True, text=True)


def scene_args():
    """SCENE as command-line options."""
    opts = []
    for k, v in SCENE.items():
        opts += ["--" + k.replace("_", "-")] + ([] if v is True else [sr._fmt(k, v)])
    return opts


@pytest.fixture(scope="module")
def scene():
    with sr.Scene(**SCENE) as s:
        yield s


def test_the_reference_passes_itself(scene):
    img = scene.render().image[:, :, :3].copy()
    r = sr.check(img, scene)
    assert r and r.report["differing_pixels"] == 0 and r.failing == []


def test_one_lsb_fails_naming_the_pixel_and_passes_tier_b(scene):
    img = sr.to_u8(scene.render().image[:, :, :3])
    row, col = 20, 33
    img[row, col, 2] = img[row, col, 2] + 1 if img[row, col, 2] < 255 else 254
    r = sr.check(img, scene)
    assert not r
    y = scene.height - 1 - row
    assert r.failing == [(col, y)]
    f = r.report["first_failing"]
    assert (f["x"], f["y"], f["row_from_top"], f["channel"]) == (col, y, row, 2)
    assert r.state[row, col] == 3 and int((r.state != 0).sum()) == 1
    b = sr.check(img, scene, tier="B", lsb=1)
    assert b and b.report["failing_pixels"] == 0 and b.report["differing_pixels"] == 1 and b.state[row, col] == 1


def test_check_equals_the_command_line(scene, tmp_path):
    img = scene.render().image[:, :, :3].copy()
    img[5, 7, 1] = min(1.0, img[5, 7, 1] + 2.5 / 255)  # two or three LSB off once in 8 bits
    png = str(tmp_path / "theirs.png")
    sr.write_image(png, img)
    opts = scene_args()
    for tier in ([], ["--tier", "B", "--lsb", "1"], ["--tier", "B", "--lsb", "3"]):
        out = tmp_path / ("report" + "".join(tier))
        p = cli("check", *opts, "--image", png, "--out", str(out), "--quiet", *tier)
        assert p.returncode in (0, 1), p.stderr
        want = json.load(open(out / "report.json"))
        u8 = sr.to_u8(img)  # what the PNG holds, row 0 at the top
        kw = {} if not tier else dict(tier="B", lsb=int(tier[3]))
        got = sr.check(u8, scene, label=png, **kw).report
        for k in ("heatmap", "side_by_side"):
            want.pop(k)
        first = want.get("first_failing") or want.get("first_differing")
        if first:
            first.pop("explain", None)
        assert got == want
        assert (p.returncode == 0) == (got["verdict"] == "pass")


def test_render_equals_the_command_lines_float_image(scene, tmp_path):
    opts = scene_args()
    pfm = tmp_path / "a.pfm"
    p = cli("render", *opts, "--float", str(pfm), "--out", str(tmp_path / "a.png"), "--quiet")
    assert p.returncode == 0, p.stderr
    raw = open(pfm, "rb").read()
    # PFM: "PF\nW H\n-1.0\n" then bottom-first RGB floats, little-endian
    head = raw.split(b"\n", 3)
    data = np.frombuffer(head[3], dtype="<f4").reshape(scene.height, scene.width, 3)[::-1]
    img = scene.render().image[:, :, :3]
    assert data.tobytes() == np.ascontiguousarray(img).tobytes()


def test_every_plane_of_every_pass(scene):
    f = scene.render(passes=True)
    assert len(f.passes) > 3
    for i, p in enumerate(f.passes):
        for name in p["planes"]:
            a = f.plane(i, name)
            assert a.shape[:2] == (scene.height, scene.width) and a.dtype == np.float32
    with pytest.raises(sr.Error, match="has no plane"):
        f.plane(0, "transmittance")
    # the last pass's colour is the final image (the normalisation writes it)
    last = [i for i, p in enumerate(f.passes) if "color" in p["planes"]][-1]
    assert np.array_equal(f.plane(last, "color")[:, :, :3], f.image[:, :, :3])


def test_explain_equals_the_command_line(scene):
    x, y = 40, 30
    got = sr.explain(scene, x, y, backend="cpu")
    opts = scene_args()
    p = cli("explain", *opts, "--pixel", "%d,%d" % (x, y), "--backend", "cpu", "--json", "--quiet")
    assert p.returncode == 0, p.stderr
    assert got == json.loads(p.stdout)
    assert got["pixel"] == [x, y] and got["cpu"]["passes"]


def test_parity_is_bit_exact(scene):
    try:
        rep = sr.parity(scene)
    except sr.NoDevice as e:
        pytest.skip(str(e))
    assert [a["algo"] for a in rep["algorithms"]] == ["deferred"]
    assert rep["algorithms"][0]["bit_exact"], rep


def test_a_cloud_of_arrays_renders_as_its_file():
    c = sr.load("builtin:sphere", points=3000)
    assert len(c) == 3000 and c.pos.shape == (3000, 3) and c.radius.shape == (3000,)
    with sr.Scene(model="builtin:sphere", points=3000, size=(64, 64), algo="zbuffer") as a, \
            sr.Scene(c, size=(64, 64), algo="zbuffer") as b:
        assert b.info["model"] == "arrays"
        assert a.render().image.tobytes() == b.render().image.tobytes()


@pytest.mark.parametrize("bad,match", [
    (dict(radius=-1.0), "radius"),
    (dict(radius=float("nan")), "radius"),
    (dict(pos=float("inf")), "arrays"),
    (dict(nrm=0.0), "normal"),
])
def test_bad_arrays_are_one_line_errors(bad, match):
    n = 10
    arr = dict(pos=np.random.default_rng(1).random((n, 3)), nrm=np.tile([0.0, 0.0, 1.0], (n, 1)), radius=np.full(n, 0.1))
    for k, v in bad.items():
        arr[k] = arr[k].copy()
        arr[k][3] = v
    with pytest.raises(sr.Error, match=match) as e:
        sr.Scene(sr.Cloud(**arr))
    assert "\n" not in str(e.value) and "arrays" in str(e.value)


def test_errors_carry_the_librarys_message():
    with pytest.raises(sr.Error, match="unknown option 'sparkle'"):
        sr.Scene(sparkle=1)
    with pytest.raises(sr.Error, match="/nonexistent.ply") as e:
        sr.Scene(model="/nonexistent.ply")
    assert e.value.code == -1  # SPR_E_IO, the reader's code
    with pytest.raises(sr.Error, match="--fov"):
        sr.Scene(fov=500)
    with pytest.raises(sr.Error, match="is not A, B or C"):
        sr.check(np.zeros((64, 80, 3), np.uint8), sr.Scene(model="builtin:torus", points=500, size=(80, 64)), tier="D")
    with pytest.raises(sr.Error, match="80x64"):
        sr.check(np.zeros((10, 10, 3), np.uint8), sr.Scene(model="builtin:torus", points=500, size=(80, 64)))


def test_to_u8_is_the_librarys():
    rng = np.random.default_rng(7)
    v = np.concatenate([rng.random(20000, dtype=np.float32) * np.float32(1.2) - np.float32(0.1),
                        np.array([0.5 / 255, 1.5 / 255, 254.5 / 255, -0.0, 1.0, np.nan, np.inf, -np.inf], np.float32),
                        (np.arange(256, dtype=np.float32) + np.float32(0.5)) / np.float32(255)]).astype(np.float32)
    want = np.array([sr._lib.to_u8(float(x)) for x in v], dtype=np.uint8)
    assert np.array_equal(sr.to_u8(v), want)


def test_a_png_chunk_longer_than_its_file_is_one_line(tmp_path):
    """The fuzzer's finding (tests/fuzz/corpus/image/finding_chunk_length_1_6gb): a tEXt length of
    1.66e9 bytes in a 300-byte file made libpng allocate 1.6 GB before reading it."""
    src = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "fuzz", "corpus", "image", "finding_chunk_length_1_6gb")
    png = tmp_path / "long-chunk.png"
    png.write_bytes(open(src, "rb").read()[1:])  # its first byte chose PNG
    p = cli("compare", str(png), str(png))
    assert p.returncode == 2
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and str(png) in lines[0] and "byte 33: chunk 'tEXt' of 1660944441 bytes runs past the end" in lines[0], p.stderr


def test_domain_primitives_of_the_octahedron():
    # builtin:octahedron is |x|+|y|+|z| = 1 with one colour per face (core/io/builtin.c); its level 2 has one
    # region per face (docs/domains.md): eight rectangles, each in its face's plane, normal (±1,±1,±1)/√3.
    s = sr.Scene(model="builtin:octahedron", algo="domain-noblend", size=(64, 64), level=2)
    info = s.info["primitives"]
    assert (info["level"], info["regions"], info["polygons"]) == (2, 8, 8)
    p = s.primitives()
    assert len(p) == 8 and sorted(p.domain) == list(range(8))
    face_colours = {tuple(np.round(c, 6)) for c in s.cloud().color}
    assert len(face_colours) == 8
    for k in range(8):
        n = p.normal[k]
        assert np.allclose(np.abs(n), 1 / math.sqrt(3), atol=1e-3), n
        t = p.texture(k)
        tw, th = p.size[k]
        assert t.shape == (th, tw, 4) and t[:, :, 3].min() >= 0 and t[:, :, 3].max() <= 1 + 1e-6
        # interior texels (alpha = the basis function near 1) lie on the face and carry its colour; row 0 is vmax
        rows, cols = np.nonzero(t[:, :, 3] > 0.99)
        assert len(rows) > 100
        umin, umax, vmin, vmax = p.extent[k]
        h = p.texel[k]
        su = umin + (cols + 0.5) * h
        sv = vmin + (th - 1 - rows + 0.5) * h
        x = p.centre[k] + su[:, None] * p.u[k] + sv[:, None] * p.v[k]
        # on the face's plane, and inside its triangle up to the splats' reach past its edges (a texel or two)
        assert np.allclose(x @ np.sign(n), 1.0, atol=2e-3)
        assert (x * np.sign(n)).min() > -2 * h, "texels off the face: the texture's rows are flipped"

        inner = (x * np.sign(n)).min(axis=1) > 3 * h  # beyond the reach of the next face's splats
        colours = {tuple(np.round(c, 6)) for c in t[rows[inner], cols[inner], :3]}
        assert len(colours) == 1 and colours <= face_colours, colours
    with pytest.raises(sr.Error, match="draws no domain primitives"):
        sr.Scene(**SCENE).primitives()


@pytest.mark.parametrize("driver", ["zink", "llvmpipe"])
def test_a_scene_names_its_gl_driver(driver):
    """gl_driver is a scene key: parity and render run on that driver, one after the other in one process."""
    with sr.Scene(model="builtin:torus", points=2000, size=(48, 40), algo="depthpeel", gl_driver=driver) as s:
        try:
            p = s.parity()
        except sr.NoDevice as e:
            if os.environ.get("SPLATREF_REQUIRE_GL", "0") not in ("", "0"):
                raise
            pytest.skip(str(e))
        assert p["gl_renderer"].startswith(driver + " ("), p["gl_renderer"]
        a = p["algorithms"][0]
        assert a["bit_exact"] and a["stats_mismatches"] == 0, a["first_stats_mismatch"]
        assert s.render(backend="gl").renderer.startswith("gl [" + driver + " (")


def test_an_unknown_gl_driver_is_one_line():
    with pytest.raises(sr.Error, match=r"--gl-driver: 'swiftshader' is not a GL driver here \(default \| llvmpipe \| zink\)"):
        sr.Scene(model="builtin:torus", points=500, gl_driver="swiftshader")


def test_profiles_are_the_clis_table():
    """splatref.profiles() is the table `splatref profiles --json` prints; a scene takes any of its names."""
    names = [p["name"] for p in sr.profiles()]
    assert "inria" in names and "spark" in names and len(names) == len(set(names))
    r = cli("profiles", "--json")
    assert r.returncode == 0, r.stderr
    assert [p["name"] for p in json.loads(r.stdout)] == names
    cap = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "data", "captures", "splat-transform", "2.7.1", "sheet.ply")
    for p in sr.profiles():
        with sr.Scene(model=cap, size=(40, 32), eye=(0.9, 0.7, 2.4), target=(0, 0, 0), gauss_profile=p["name"]) as s:
            assert s.info["algo"] == p["algo"], (p["name"], s.info)
            img = s.render().image
            assert img.shape[:2] == (32, 40) and float(img[..., :3].max()) > 0.0
    with pytest.raises(sr.Error, match="not a profile .*inria, gsplat"):
        sr.Scene(model=cap, gauss_profile="unity")
    with pytest.raises(sr.Error, match="belongs to --algo gauss-blend"):
        sr.Scene(model=cap, gauss_profile="spark", algo="gauss3d")
