#!/bin/sh
# Regenerates the pictures of README.md and docs/ with the CPU reference
# (`domains` as the argument: only those of docs/domains.md).
# Run deliberately, look at every picture before committing them.
set -eu
cd "$(dirname "$0")/.."
S=build/splatref
B=data/cgal/data/meshes/bunny00.off
O=docs/images
mkdir -p "$O"
domain_images() { # docs/domains.md: strict domains per level, the seven methods side by side
  D=$O/domains
  E=data/cgal/data/meshes/refined_elephant.off
  mkdir -p "$D"
  tmp=$(mktemp -d)
  for m in bunny:$B elephant:$E; do
    name=${m%%:*} model=${m#*:}
    for l in 3 6 9; do
      $S domains --model "$model" --level $l --domain strict --dump "$tmp/$name$l.ply" --quiet > /dev/null
      $S render --model "$tmp/$name$l.ply" --algo pbr2p1 --size 256x256 --quiet --out "$D/${name}_level${l}_strict.png"
      cp "$tmp/$name$l-atlas.png" "$D/${name}_level${l}_atlas.png"
    done
  done
  rm -rf "$tmp"
  $S render --model $B --algo pbr2p1 --size 256x256 --quiet --out "$D/bunny_points_pbr2p1.png"
  for meth in blendall noblend twopass darkback-hard darkback-soft overlap prefix; do
    $S render --model $B --algo domain-$meth --level 9 --extend-color --size 256x256 --quiet --out "$D/bunny_level9_$meth.png"
  done
}
if [ "${1:-}" = domains ]; then domain_images; exit 0; fi

common="--model $B --size 384x384 --quiet"
$S render $common --algo pbr2p1 --out $O/bunny_pbr2p1.png
$S render $common --algo deferred --groups mgc --c 0.4 --voronoi --out $O/bunny_deferred_mgc_voronoi.png
$S render $common --algo deferred --groups mgc --c 0.4 --out $O/bunny_deferred_mgc_plain.png
$S render $common --algo deferred --groups hash --k 8 --voronoi --out $O/bunny_deferred_hash8_voronoi.png
$S render $common --algo deferred --groups none --out $O/bunny_deferred_k1.png
$S render --size 384x384 --quiet --out $O/default_torus.png
domain_images
