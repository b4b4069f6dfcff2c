#!/bin/sh
# fuzz.sh — run the libFuzzer harnesses of tests/fuzz/ for as long as you ask.
#   sh tools/fuzz.sh [SECONDS_EACH] [ply|off|xyz|groups|splat|spz|glb|sog|cameras|image|scene|npy ...]   (default 600 s, all)
# Builds them first (clang; the installer provides it) into build/.  New
# inputs that grow coverage go to build/fuzz-corpus-<reader>/; a crash, leak,
# timeout or out-of-memory input is written as build/fuzz-<reader>-crash-*:
# copy it to tests/fuzz/corpus/<reader>/finding_<what>.<ext>, add a test,
# fix the reader.
set -eu
cd "$(dirname "$0")/.."
secs=${1:-600}
[ $# -gt 0 ] && shift
readers=${*:-ply off xyz groups splat spz glb sog cameras image scene npy}
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --target fuzz_harnesses >/dev/null
for r in $readers; do
  mkdir -p "build/fuzz-corpus-$r"
  echo "fuzz.sh: $r for $secs s"
  ./build/fuzz_"$r" -max_total_time="$secs" -timeout=5 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
    -artifact_prefix="build/fuzz-$r-" "build/fuzz-corpus-$r" "tests/fuzz/corpus/$r" 2>&1 |
    grep -E "^(Done|stat::number_of_executed_units|stat::peak_rss_mb)|ERROR|SUMMARY" || true
done
