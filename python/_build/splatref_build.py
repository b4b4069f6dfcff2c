"""The package's own PEP 517 build backend (pyproject.toml: backend-path).

`pip install ./python` builds in an isolated environment and would fetch
setuptools from an index first; this backend needs nothing but the
standard library, so the install works offline.  The wheel holds the
Python sources and the libsplatref.so already built (SPLATREF_LIB, else
../build/libsplatref.so), so the installed package needs no source tree.
"""
import base64
import hashlib
import os
import re
import sys
import sysconfig
import zipfile

_HERE = os.path.dirname(os.path.abspath(__file__))
_ROOT = os.path.normpath(os.path.join(_HERE, ".."))
NAME = "splatref"


def _version():
    with open(os.path.join(_ROOT, "..", "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(splatref VERSION ([0-9.]+)", f.read())
    if not m:
        raise RuntimeError("splatref_build: no project(splatref VERSION ...) in CMakeLists.txt")
    return m.group(1)


def _library():
    path = os.environ.get("SPLATREF_LIB") or os.path.join(_ROOT, "..", "build", "libsplatref.so")
    path = os.path.realpath(path)
    if not os.path.isfile(path):
        raise RuntimeError("splatref_build: %s not found: build the library first (cmake -S . -B build && cmake --build build) "
                           "or set SPLATREF_LIB" % path)
    return path


def _tag():
    plat = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return "py3-none-" + plat


def _metadata(version):
    return ("Metadata-Version: 2.1\nName: %s\nVersion: %s\nSummary: the splatref reference renderer from Python (numpy in and out)\n"
            "Requires-Python: >=3.9\nRequires-Dist: numpy\nLicense: see the splatref repository\n" % (NAME, version))


def _wheel_meta():
    return "Wheel-Version: 1.0\nGenerator: splatref_build\nRoot-Is-Purelib: false\nTag: %s\n" % _tag()


def get_requires_for_build_wheel(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    version = _version()
    d = os.path.join(metadata_directory, "%s-%s.dist-info" % (NAME, version))
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "METADATA"), "w", encoding="utf-8") as f:
        f.write(_metadata(version))
    with open(os.path.join(d, "WHEEL"), "w", encoding="utf-8") as f:
        f.write(_wheel_meta())
    return os.path.basename(d)


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    version = _version()
    files = []  # (name in the wheel, bytes)
    pkg = os.path.join(_ROOT, NAME)
    for name in sorted(os.listdir(pkg)):
        if name.endswith(".py") and name != "_config.py":
            with open(os.path.join(pkg, name), "rb") as f:
                files.append(("%s/%s" % (NAME, name), f.read()))
    with open(_library(), "rb") as f:
        files.append(("%s/libsplatref.so" % NAME, f.read()))
    info = "%s-%s.dist-info" % (NAME, version)
    files.append((info + "/METADATA", _metadata(version).encode()))
    files.append((info + "/WHEEL", _wheel_meta().encode()))
    record = []
    for name, data in files:
        digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
        record.append("%s,sha256=%s,%d" % (name, digest, len(data)))
    record.append(info + "/RECORD,,")
    files.append((info + "/RECORD", ("\n".join(record) + "\n").encode()))
    whl = "%s-%s-%s.whl" % (NAME, version, _tag())
    tmp = os.path.join(wheel_directory, whl + ".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in files:
            zi = zipfile.ZipInfo(name, date_time=(2020, 1, 1, 0, 0, 0))
            zi.external_attr = (0o755 if name.endswith(".so") else 0o644) << 16
            zi.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(zi, data)
    os.replace(tmp, os.path.join(wheel_directory, whl))
    return whl
