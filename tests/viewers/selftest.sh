#!/bin/sh
# Generate the test PLY, render it with all three viewers twice, check that each
# viewer's two PNGs are bit-identical and that all images pass compare.py.
#   sh selftest.sh [OUTDIR] [extra render.mjs args, e.g. --frames 5]
set -eu
cd "$(dirname "$0")"
out=${1:-out}; [ $# -gt 0 ] && shift
mkdir -p "$out"
/usr/bin/python3 make_test_ply.py "$out"
status=0
for v in gs3d spark playcanvas; do
  for run in 1 2; do
    node render.mjs --viewer $v --ply "$out/test.ply" --camera "$out/camera.json" \
      --out "$out/$v.run$run.png" --json "$out/$v.run$run.json" "$@"
  done
  if cmp -s "$out/$v.run1.png" "$out/$v.run2.png"; then echo "$v: run1 and run2 PNGs are bit-identical"
  else echo "$v: run1 and run2 PNGs DIFFER"; status=1; fi
done
/usr/bin/python3 compare.py "$out/camera.json" "$out/markers.json" \
  "$out/gs3d.run1.png" "$out/spark.run1.png" "$out/playcanvas.run1.png" || status=1
exit $status
