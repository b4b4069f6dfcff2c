#!/bin/sh
# Regenerates the pictures of README.md and docs/ with the CPU reference
# (`domains`, `gaussians`, `profiles` or `captures` as the argument: only those
# of docs/domains.md, docs/gaussians.md, its profile gallery or docs/formats.md's
# real captures).
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
gauss_images() { # docs/gaussians.md: the three algorithms of SPEC 10 on captures, gauss3d's planes
  G=$O/gaussians
  mkdir -p "$G"
  tmp=$(mktemp -d)
  C=tests/data/captures/splat-transform/3.7.0/sphere.ply
  cam="--model $C --sh-degree 3 --cameras docs/examples/sphere-cameras.json --camera 1 --quiet"
  for a in gauss3d gauss2d gauss-blend pbr2p1; do $S render $cam --algo $a --out "$G/sphere_$a.png" --float "$tmp/$a.pfm" > /dev/null; done
  $S render $cam --algo gauss3d --dump "$tmp/dump" --out "$tmp/x.png" > /dev/null
  for p in transmittance contrib invdepth; do
    f=$(ls "$tmp/dump"/*"$p"*.pfm | tail -1)
    $S show "$f" --out "$G/sphere_gauss3d_$p.png" > /dev/null
  done
  # where the viewers' image and the surfels' differ from the training rasterizer's: checked against gauss3d
  # at Tier B within 2 LSB, the heat maps (red: more than 2 LSB apart)
  for a in gauss-blend gauss2d; do
    $S check $cam --algo gauss3d --image "$tmp/$a.pfm" --tier B --lsb 2 --out "$tmp/check-$a" > /dev/null || true
    cp "$tmp/check-$a/heatmap.png" "$G/sphere_${a}_vs_gauss3d_heatmap.png"
  done
  $S sample --model $B --points 40000 --gaussians --out "$tmp/bunny-3dgs.ply" --quiet > /dev/null
  for a in gauss3d gauss2d gauss-blend; do $S render --model "$tmp/bunny-3dgs.ply" --algo $a --size 384x384 --quiet --out "$G/bunny_capture_$a.png" > /dev/null; done
  rm -rf "$tmp"
}
profile_images() { # docs/gaussians.md: the real donut capture under every profile (SPEC 10.9), and each against inria
  P=$O/gaussians/profiles
  mkdir -p "$P"
  tmp=$(mktemp -d)
  cam="--model tests/data/captures/real/donut-mipsplat.ply --eye 0.02,-0.16,0.28 --target 0,0,0.03 --fov 50 --size 200x160 --quiet"
  for p in $($S profiles --json | sed -n 's/^.*"name":[^"]*"\([^"]*\)".*$/\1/p'); do
    $S render $cam --gauss-profile "$p" --out "$P/donut_$p.png" --float "$tmp/$p.pfm" > /dev/null
    # the heat map of profile p against inria: check renders inria as the reference, p's image is the one checked
    $S check $cam --gauss-profile inria --image "$tmp/$p.pfm" --tier B --lsb 2 --out "$tmp/check-$p" > /dev/null || true
    cp "$tmp/check-$p/heatmap.png" "$P/donut_${p}_vs_inria_heatmap.png"
  done
  rm -rf "$tmp"
}
capture_images() { # docs/formats.md: the real third-party captures (tests/data/captures/real), gauss3d, SH degree 3, the tests' cameras
  D=$O/captures
  R=tests/data/captures/real
  mkdir -p "$D"
  for c in "donut:donut-mipsplat.ply:0.02,-0.16,0.28:0,0,0.03:0,1,0" "biker-compressed:biker.compressed.ply:-0.1,-1.65,4.9:-0.1,-1.65,0:0,-1,0" \
           "biker-spz:biker.spz:-0.1,-1.65,4.9:-0.1,-1.65,0:0,-1,0" "fruit-drops:fruit-drops-sh3.ply:0.74,0.12,-1.2:0.74,0.12,-2.13:0,-1,0" \
           "seal:seal.splat:0,-0.5,-2.5:0,0,0:0,-1,0" "fourth-st:fourth-st-sh3.spz:0,-0.1,-0.45:0,0,0:0,-1,0" \
           "playbot:sog/playbot-lod6/meta.json:0,-0.8,-3.5:0,-0.5,0:0,-1,0" "wave:sog/wave_0001.sog:0,-3,-6:0,-0.5,0:0,-1,0"; do
    IFS=: read -r name file eye target up <<EOF2
$c
EOF2
    $S render --model "$R/$file" --algo gauss3d --sh-degree 3 --size 240x180 --fov 40 --eye "$eye" --target "$target" --up "$up" --quiet \
      --out "$D/$name.png" > /dev/null
  done
}
if [ "${1:-}" = captures ]; then capture_images; exit 0; fi
if [ "${1:-}" = domains ]; then domain_images; exit 0; fi
if [ "${1:-}" = gaussians ]; then gauss_images; profile_images; exit 0; fi
if [ "${1:-}" = profiles ]; then profile_images; exit 0; fi

common="--model $B --size 384x384 --quiet"
$S render $common --algo pbr2p1 --out $O/bunny_pbr2p1.png
$S render $common --algo deferred --groups mgc --c 0.4 --voronoi --out $O/bunny_deferred_mgc_voronoi.png
$S render $common --algo deferred --groups mgc --c 0.4 --out $O/bunny_deferred_mgc_plain.png
$S render $common --algo deferred --groups hash --k 8 --voronoi --out $O/bunny_deferred_hash8_voronoi.png
$S render $common --algo deferred --groups none --out $O/bunny_deferred_k1.png
$S render --size 384x384 --quiet --out $O/default_torus.png
domain_images
gauss_images
profile_images
capture_images
