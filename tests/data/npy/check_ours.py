#!/usr/bin/python3
"""check_ours.py DIR — numpy reads what splatref's writer wrote (tests/test_npy.c, round_trip_numpy).

DIR holds ours.npz (members a, n, s, e, q) and a.npy (the member a alone), written by spr_npz_write and
spr_npy_write; the values are the test's formulas, computed here again: exit 0 when every one holds.
"""
import sys
import zipfile

import numpy as np

d = sys.argv[1]
i24 = np.arange(24, dtype=np.float64)
want = {
    "a": ((i24 * 0.5 - 3.0).astype(np.float32).reshape(3, 4, 2)),
    "n": (np.arange(5, dtype=np.int64) ** 2 * 1000 - 7).astype(np.int32),
    "s": np.array(1.25, dtype=np.float32),
    "e": np.zeros((0,), dtype=np.float32),
    "q": np.arange(6, dtype=np.float32).reshape(1, 2, 1, 3),
}
with zipfile.ZipFile(d + "/ours.npz") as z:
    assert z.testzip() is None, "a member's CRC-32 is wrong"
    assert [i.compress_type for i in z.infolist()] == [zipfile.ZIP_STORED] * 5
with np.load(d + "/ours.npz") as f:
    assert sorted(f.files) == sorted(want), f.files
    for k, v in want.items():
        got = f[k]
        assert got.dtype == v.dtype and got.dtype.byteorder in "<=", (k, got.dtype)
        assert got.shape == v.shape, (k, got.shape, v.shape)
        assert np.array_equal(got, v), (k, got, v)
alone = np.load(d + "/a.npy")
assert alone.dtype == np.float32 and alone.shape == (3, 4, 2) and np.array_equal(alone, want["a"])
print("check_ours: numpy %s read ours.npz (5 members) and a.npy" % np.__version__)
