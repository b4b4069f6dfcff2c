"""splatref from Python: the reference renderer of deferred-blending splats,
domain primitives and Gaussian splatting, with numpy arrays in and out.

    import splatref as sr
    scene = sr.Scene(model="builtin:torus", algo="deferred", size=(256, 256))
    frame = scene.render()                 # the CPU reference; backend="gl" for the GL backend
    frame.image                            # (256, 256, 4) float32, row 0 = top
    frame.plane(0, "depth")                # any plane of any pass (render(passes=True))
    result = sr.check(my_image, scene)     # the verdict and the failing pixels
    assert result, result.summary()
    g = sr.Scene(model="cap.ply", algo="gauss3d", gauss_profile="gsplat").grad(loss="l2", target=img)
    g["means"], g.opacities, g.counts      # gauss3d's gradients, gsplat's names and shapes (`splatref grad`)

Every option is a scene-file key or an option of `splatref render`, by its
command-line name with '_' for '-' (radius_scale=0.5), values as the
command line takes them (numbers, tuples for X,Y,Z, True for a flag).

Arrays handed out are indexed [row, column] with row 0 the top of the
image, as a PNG file is and as matplotlib shows it.  Pixel coordinates in
reports (check's first failing pixel, explain's pixel) are the library's:
x from the left, y from the bottom (GL's convention, the command line's);
Python's row is height - 1 - y.
"""
import ctypes
import json

import numpy as np

from . import _lib

__all__ = ["Error", "NoDevice", "Cloud", "Scene", "Frame", "Primitives", "CheckResult", "Grads", "load", "render", "check", "explain",
           "parity", "grad", "write_image", "to_u8", "__version__"]

__version__ = _lib.version().decode()

_NO_DEVICE = -9


class Error(Exception):
    """A failure of the library: its one-line message, and code (spr_result)."""

    def __init__(self, message, code=-7):
        super().__init__(message)
        self.code = code


class NoDevice(Error):
    """The GL backend has no device here (no EGL display or context)."""


def _raise():
    msg = _lib.error().decode(errors="replace")
    code = _lib.error_code()
    raise (NoDevice if code == _NO_DEVICE else Error)(msg, code)


def _take_json(ptr):
    """A JSON string the library returned, parsed, then freed."""
    if not ptr:
        _raise()
    try:
        return json.loads(ctypes.string_at(ptr).decode())
    finally:
        _lib.free(ptr)


def profiles():
    """The Gaussian renderer profiles (SPEC 10.9), the table the CLI's --gauss-profile and scene files read: a list
    of dicts (name, algo, renderer, version, source, rules), in the table's order.  Scene(gauss_profile=NAME)
    takes a name."""
    return _take_json(_lib.profiles())


def _fmt(key, v):
    if isinstance(v, bool):
        return "1" if v else None
    if key == "size" and isinstance(v, (tuple, list)):
        return "%dx%d" % (int(v[0]), int(v[1]))
    if isinstance(v, (tuple, list, np.ndarray)):
        return ",".join(_fmt(key, x) for x in np.asarray(v).ravel().tolist())
    if isinstance(v, float):
        return repr(v)  # the shortest text that reads back as the same double
    return str(v)


def _f32(a, comps, name, n=None):
    a = np.ascontiguousarray(a, dtype=np.float32)
    if comps > 1:
        a = a.reshape(-1, comps)
    else:
        a = a.reshape(-1)
    if n is not None and a.shape[0] != n:
        raise Error("%s: %d rows, pos has %d" % (name, a.shape[0], n))
    return a


class Cloud:
    """A cloud as arrays: pos (n,3), nrm (n,3), radius (n,), color (n,3) in
    [0,1] or None (colours by normal, as a file without colours), alpha
    (n,) or None (1).  Checked as a loaded file is when a Scene takes it."""

    def __init__(self, pos, nrm, radius, color=None, alpha=None):
        self.pos = _f32(pos, 3, "pos")
        n = self.pos.shape[0]
        self.nrm = _f32(nrm, 3, "nrm", n)
        self.radius = _f32(radius, 1, "radius", n)
        self.color = None if color is None else _f32(color, 3, "color", n)
        self.alpha = None if alpha is None else _f32(alpha, 1, "alpha", n)

    def __len__(self):
        return self.pos.shape[0]

    def _struct(self):
        p = lambda a: None if a is None else a.ctypes.data_as(_lib.c_float_p)
        return _lib.Arrays(len(self), p(self.pos), p(self.nrm), p(self.radius), p(self.color), p(self.alpha))


