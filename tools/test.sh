#!/bin/sh
# test.sh — the whole test suite (README's test command; .ci/run runs it):
#   1. the release build and every CTest test (two at a time): the Check suites, the
#      reference images, parity --random, and the libFuzzer harnesses for a
#      bounded number of inputs (tests/fuzz/, built with clang);
#   2. a second build with AddressSanitizer and UndefinedBehaviorSanitizer
#      (-DSPR_SANITIZE=ON) running the suite again at the small test size
#      (SPLATREF_TEST_SIZE=small, parity --random on 60 scenes) so it stays fast; leaks inside libgomp,
#      Mesa and LLVM are suppressed by tools/lsan.supp, which names only their
#      libraries.  intercept_tls_get_addr=0: up to GCC 13 the runtime's
#      __tls_get_addr interceptor can take a dynamic TLS block (Mesa's) for a
#      pre-2.25 glibc header by coincidence of its address, and LeakSanitizer's
#      tracer then dies at exit ("Tracer caught signal 11", no leak reported).
set -eu
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
ctest --test-dir build --output-on-failure -j2
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPR_SANITIZE=ON
cmake --build build-asan -j2
SPLATREF_TEST_SIZE=small ASAN_OPTIONS=detect_leaks=1:intercept_tls_get_addr=0 UBSAN_OPTIONS=print_stacktrace=1 \
  LSAN_OPTIONS="suppressions=$(pwd)/tools/lsan.supp:print_suppressions=0" \
  ctest --test-dir build-asan --output-on-failure -j2
