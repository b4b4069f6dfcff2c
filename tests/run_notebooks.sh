#!/bin/sh
# run_notebooks.sh PYTHON LIB SOURCE WORK — execute every teaching notebook of
# docs/notebooks (jupyter nbconvert, Debian's packages) on the built library;
# a cell that raises fails the test, and so does a notebook without pictures.
set -eu
py=$1 lib=$2 src=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
n=0
for nb in "$src"/docs/notebooks/*.ipynb; do
  env SPLATREF_LIB="$lib" PYTHONPATH="$src/python" SPLATREF_DATA="$src/data/cgal/data" PYDEVD_DISABLE_FILE_VALIDATION=1 \
    "$py" -m nbconvert --to notebook --execute --ExecutePreprocessor.timeout=600 --output-dir "$work" "$nb"
  pics=$("$py" -c "import json,sys; nb=json.load(open(sys.argv[1])); print(sum('image/png' in o.get('data', {}) for c in nb['cells'] if c['cell_type'] == 'code' for o in c.get('outputs', [])))" "$work/$(basename "$nb")")
  [ "$pics" -ge 1 ] || { echo "run_notebooks: $(basename "$nb") drew no picture" >&2; exit 1; }
  echo "run_notebooks: $(basename "$nb") executed, $pics pictures"
  n=$((n + 1))
done
[ "$n" -ge 1 ] || { echo "run_notebooks: no notebook in docs/notebooks" >&2; exit 1; }
