#!/bin/sh
# make-walkthroughs.sh [OUT] — the walk-through page of every algorithm of
# the registry (splatref step), OUT/<algo>/index.html, and OUT/index.html
# linking them (default OUT: build/walkthroughs).  docs/tutorial.md links
# them.  Scenes: the torus (3,000 points; deferred and the transparent ones
# with WGC K = 4), the cube's domain primitives at level 1, and the Gaussian
# algorithms on the converter's sphere capture (600 Gaussians, SH degree 3).
set -eu
cd "$(dirname "$0")/.."
S=build/splatref
OUT=${1:-build/walkthroughs}
mkdir -p "$OUT"
algos=$($S info | sed -n '/^algorithms:/,/^composite ops:/p' | sed -n 's/^  \([a-z0-9-]*\) .*/\1/p')
{
  echo '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>splatref walk-throughs</title></head><body>'
  echo '<h1>splatref: every algorithm, step by step</h1><ul>'
} > "$OUT/index.html.tmp"
for a in $algos; do
  case $a in
    domain-*) extra="--model builtin:cube --points 1500 --level 1" ;;
    deferred|transparent*) extra="--points 3000 --groups wgc --k 4" ;;
    gauss*) extra="--model tests/data/captures/splat-transform/3.7.0/sphere.ply --sh-degree 3" ;;
    *) extra="--points 3000" ;;
  esac
  rm -rf "$OUT/$a"
  # shellcheck disable=SC2086
  $S step --algo "$a" $extra --size 128x112 --out "$OUT/$a" --quiet
  echo "<li><a href=\"$a/index.html\">$a</a></li>" >> "$OUT/index.html.tmp"
done
echo '</ul></body></html>' >> "$OUT/index.html.tmp"
mv "$OUT/index.html.tmp" "$OUT/index.html"
echo "walk-throughs: $OUT/index.html"
