#!/usr/bin/python3
"""make_npy.py — the .npy/.npz files that tests/test_npy.c reads, written by numpy itself (issue 43).

Run from anywhere with Debian's python3-numpy: /usr/bin/python3 tests/data/npy/make_npy.py
Every value is arange-based, so the test recomputes it without reading any file back through our writer.
"""
import os
import zipfile

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))


def out(name):
    return os.path.join(here, name)


# float32 [H, W, 3] image: value (y*W + x)*3 + c, scaled by 0.25
np.save(out("img_f4.npy"), (np.arange(4 * 5 * 3, dtype=np.float32) * 0.25).reshape(4, 5, 3))
# float64 [2, 3]: i / 3 + 1e-9 (not representable in float32: the reader rounds once to nearest)
np.save(out("f8.npy"), np.arange(6, dtype=np.float64).reshape(2, 3) / 3.0 + 1e-9)
# big-endian float32 [7]: -1.5 + i * 0.75
np.save(out("be_f4.npy"), (np.arange(7, dtype=np.float32) * 0.75 - 1.5).astype(">f4"))
# big-endian float64 [3]: 1 / (i + 1)
np.save(out("be_f8.npy"), (1.0 / (np.arange(3, dtype=np.float64) + 1.0)).astype(">f8"))
# 0-d float32 scalar 3.25
np.save(out("scalar_f4.npy"), np.array(3.25, dtype=np.float32))
# int32 counts [6]: i*i - 10
np.save(out("counts_i4.npy"), (np.arange(6, dtype=np.int32) ** 2 - 10).astype(np.int32))
# int64 [4] (numpy's default integer): 1000000 * i - 5; and one that does not fit int32
np.save(out("i8.npy"), np.arange(4, dtype=np.int64) * 1000000 - 5)
np.save(out("i8_big.npy"), np.array([1, 2, 2**31], dtype=np.int64))
# uint8 [2, 2]: 250 + i
np.save(out("u1.npy"), (np.arange(4, dtype=np.uint8) + 250).reshape(2, 2))
# an empty float32 [0, 3]
np.save(out("empty_f4.npy"), np.zeros((0, 3), dtype=np.float32))
# refused: Fortran order, complex
np.save(out("fortran_f4.npy"), np.asfortranarray(np.arange(6, dtype=np.float32).reshape(2, 3)))
np.save(out("c8.npy"), np.arange(3, dtype=np.complex64))
# format versions 2.0 and 3.0 (numpy picks them only for huge or non-latin-1 headers: asked for here)
with open(out("v2_f4.npy"), "wb") as f:
    np.lib.format.write_array(f, np.arange(5, dtype=np.float32), version=(2, 0))
with open(out("v3_f4.npy"), "wb") as f:
    np.lib.format.write_array(f, np.arange(5, dtype=np.float32), version=(3, 0))

# npz: several members, stored (np.savez) and deflated (np.savez_compressed)
members = dict(
    image=(np.arange(4 * 5 * 3, dtype=np.float32) * 0.25).reshape(4, 5, 3),
    grad=(np.arange(8, dtype=np.float64) - 3.5).reshape(2, 4) * 0.1,
    counts=np.arange(5, dtype=np.int32) * 7,
    scale=np.array(2.5, dtype=np.float32),
)
np.savez(out("several.npz"), **members)
np.savez_compressed(out("several_compressed.npz"), **members)
# refused: two members of one name (zipfile warns and writes both), a member that is not NAME.npy
with zipfile.ZipFile(out("dup.npz"), "w") as z:
    with z.open("a.npy", "w") as f:
        np.lib.format.write_array(f, np.arange(2, dtype=np.float32))
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with z.open("a.npy", "w") as f:
            np.lib.format.write_array(f, np.arange(3, dtype=np.float32))
with zipfile.ZipFile(out("not_npy.npz"), "w") as z:
    z.writestr("readme.txt", "not an array")

with open(out("README"), "w") as f:
    f.write("These files were written by numpy %s (Debian's python3-numpy) with tests/data/npy/make_npy.py: "
            "np.save, np.savez, np.savez_compressed, np.lib.format.write_array and zipfile.\n" % np.__version__)
