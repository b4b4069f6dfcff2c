#!/bin/sh
# How cost grows with the number of splats (docs/performance.md): the
# armadillo resampled to 100K, 1M, 10M and 100M splats, each phase timed by
# `splatref render --stats` (1024x1024, all cores), plotted log-log with a
# line of slope 1 for comparison.  Writes DIR/cost.tsv, DIR/cost.html and
# docs/images/performance/cost-loglog.png (the page screenshotted by
# headless Chromium, which tools/install-deps.sh installs).
#
#   tools/cost-plot.sh [DIR]        DIR caches the sampled clouds (default build/scale)
#   SPLATREF_SCALE_MAX=10000000     stop at 10M: `splatref sample` holds ~17 GB
#                                   while it sizes 100M splats (the render does not)
#
# In memory up to 10M (load, streaming pass, hash grouping, frames); with
# --stream at every size (the only way at 100M): the read-and-check pass, the
# frames reading the file chunk by chunk.
set -eu
cd "$(dirname "$0")/.."
S=build/splatref
M=${SPLATREF_DATA:-data/cgal/data}/meshes/armadillo.off
D=${1:-build/scale}
MAX=${SPLATREF_SCALE_MAX:-100000000}
OUT=docs/images/performance/cost-loglog.png
mkdir -p "$D" "$(dirname "$OUT")"
T=$D/cost.tsv
printf 'splats\tphase\tms\n' > "$T"

num() { # num KEY FILE: a top-level number of a cJSON-printed stats file
  sed -n "s/^	\"$1\":	\([-0-9.e+]*\),\{0,1\}\$/\1/p" "$2"
}

for n in 100000 1000000 10000000 100000000; do
  [ "$n" -le "$MAX" ] || continue
  f=$D/armadillo-$n.ply
  [ -f "$f" ] || $S sample --model "$M" --points $n --out "$f" --quiet
  j=$D/stats.json
  if [ "$n" -le 10000000 ]; then
    $S render --model "$f" --algo pbr2p1 --size 1024x1024 --out "$D/p.png" --stats "$j" --quiet > /dev/null
    printf '%s\tload (whole file)\t%s\n%s\tstreaming pass\t%s\n%s\tframe pbr2p1\t%s\n' \
      $n "$(num ms_load "$j")" $n "$(num ms_stream_pass "$j")" $n "$(num ms_render "$j")" >> "$T"
    $S render --model "$f" --algo deferred --groups hash --size 1024x1024 --out "$D/d.png" --stats "$j" --quiet > /dev/null
    printf '%s\thash grouping (BSP axes)\t%s\n%s\tframe deferred\t%s\n' $n "$(num ms_grouping "$j")" $n "$(num ms_render "$j")" >> "$T"
  fi
  $S render --model "$f" --algo pbr2p1 --stream --size 1024x1024 --out "$D/p.png" --stats "$j" --quiet > /dev/null
  printf '%s\t--stream: read and check\t%s\n%s\t--stream: frame pbr2p1\t%s\n' $n "$(num ms_load "$j")" $n "$(num ms_render "$j")" >> "$T"
  $S render --model "$f" --algo deferred --groups hash --stream --size 1024x1024 --out "$D/d.png" --stats "$j" --quiet > /dev/null
  printf '%s\t--stream: frame deferred\t%s\n' $n "$(num ms_render "$j")" >> "$T"
  [ "$n" -le 10000000 ] || printf '%s\thash grouping (BSP axes)\t%s\n' $n "$(num ms_grouping "$j")" >> "$T"
done

