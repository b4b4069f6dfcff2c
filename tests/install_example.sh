#!/bin/sh
# install_example.sh BUILD SOURCE WORK CLI — the library as a user gets it:
# `cmake --install` into WORK/prefix, then examples/check_planes configured
# and built as a separate CMake project against that tree (find_package),
# and once more with pkg-config alone; both run on a scene saved by the CLI
# against that scene's own float image (must pass) and a changed one (must fail).
set -eu
build=$1 src=$2 work=$3 cli=$4
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
test -f "$work/prefix/include/splatref/spr_scene.h"
test -f "$work/prefix/lib/cmake/splatref/splatrefConfig.cmake"
test -f "$work/prefix/lib/pkgconfig/splatref.pc"
# the shared library with its soname, the internal headers left out, and
# every installed header compiling in a translation unit of its own
soname=$(objdump -p "$work/prefix/lib/libsplatref.so" | sed -n 's/^ *SONAME *//p')
test "$soname" = "libsplatref.so.0.1"
test -f "$work/prefix/lib/$soname"
if ls "$work/prefix/include/splatref/" | grep -q '^spr__'; then echo "install_example: an internal header is installed" >&2; exit 1; fi
nh=0
for h in "$work/prefix/include/splatref/"*.h; do
  printf '#include <%s>\ntypedef int spr_header_compiles;\n' "$(basename "$h")" > "$work/header.c"
  cc -std=c11 -Wall -Wextra -Wpedantic -Werror -fsyntax-only -I"$work/prefix/include/splatref" "$work/header.c" ||
    { echo "install_example: $(basename "$h") does not compile on its own" >&2; exit 1; }
  nh=$((nh + 1))
done
# the Python package from the prefix: found on its path, loading the prefix's library
pyver=$(cd / && env -u SPLATREF_LIB PYTHONPATH="$work/prefix/lib/python3/dist-packages" /usr/bin/python3 -c \
  "import splatref, os; assert os.path.realpath(splatref._lib.lib._name).startswith(os.path.realpath('$work/prefix')), splatref._lib.lib._name; print(splatref.__version__)")
cmake -S "$src/examples/check_planes" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
cmake --build "$work/example" > "$work/build.log"
# pkg-config alone, as a Makefile user would (the shared library)
PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig" cc -std=c11 -o "$work/check_planes_pc" "$src/examples/check_planes/check_planes.c" \
  $(PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig" pkg-config --static --cflags --libs splatref)
cd "$work"
"$cli" render --model builtin:torus --points 4000 --size 96x80 --algo deferred --voronoi --groups mgc --save-scene scene.json \
  --float mine.pfm --out mine.png --quiet > /dev/null
./example/check_planes scene.json mine.pfm
# -lsplatref takes the shared library, found at run time as any library in a prefix off the loader's path
ldd ./check_planes_pc | grep -q "libsplatref.so.0.1 => not found"
LD_LIBRARY_PATH="$work/prefix/lib" ./check_planes_pc scene.json mine.pfm > /dev/null
# the PFM's last float (top row, last pixel's blue) one ulp above zero: must fail
cp mine.pfm changed.pfm
printf '\001' | dd of=changed.pfm bs=1 seek=$(( $(stat -c %s changed.pfm) - 4 )) conv=notrunc 2> /dev/null
if ./example/check_planes scene.json changed.pfm; then echo "install_example: a changed image passed" >&2; exit 1; fi
echo "install_example: installed package found by find_package and by pkg-config; example passes on the scene's own image and fails on a changed one; $nh headers compile alone; Python package $pyver imports from the prefix"