def load(model, **options):
    """Load a model file (or builtin:NAME) as the command line does (radius
    rule, --opacity, ...) and return its Cloud (centres, normals, radii,
    colours, opacities; a Gaussian capture's own Gaussians are not kept:
    give Scene(model=...) for those)."""
    s = Scene(model=model, quiet=True, **options)
    try:
        return s.cloud()
    finally:
        s.close()


class Scene:
    """A scene: the model (or a Cloud), the camera, the algorithm and its
    options, loaded, framed and grouped as `splatref render` does.
    scene="S.json" reads a scene file; the other options override it."""

    def __init__(self, cloud=None, **options):
        options.setdefault("quiet", True)
        keys, vals = [], []
        for k, v in options.items():
            t = _fmt(k, v)
            if t is None:
                continue
            keys.append(k.encode())
            vals.append(t.encode())
        ka = (ctypes.c_char_p * max(1, len(keys)))(*keys)
        va = (ctypes.c_char_p * max(1, len(vals)))(*vals)
        arr = None
        if cloud is not None:
            if not isinstance(cloud, Cloud):
                raise Error("cloud: a splatref.Cloud (or give model=PATH)")
            self._cloud = cloud  # kept alive while the library copies it
            arr = ctypes.byref(cloud._struct())
        self._h = _lib.scene_new(len(keys), ka, va, arr)
        if not self._h:
            _raise()
        self.info = _take_json(_lib.scene_json(self._h))
        self.width, self.height, self.algo = self.info["width"], self.info["height"], self.info["algo"]

    def close(self):
        if getattr(self, "_h", None):
            _lib.scene_free(self._h)
            self._h = None

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _handle(self):
        if not self._h:
            raise Error("the scene is closed")
        return self._h

    def cloud(self):
        """The loaded cloud as a Cloud of copies."""
        out = {}
        for f in ("pos", "nrm", "radius", "color", "alpha"):
            n, comps = ctypes.c_size_t(), ctypes.c_int()
            p = _lib.scene_cloud(self._handle(), f.encode(), ctypes.byref(n), ctypes.byref(comps))
            if not p:
                _raise()
            a = np.ctypeslib.as_array(p, shape=(n.value * comps.value,)).copy()
            out[f] = a.reshape(n.value, comps.value) if comps.value > 1 else a
        return Cloud(**out)

    def primitives(self):
        """The domain primitives a domain-* scene draws (SPEC §7.4, §7.5),
        as a Primitives of copies; info["primitives"] has the level's figures."""
        n, ntex = ctypes.c_size_t(), ctypes.c_size_t()
        ints = ctypes.POINTER(ctypes.c_uint32)()
        tex = _lib.c_float_p()
        f = _lib.scene_rects(self._handle(), ctypes.byref(n), ctypes.byref(ints), ctypes.byref(tex), ctypes.byref(ntex))
        if not f:
            _raise()
        return Primitives(np.ctypeslib.as_array(f, shape=(n.value * 17,)).reshape(n.value, 17).copy(),
                          np.ctypeslib.as_array(ints, shape=(n.value * 4,)).reshape(n.value, 4).copy(),
                          np.ctypeslib.as_array(tex, shape=(ntex.value * 4,)).reshape(ntex.value, 4).copy()
                          if ntex.value else np.zeros((0, 4), np.float32))

    def render(self, backend="cpu", passes=False, gl_device=-1):
        """Render on "cpu" (the reference) or "gl"; passes=True keeps every
        plane of every pass (Frame.plane)."""
        f = _lib.render(self._handle(), backend.encode(), gl_device, 1 if passes else 0)
        if not f:
            _raise()
        return Frame(f)

    def check(self, image, **kw):
        return check(image, self, **kw)

    def explain(self, x, y, backend="both", gl_device=-1):
        return explain(self, x, y, backend, gl_device)

    def parity(self, algo=None, gl_device=-1):
        return parity(self, algo, gl_device)

    def grad(self, dl_dimage=None, loss=None, target=None, dl_dalpha=None, dl_ddepth=None, backend="cpu", gl_device=-1, batch=0):
        """The gradients of the scene's gauss3d frame (SPEC 10.10, docs/gradients.md), as `splatref grad` computes
        them, for an upstream gradient: dl_dimage, dL/dC as an (H, W, 3) float32 image, or loss="l1" | "l2", the
        mean over pixels and channels of |C - target| or (C - target)^2, against target ((H, W, 3) or (H, W, 4),
        float or uint8; None: black).  dl_dalpha, dl_ddepth: (H, W) or None, dL/d(alpha) for the alpha 1 - T and
        dL/d(inverse depth).  Images are row 0 = top, as trainers hold them.  Returns a Grads: a dict of gsplat's
        names and shapes (means (N, 3), quats (N, 4), scales (N, 3), opacities (N,), sh0 (N, 1, 3),
        shN (N, K-1, 3), means2d (N, 2), conics (N, 3), colors (N, 3), absgrad (N, 2), counts (N,) int32),
        the forward's image and the loss.  batch: grad's --grad-batch (0: the backend's own)."""
        return grad(self, dl_dimage, loss, target, dl_dalpha, dl_ddepth, backend, gl_device, batch)