# The plot: an SVG page, drawn by awk from the table (log10 axes).
awk -F '\t' -v cpu="$(nproc) cores" '
NR == 1 { next }
{ key = $2; if (!(key in idx)) { idx[key] = ++nk; name[nk] = key }; k = idx[key]; m = ++cnt[k]; X[k, m] = $1; Y[k, m] = $3 }
function px(v) { return 90 + (log(v) / log(10) - 5) / 3 * 640 }
function py(v) { return 470 - (log(v) / log(10) + 1) / 7 * 440 }
END {
  split("#1f77b4 #ff7f0e #2ca02c #d62728 #9467bd #8c564b #e377c2 #7f7f7f #17becf", col, " ")
  print "<!doctype html><meta charset=utf-8><body style=\"margin:0;background:#fff\">"
  print "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1100\" height=\"540\" font-family=\"sans-serif\" font-size=\"13\">"
  print "<text x=\"90\" y=\"20\" font-size=\"15\">splatref: cost of each phase against the number of splats (armadillo, 1024x1024, " cpu ")</text>"
  for (e = 5; e <= 8; e++) { x = px(10 ^ e); printf "<line x1=\"%.1f\" y1=\"30\" x2=\"%.1f\" y2=\"470\" stroke=\"#ddd\"/><text x=\"%.1f\" y=\"490\" text-anchor=\"middle\">10^%d</text>\n", x, x, x, e }
  for (e = -1; e <= 6; e++) { y = py(10 ^ e); printf "<line x1=\"90\" y1=\"%.1f\" x2=\"730\" y2=\"%.1f\" stroke=\"#ddd\"/><text x=\"84\" y=\"%.1f\" text-anchor=\"end\">%s</text>\n", y, y, y + 4, e < 0 ? "0.1 ms" : e < 3 ? 10 ^ e " ms" : 10 ^ (e - 3) " s" }
  print "<text x=\"410\" y=\"520\" text-anchor=\"middle\">splats (log scale)</text>"
  print "<text x=\"20\" y=\"250\" transform=\"rotate(-90 20 250)\" text-anchor=\"middle\">time (log scale)</text>"
  # slope 1 through the streaming pass at its first size
  s = idx["streaming pass"]; if (s) { x0 = X[s, 1]; y0 = Y[s, 1]; printf "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#000\" stroke-dasharray=\"4 4\"/>\n", px(x0), py(y0), px(x0 * 1000), py(y0 * 1000) }
  for (k = 1; k <= nk; k++) {
    c = col[(k - 1) % 9 + 1]; pts = ""
    for (m = 1; m <= cnt[k]; m++) { pts = pts sprintf("%.1f,%.1f ", px(X[k, m]), py(Y[k, m])); printf "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>\n", px(X[k, m]), py(Y[k, m]), c }
    printf "<polyline points=\"%s\" fill=\"none\" stroke=\"%s\" stroke-width=\"2\"%s/>\n", pts, c, name[k] ~ /^--stream/ ? " stroke-dasharray=\"8 3\"" : ""
    printf "<line x1=\"750\" y1=\"%d\" x2=\"780\" y2=\"%d\" stroke=\"%s\" stroke-width=\"2\"%s/><text x=\"788\" y=\"%d\">%s</text>\n", 40 + 22 * k, 40 + 22 * k, c, name[k] ~ /^--stream/ ? " stroke-dasharray=\"8 3\"" : "", 44 + 22 * k, name[k]
  }
  printf "<line x1=\"750\" y1=\"%d\" x2=\"780\" y2=\"%d\" stroke=\"#000\" stroke-dasharray=\"4 4\"/><text x=\"788\" y=\"%d\">slope 1 (linear cost)</text>\n", 62 + 22 * nk, 62 + 22 * nk, 66 + 22 * nk
  print "</svg>"
}' "$T" > "$D/cost.html"

C=$(command -v chromium || command -v chromium-browser || true)
[ -n "$C" ] || { echo "cost-plot: Chromium is not installed (tools/install-deps.sh installs it)" >&2; exit 1; }
"$C" --headless --no-sandbox --disable-gpu --no-first-run --user-data-dir="$D/chrome-profile" --hide-scrollbars \
  --window-size=1100,540 --screenshot="$OUT" "file://$(cd "$D" && pwd)/cost.html" 2> /dev/null
echo "cost-plot: $T, $OUT"
