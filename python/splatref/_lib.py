"""Loading libsplatref.so and declaring the functions of spr_ffi.h (ctypes)."""
import ctypes
import os

_HERE = os.path.dirname(os.path.abspath(__file__))


def _candidates():
    env = os.environ.get("SPLATREF_LIB")
    if env:
        yield env
    # a wheel built by python/_build carries the library beside this file
    for name in sorted(os.listdir(_HERE)):
        if name.startswith("libsplatref.so"):
            yield os.path.join(_HERE, name)
    # cmake --install: <prefix>/lib/python3/dist-packages/splatref -> <prefix>/lib
    try:
        from . import _config  # written by cmake --install
        yield os.path.join(_HERE, _config.LIBDIR_FROM_PACKAGE, "libsplatref.so")
    except ImportError:
        pass
    # the source tree: python/splatref -> build/
    yield os.path.join(_HERE, "..", "..", "build", "libsplatref.so")


def _load():
    tried = []
    for path in _candidates():
        path = os.path.normpath(path)
        if not os.path.exists(path):
            tried.append(path)
            continue
        return ctypes.CDLL(path)
    raise ImportError("splatref: libsplatref.so not found (tried %s); build it (cmake --build build) or set SPLATREF_LIB"
                      % ", ".join(tried))


lib = _load()

c_float_p = ctypes.POINTER(ctypes.c_float)
c_char_pp = ctypes.POINTER(ctypes.c_char_p)


class Arrays(ctypes.Structure):
    _fields_ = [("n", ctypes.c_size_t), ("pos", c_float_p), ("nrm", c_float_p), ("radius", c_float_p),
                ("color", c_float_p), ("alpha", c_float_p)]


def _fn(name, restype, *argtypes):
    f = getattr(lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)
    return f


_vp = ctypes.c_void_p
_int = ctypes.c_int
_ip = ctypes.POINTER(ctypes.c_int)
_szp = ctypes.POINTER(ctypes.c_size_t)
_str = ctypes.c_char_p

version = _fn("spr_ffi_version", _str)
error = _fn("spr_ffi_error", _str)
error_code = _fn("spr_ffi_error_code", _int)
free = _fn("spr_ffi_free", None, _vp)
scene_new = _fn("spr_ffi_scene_new", _vp, _int, c_char_pp, c_char_pp, ctypes.POINTER(Arrays))
scene_free = _fn("spr_ffi_scene_free", None, _vp)
scene_json = _fn("spr_ffi_scene_json", _vp, _vp)
profiles = _fn("spr_ffi_profiles", _vp)
scene_cloud = _fn("spr_ffi_scene_cloud", c_float_p, _vp, _str, _szp, _ip)
scene_rects = _fn("spr_ffi_scene_rects", c_float_p, _vp, _szp, ctypes.POINTER(ctypes.POINTER(ctypes.c_uint32)),
                  ctypes.POINTER(c_float_p), _szp)
render = _fn("spr_ffi_render", _vp, _vp, _str, _int, _int)
frame_free = _fn("spr_ffi_frame_free", None, _vp)
frame_image = _fn("spr_ffi_frame_image", c_float_p, _vp, _ip, _ip)
frame_json = _fn("spr_ffi_frame_json", _vp, _vp)
frame_plane = _fn("spr_ffi_frame_plane", c_float_p, _vp, _int, _str, _ip)
frame_records = _fn("spr_ffi_frame_records", c_float_p, _vp, _int, _szp, _ip)
check = _fn("spr_ffi_check", _vp, _vp, _vp, _int, _int, _int, _int, _str, _str, _int, _str, ctypes.c_double, _int, _int,
            ctypes.POINTER(ctypes.c_ubyte))
explain = _fn("spr_ffi_explain", _vp, _vp, _int, _int, _str, _int)
parity = _fn("spr_ffi_parity", _vp, _vp, _str, _int)
write_image = _fn("spr_ffi_write_image", _int, _str, c_float_p, _int, _int, _int)
to_u8 = _fn("spr_ffi_to_u8", ctypes.c_uint8, ctypes.c_float)
grad = _fn("spr_ffi_grad", _vp, _vp, _str, _int, _str, c_float_p, c_float_p, c_float_p, c_float_p, ctypes.c_size_t)
grads_free = _fn("spr_ffi_grads_free", None, _vp)
grads_json = _fn("spr_ffi_grads_json", _vp, _vp)
grads_array = _fn("spr_ffi_grads_array", _vp, _vp, _str, _szp)
grads_image = _fn("spr_ffi_grads_image", c_float_p, _vp, _ip, _ip)