class Primitives:
    """Domain primitives ([R]; SPEC §7.4, §7.5): rectangle k is
    {centre + s*u + t*v : extent[k] = (umin, umax, vmin, vmax)} in the
    plane through centre[k] with normal[k], covered by a texture of
    size[k] = (tw, th) square texels of side texel[k]; domain[k] is its
    region of the decomposition.  Arrays (n, 3), (n, 4), (n,), (n, 2), (n,)."""

    def __init__(self, f, i, texels):
        self.centre, self.normal, self.u, self.v = f[:, 0:3], f[:, 3:6], f[:, 6:9], f[:, 9:12]
        self.extent, self.texel = f[:, 12:16], f[:, 16]
        self.size, self.domain = i[:, 0:2].astype(np.int64), i[:, 3].astype(np.int64)
        self._first, self._texels = i[:, 2].astype(np.int64), texels

    def __len__(self):
        return len(self.centre)

    def texture(self, k):
        """Rectangle k's texture, (th, tw, 4) float32: colour and alpha (the
        basis function), row 0 = the top (v = vmax), as an image shows it."""
        tw, th = self.size[k]
        t = self._texels[self._first[k]:self._first[k] + tw * th].reshape(th, tw, 4)
        return np.ascontiguousarray(t[::-1])

    def corners(self, k):
        """Rectangle k's corners in world space, (4, 3): (umin, vmin),
        (umax, vmin), (umax, vmax), (umin, vmax)."""
        umin, umax, vmin, vmax = (float(x) for x in self.extent[k])
        c, u, v = (a[k].astype(np.float64) for a in (self.centre, self.u, self.v))
        return np.array([c + s * u + t * v for s, t in ((umin, vmin), (umax, vmin), (umax, vmax), (umin, vmax))])


def _top_first(a, h, w, ch):
    a = a.reshape(h, w, ch)[::-1]
    return np.ascontiguousarray(a[:, :, 0] if ch == 1 else a)


class Frame:
    """A rendered frame: image (H, W, 4) float32, passes (what each pass
    was), plane(i, name) for the kept passes.  Arrays are copies, row 0 = top."""

    def __init__(self, handle):
        self._h = handle
        try:
            w, h = ctypes.c_int(), ctypes.c_int()
            p = _lib.frame_image(handle, ctypes.byref(w), ctypes.byref(h))
            self.width, self.height = w.value, h.value
            self.image = _top_first(np.ctypeslib.as_array(p, shape=(w.value * h.value * 4,)), h.value, w.value, 4)
            meta = _take_json(_lib.frame_json(handle))
            self.backend, self.renderer = meta["backend"], meta["renderer"]
            self.K, self.eps_t, self.passes = meta["K"], meta["eps_t"], meta["passes"]
        except Exception:
            self.close()
            raise

    def close(self):
        if getattr(self, "_h", None):
            _lib.frame_free(self._h)
            self._h = None

    def __del__(self):
        self.close()

    def plane(self, i, name):
        """Plane `name` (color, depth, test, id, count, opacity, normal,
        transmittance, ...) after the i-th kept pass: (H, W) or (H, W, ch)
        float32, ids and counts as floats (none = -1)."""
        if not self._h:
            raise Error("the frame is closed")
        ch = ctypes.c_int()
        p = _lib.frame_plane(self._h, int(i), name.encode(), ctypes.byref(ch))
        if not p:
            _raise()
        n = self.width * self.height * ch.value
        return _top_first(np.ctypeslib.as_array(p, shape=(n,)), self.height, self.width, ch.value)

    def records(self, i):
        """A Gaussian preprocessing pass's records: (rows, fields) float32."""
        rows, cols = ctypes.c_size_t(), ctypes.c_int()
        p = _lib.frame_records(self._h, int(i), ctypes.byref(rows), ctypes.byref(cols))
        if not p:
            _raise()
        return np.ctypeslib.as_array(p, shape=(rows.value * cols.value,)).reshape(rows.value, cols.value).copy()


