#!/bin/sh
# The transparency figures of docs/transparency.md: every scene of the set
# rendered by the CPU reference with 8-layer peeling (the ground truth of
# [ZP] §6.3), 3-layer peeling (its ref. [11]), Algorithm-1 and Algorithm-2
# under two groupings: WGC K = 4 with the Eq. 13 radius enlargement (the
# off-line grouping of [ZP] §4.2, §4.4.2) and hash K = 8 with sqrt(50)/4
# (the on-line one, §4.3), and Algorithm-2 with Phong and the environment
# effects.  Prints [ZP]'s eps of each image against the 8-layer image as a
# Markdown table; pictures go to docs/images/transparency/ (look at them
# before committing).  WGC with Eq. 13 takes minutes on the real models.
# Usage: sh tools/transparency-table.sh [SIZE]
set -eu
cd "$(dirname "$0")/.."
S=build/splatref
M=data/cgal/data/meshes
O=docs/images/transparency
SIZE=${1:-384x384}
mkdir -p "$O"
HASH="--groups hash --k 8 --extend hash-radius"
WGC="--groups wgc --k 4 --extend radius"
ms() { "$@" | sed -n 's/.* \([0-9.]*\) ms -> .*/\1/p'; }
eps() { $S compare "$1" "$2" --metric zp-eps | sed -n 's/^compare: zp-eps \([0-9.]*\).*/\1/p'; }
# the part of eps from pixels the 8-layer image leaves black (outside the true silhouette)
outside() { $S compare "$1" "$2" --metric zp-eps | sed -n 's/^compare: of which \([0-9.]*\) from.*/\1/p'; }
SPLIT=$(mktemp)
trap 'rm -f "$SPLIT"' EXIT
echo "| scene | splats | pixels with a 4th layer | A-1 hash | A-2 hash | A-1 WGC | A-2 WGC | 3-layer peeling | frame ms: A-1 / A-2 (hash) / peel-3 / peel-8 |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
while IFS='|' read -r name model view; do
  [ -n "$name" ] || continue
  common="$model $view --size $SIZE --quiet"
  t8=$(ms $S render $common --algo depthpeel --layers 8 --out "$O/${name}_peel8.png")
  t3=$(ms $S render $common --algo depthpeel --layers 3 --out "$O/${name}_peel3.png")
  ta1=$(ms $S render $common --algo transparent1 $HASH --out "$O/${name}_a1_hash.png")
  ta2=$(ms $S render $common --algo transparent2 $HASH --voronoi --out "$O/${name}_a2_hash.png")
  $S render $common --algo transparent1 $WGC --out "$O/${name}_a1_wgc.png" >/dev/null
  $S render $common --algo transparent2 $WGC --voronoi --out "$O/${name}_a2_wgc.png" >/dev/null
  $S render $common --algo transparent2 $HASH --voronoi --shade phong --env sky --out "$O/${name}_a2_env.png" >/dev/null
  $S compare "$O/${name}_a2_wgc.png" "$O/${name}_peel8.png" --metric zp-eps --tier C --heatmap "$O/${name}_a2_wgc_heat.png" >/dev/null
  $S compare "$O/${name}_peel3.png" "$O/${name}_peel8.png" --metric zp-eps --tier C --heatmap "$O/${name}_peel3_heat.png" >/dev/null
  n=$($S info $model --quiet | sed -n 's/^splats: *\([0-9]*\).*/\1/p')
  four=$($S compare "$O/${name}_peel3.png" "$O/${name}_peel8.png" --metric zp-eps --tier C | sed -n 's/^compare: zp-eps .* \([0-9]*\) pixels differ$/\1/p')
  P8="$O/${name}_peel8.png"
  echo "| $name | $n | $four | $(eps "$O/${name}_a1_hash.png" "$P8") | $(eps "$O/${name}_a2_hash.png" "$P8") |" \
       "$(eps "$O/${name}_a1_wgc.png" "$P8") | $(eps "$O/${name}_a2_wgc.png" "$P8") | $(eps "$O/${name}_peel3.png" "$P8") | $ta1 / $ta2 / $t3 / $t8 |"
  echo "| $name | $(outside "$O/${name}_a1_hash.png" "$P8") | $(outside "$O/${name}_a2_hash.png" "$P8") |" \
       "$(outside "$O/${name}_a1_wgc.png" "$P8") | $(outside "$O/${name}_a2_wgc.png" "$P8") |" >> "$SPLIT"
done <<SCENES
planes|--model builtin:planes|--eye 3,2,5 --target 0,0,-0.25
spheres|--model builtin:spheres --points 40000|--eye 0.3,0.4,4
bunny|--model $M/bunny00.off --opacity 0.5 --balls 6|
armadillo|--model $M/armadillo.off --opacity 0.5 --balls 6|--eye 0,0,-300
dragon|--model $M/ChineseDragon-10kv.off --opacity 0.5 --balls 6|--eye 250,40,-982 --target -3.6,3.7,-982
SCENES
$S render --model builtin:spheres --points 40000 --eye 0.3,0.4,4 --size "$SIZE" --quiet --algo transparent2 $HASH \
  --env checker --env-size 32 --eta 0.9,0.75,0.6 --env-layers single --out "$O/spheres_env_single_dispersion.png" >/dev/null
echo
echo "Part of eps from pixels outside the 8-layer image's silhouette:"
echo
echo "| scene | A-1 hash | A-2 hash | A-1 WGC | A-2 WGC |"
echo "|---|---:|---:|---:|---:|"
cat "$SPLIT"
