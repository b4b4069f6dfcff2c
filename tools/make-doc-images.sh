#!/bin/sh
# Regenerates the pictures of README.md and docs/ with the CPU reference.
# Run deliberately, look at every picture before committing them.
set -eu
cd "$(dirname "$0")/.."
S=build/splatref
B=data/cgal/data/meshes/bunny00.off
O=docs/images
mkdir -p "$O"
common="--model $B --size 384x384 --quiet"
$S render $common --algo pbr2p1 --out $O/bunny_pbr2p1.png
$S render $common --algo deferred --groups mgc --c 0.4 --voronoi --out $O/bunny_deferred_mgc_voronoi.png
$S render $common --algo deferred --groups mgc --c 0.4 --out $O/bunny_deferred_mgc_plain.png
$S render $common --algo deferred --groups hash --k 8 --voronoi --out $O/bunny_deferred_hash8_voronoi.png
$S render $common --algo deferred --groups none --out $O/bunny_deferred_k1.png
$S render --size 384x384 --quiet --out $O/default_torus.png