class Grads(dict):
    """Scene.grad's result: a dict of the gradient arrays by gsplat's names (also attributes: g.means), in SPEC
    10.10's order, as `splatref grad`'s .npz holds them (np.savez(path, **g) writes the same members); and
    image (H, W, 4) float32, row 0 = top, the forward's frame; loss ("l1", "l2" or None for a given dl_dimage),
    loss_value (the loss, 0 for a given gradient), profile, backend, renderer, sh_k, width, height, ms_forward,
    ms_backward."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __repr__(self):
        return "Grads(%s, %d Gaussians, %s)" % (self.profile, len(self["means"]), ", ".join(
            "%s %s" % (k, "x".join(str(d) for d in v.shape)) for k, v in self.items()))


def _image_in(a, h, w, chans, name, u8=False):
    """An (H, W, ch) or (H, W) image, row 0 = top, as the library's float32, row 0 = bottom (None stays None)."""
    if a is None:
        return None
    a = np.asarray(a)
    if u8 and a.dtype == np.uint8:
        a = a.astype(np.float32) / np.float32(255)  # as the PNG reader: v / 255, correctly rounded
    elif a.dtype.kind not in "fiu":
        raise Error("grad: %s: an array of numbers (this one is %s)" % (name, a.dtype))
    want = "(%d, %d%s)" % (h, w, "" if chans == (1,) else ", " + " or ".join(str(c) for c in chans))
    ok = a.shape[:2] == (h, w) and ((a.ndim == 2 and 1 in chans) or (a.ndim == 3 and a.shape[2] in chans))
    if not ok:
        raise Error("grad: %s has shape %s; the scene needs %s (row 0 the top row)" % (name, tuple(a.shape), want))
    if a.ndim == 3:
        a = a[:, :, :3]
    return np.ascontiguousarray(a[::-1], dtype=np.float32)


def grad(scene, dl_dimage=None, loss=None, target=None, dl_dalpha=None, dl_ddepth=None, backend="cpu", gl_device=-1, batch=0):
    """Scene.grad (which see)."""
    h, w = scene.height, scene.width
    ins = [_image_in(target, h, w, (3, 4), "target", u8=True), _image_in(dl_dimage, h, w, (3,), "dl_dimage"),
           _image_in(dl_dalpha, h, w, (1,), "dl_dalpha"), _image_in(dl_ddepth, h, w, (1,), "dl_ddepth")]
    ptr = [None if a is None else a.ctypes.data_as(_lib.c_float_p) for a in ins]
    g = _lib.grad(scene._handle(), backend.encode(), int(gl_device), None if loss is None else str(loss).encode(), ptr[0], ptr[1], ptr[2],
                  ptr[3], int(batch))
    if not g:
        _raise()
    try:
        meta = _take_json(_lib.grads_json(g))
        out = Grads()
        for a in meta.pop("arrays"):
            count = ctypes.c_size_t()
            p = _lib.grads_array(g, a["name"].encode(), ctypes.byref(count))
            if not p:
                _raise()
            ct = ctypes.c_int32 if a["dtype"] == "int32" else ctypes.c_float
            v = np.ctypeslib.as_array(ctypes.cast(p, ctypes.POINTER(ct)), shape=(count.value,)) if count.value else np.zeros(0, ct)
            out[a["name"]] = v.reshape(a["shape"]).astype(np.dtype(a["dtype"]), copy=True)
        wi, hi = ctypes.c_int(), ctypes.c_int()
        p = _lib.grads_image(g, ctypes.byref(wi), ctypes.byref(hi))
        out.image = _top_first(np.ctypeslib.as_array(p, shape=(wi.value * hi.value * 4,)), hi.value, wi.value, 4)
        for k, v in meta.items():
            setattr(out, k, v)
        return out
    finally:
        _lib.grads_free(g)


