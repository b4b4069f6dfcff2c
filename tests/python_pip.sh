#!/bin/sh
# python_pip.sh PYTHON SOURCE LIB WORK — the Python package as a user installs
# it: a virtual environment (with the system's numpy and pytest), then
# `pip install ./python` with no package index, then the example test run
# from outside the source tree on the wheel's own copy of the library.
set -eu
py=$1 src=$2 lib=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
"$py" -m venv --system-site-packages "$work/venv"
SPLATREF_LIB="$lib" "$work/venv/bin/pip" install --no-index --no-cache-dir --disable-pip-version-check -q "$src/python"
cp "$src/python/examples/test_my_renderer.py" "$work/"
cd "$work"
where=$(env -u SPLATREF_LIB -u PYTHONPATH "$work/venv/bin/python" -c "import splatref; print(splatref._lib.lib._name)")
case "$where" in "$work/venv/"*) ;; *) echo "python_pip: splatref loaded $where, not the wheel's library" >&2; exit 1;; esac
env -u SPLATREF_LIB -u PYTHONPATH "$work/venv/bin/python" -m pytest -q -p no:cacheprovider test_my_renderer.py
echo "python_pip: pip install ./python offline, the example test passes on $where"
