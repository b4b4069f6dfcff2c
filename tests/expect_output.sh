#!/bin/sh
# expect_output.sh PATTERN... -- COMMAND [ARG...] — run COMMAND, show its
# output, and pass only when it exits 0 and its output matches every
# extended regular expression PATTERN (grep -E, one line each).  Exit 77
# (CTest's skip) passes through unchanged.
set -u
pats=""
while [ $# -gt 0 ] && [ "$1" != "--" ]; do pats="$pats
$1"; shift; done
[ $# -gt 1 ] || { echo "expect_output: usage: PATTERN... -- COMMAND [ARG...]" >&2; exit 2; }
shift
out=$(mktemp)
"$@" > "$out" 2>&1
rc=$?
cat "$out"
if [ "$rc" -ne 0 ]; then rm -f "$out"; [ "$rc" -eq 77 ] && exit 77; echo "expect_output: exit status $rc" >&2; exit 1; fi
bad=0
echo "$pats" | while IFS= read -r p; do
  [ -n "$p" ] || continue
  grep -Eq -- "$p" "$out" || { echo "expect_output: no line matches '$p'" >&2; exit 1; }
done || bad=1
rm -f "$out"
exit "$bad"