def render(scene, backend="cpu", passes=False, gl_device=-1):
    return scene.render(backend, passes, gl_device)


class CheckResult:
    """check()'s verdict: passed (also its truth value), report (the keys of
    `splatref check`'s report.json), state (H, W) uint8 per pixel — 0 equal,
    1 within the tier's bounds, 2 passing only within one pixel, 3 failing —
    and failing, the failing pixels as (x, y) with y from the bottom."""

    def __init__(self, report, state):
        self.report = report
        self.passed = report["verdict"] != "fail"
        self.state = state
        rows, cols = np.nonzero(state == 3)
        h = state.shape[0]
        order = np.lexsort((cols, h - 1 - rows))  # by y from the bottom, then x: the library's scan order
        self.failing = [(int(cols[k]), int(h - 1 - rows[k])) for k in order]

    def __bool__(self):
        return self.passed

    def summary(self):
        r = self.report
        s = "Tier %s: %d of %d pixels differ, %d fail" % (r["tier"], r["differing_pixels"], r["pixels"], r["failing_pixels"])
        f = r.get("first_failing") or r.get("first_differing")
        if f:
            s += "; first %s pixel x %d, y %d (row %d from the top), channel %d: reference %.9g, image %.9g" % (
                "failing" if "first_failing" in r else "differing", f["x"], f["y"], f["row_from_top"], f["channel"], f["reference"],
                f["image"])
        return s + "; verdict " + r["verdict"]

    def __repr__(self):
        return "CheckResult(%s)" % self.summary()


def check(image, scene, tier=None, ulp=None, lsb=None, position=False, plane=None, pass_=None, label="image"):
    """An image (H, W, ch) or (H, W), row 0 = top, of uint8, uint16 or
    float32 values, against the scene's reference plane (plane None: the
    final colour, RGB) under PARITY.md's tiers, as `splatref check` does."""
    a = np.asarray(image)
    if a.dtype == np.uint8:
        bits = 8
    elif a.dtype == np.uint16:
        bits = 16
    elif a.dtype == np.float32:
        bits = 32
    else:
        raise Error("check: an image of uint8, uint16 or float32 values (this one is %s)" % a.dtype)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3:
        raise Error("check: an image of shape (H, W) or (H, W, channels)")
    h, w, ch = a.shape
    bottom_first = np.ascontiguousarray(a[::-1])
    state = np.zeros((h, w), dtype=np.uint8)
    ptr = _lib.check(scene._handle(), bottom_first.ctypes.data_as(ctypes.c_void_p), w, h, ch, bits, label.encode(),
                     None if plane is None else plane.encode(), -1 if pass_ is None else int(pass_),
                     None if tier is None else str(tier).encode(), -1.0 if ulp is None else float(ulp), -1 if lsb is None else int(lsb),
                     1 if position else 0, state.ctypes.data_as(ctypes.POINTER(ctypes.c_ubyte)))
    report = _take_json(ptr)
    return CheckResult(report, np.ascontiguousarray(state[::-1]))


def explain(scene, x, y, backend="both", gl_device=-1):
    """The history of pixel (x, y), y from the bottom, as `splatref explain
    --json` gives it: every pass, every fragment, every plane after each."""
    return _take_json(_lib.explain(scene._handle(), int(x), int(y), backend.encode(), gl_device))


def parity(scene, algo=None, gl_device=-1):
    """The CPU reference against the GL backend, every plane of every pass,
    as `splatref parity --report`'s report.json (algo "all": every one)."""
    return _take_json(_lib.parity(scene._handle(), None if algo is None else algo.encode(), gl_device))


def write_image(path, image):
    """Save (H, W, ch) float values, row 0 = top, as .png (8-bit) or .pfm."""
    a = np.asarray(image, dtype=np.float32)
    if a.ndim == 2:
        a = a[:, :, None]
    h, w, ch = a.shape
    b = np.ascontiguousarray(a[::-1])
    if _lib.write_image(path.encode() if isinstance(path, str) else path, b.ctypes.data_as(_lib.c_float_p), w, h, ch):
        _raise()


def to_u8(image):
    """8-bit values of a float image as PNG files hold them (PARITY rule 8:
    clamp to [0,1], times 255, round to nearest even)."""
    a = np.asarray(image, dtype=np.float32)
    c = np.nan_to_num(np.clip(a, np.float32(0), np.float32(1)), nan=0.0)
    return np.rint(c * np.float32(255)).astype(np.uint8)
