#!/bin/sh
# make.sh — how the files under tests/data/captures/splat-transform/ were
# written (PROVENANCE.md): PlayCanvas's converter @playcanvas/splat-transform,
# both current lines, from npm, reading the generators gen-*.mjs.  Run on a
# development machine with Node and the npm registry; the tests never run it.
#   sh tests/data/captures/splat-transform/make.sh
set -eu
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
for v in 2.7.1 3.7.0; do
  mkdir -p "$work/$v" "$here/$v"
  (cd "$work/$v" && npm init -y >/dev/null && npm install --silent "@playcanvas/splat-transform@$v" >/dev/null)
  st="$work/$v/node_modules/.bin/splat-transform"
  for scene in sheet sphere; do
    for ext in ply compressed.ply spz glb; do
      "$st" -w -q "$here/gen-$scene.mjs" "$here/$v/$scene.$ext"
    done
  done
  # the SOG bundle of the sheet (the sphere's SH need a GPU to compress)
  "$st" -w -q "$here/gen-sheet.mjs" "$here/$v/sheet.sog"
done
# the 3.x line also writes SPZ version 3 (gzip)
for scene in sheet sphere; do
  "$work/3.7.0/node_modules/.bin/splat-transform" -w -q --spz-version 3 "$here/gen-$scene.mjs" "$here/3.7.0/$scene-v3.spz"
done
rm -rf "$work"
