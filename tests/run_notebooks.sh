#!/bin/sh
# run_notebooks.sh PYTHON LIB SOURCE WORK — execute every teaching notebook of
# docs/notebooks as a person does after the README's main command: from the
# source root, `jupyter nbconvert --to notebook --execute`, no PYTHONPATH,
# no SPLATREF_* setting (a notebook finds the tree's python/ package, its
# build/libsplatref.so and its data itself).  Only a build elsewhere than
# SOURCE/build names its library (SPLATREF_LIB).  A cell that raises fails
# the test, and so does a notebook without pictures.
set -eu
py=$1 lib=$2 src=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
jupyter=$(command -v jupyter || true)
[ -n "$jupyter" ] || { echo "run_notebooks: no jupyter command (Debian's jupyter-nbconvert)" >&2; exit 1; }
unset PYTHONPATH SPLATREF_LIB SPLATREF_DATA SPLATREF_CLI
[ "$(cd "$(dirname "$lib")" && pwd)" = "$(cd "$src" && pwd)/build" ] || export SPLATREF_LIB="$lib"
cd "$src"
n=0
for nb in docs/notebooks/*.ipynb; do
  "$jupyter" nbconvert --to notebook --execute --ExecutePreprocessor.timeout=600 --output-dir "$work" "$nb"
  pics=$("$py" -c "import json,sys; nb=json.load(open(sys.argv[1])); print(sum('image/png' in o.get('data', {}) for c in nb['cells'] if c['cell_type'] == 'code' for o in c.get('outputs', [])))" "$work/$(basename "$nb")")
  [ "$pics" -ge 1 ] || { echo "run_notebooks: $(basename "$nb") drew no picture" >&2; exit 1; }
  echo "run_notebooks: $(basename "$nb") executed, $pics pictures"
  n=$((n + 1))
done
[ "$n" -ge 1 ] || { echo "run_notebooks: no notebook in docs/notebooks" >&2; exit 1; }
