#!/bin/sh
# tools/gpu-kit.sh — take splatref to a machine with a GPU and no package
# registry, build it there from Debian 12's packages, and run the GL backend's
# checks on the GPU driver (docs/parity-gpu.md).
#
#   sh tools/gpu-kit.sh gather
#       Here (Debian 12, apt registry reachable): `apt-get download` (no install)
#       the packages the build and the GL loader need into .gpu-kit/debs
#       (ignored by git), with a manifest of names, versions and sha256.
#   sh tools/gpu-kit.sh run [--random N] [--gl-device N] [--out DIR] [--reps N] [--no-bench]
#       There (x86-64, as root, a C compiler with OpenMP and CMake ≥ 3.16 on
#       the PATH; nothing else installed): unpack the packages into
#       .gpu-kit/prefix, build with that prefix alone on CMake's and
#       pkg-config's paths, check that every library came from the prefix, then
#       run `splatref parity` on the default scene, `parity --random N`,
#       `reference` and `bench` on EGL device N (default 0: the GPU where the
#       NVIDIA driver is the EGL vendor) and write DIR/report.txt (default
#       .gpu-kit/report) with every command's output and exit status.
#   sh tools/gpu-kit.sh try-here [run's options]
#       Here: a fresh clone of this checkout, the gathered packages copied in,
#       and `run` inside a private mount namespace where the system's headers
#       and pkg-config files of those same packages are hidden (empty files and
#       directories bound over them), so a build that reaches for them fails.
#
# The GL loader (glvnd's libEGL, libOpenGL) travels with the kit; the vendor
# implementation is the machine's own: the NVIDIA driver's EGL vendor file is
# looked for in /usr/local/nvidia/share/glvnd/egl_vendor.d,
# /usr/share/glvnd/egl_vendor.d and /etc/glvnd/egl_vendor.d.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
kit="$here/.gpu-kit"

# What the build links and includes (BUILD_TESTING off: no Check), the GL
# loader, and pkgconf for a machine with no pkg-config.  Runtime libraries
# that any x86-64 Linux has (libc, libgcc, libstdc++, libgomp: the
# compiler's own) stay the machine's.
PKGS="libflann-dev libflann1.9 liblz4-1 liblz4-dev \
  libpng-dev libpng16-16 zlib1g-dev zlib1g libzstd-dev libzstd1 \
  libzip-dev libzip4 libbz2-1.0 libssl3 libwebp-dev libwebp7 libwebpmux3 libwebpdemux2 \
  libqhull-dev libqhull-r8.0 libqhull8.0 libqhullcpp8.0 libcjson-dev libcjson1 \
  libegl-dev libegl1 libgl-dev libgl1 libglx-dev libglx0 libopengl-dev libopengl0 libgles-dev libgles1 libgles2 libglvnd0 libglvnd-dev \
  pkgconf pkgconf-bin libpkgconf3"
# the -dev packages whose headers try-here hides
DEV_PKGS="libflann-dev liblz4-dev libpng-dev zlib1g-dev libzstd-dev libzip-dev libwebp-dev libqhull-dev libcjson-dev libegl-dev libgl-dev libglx-dev libopengl-dev libgles-dev libglvnd-dev"
ARCH_LIB=usr/lib/x86_64-linux-gnu
MODELS="bunny00.off armadillo.off ChineseDragon-10kv.off"

die() { echo "gpu-kit: $*" >&2; exit 1; }

gather() {
  [ "$(dpkg --print-architecture 2>/dev/null)" = amd64 ] || die "gather runs on Debian 12 amd64 (the packages are Debian's x86-64 builds)"
  mkdir -p "$kit/debs.tmp"
  rm -f "$kit/debs.tmp"/*.deb
  # shellcheck disable=SC2086
  (cd "$kit/debs.tmp" && apt-get download $PKGS) || {
    echo "gpu-kit: apt-get download failed; running apt-get update once and trying again" >&2
    apt-get update >/dev/null
    # shellcheck disable=SC2086
    (cd "$kit/debs.tmp" && apt-get download $PKGS)
  }
  rm -rf "$kit/debs"
  mv "$kit/debs.tmp" "$kit/debs"
  (cd "$kit/debs" && for f in *.deb; do
     printf '%s %s %s\n' "$(dpkg-deb -f "$f" Package)" "$(dpkg-deb -f "$f" Version)" "$(sha256sum "$f" | cut -d' ' -f1)"
   done) >"$kit/MANIFEST.tmp"
  # the CGAL models the reference scenes and bench read (libcgal-demo's
  # data.tar.gz, extracted by tools/install-deps.sh)
  rm -rf "$kit/models"
  mkdir -p "$kit/models"
  for m in $MODELS; do
    [ -f "$here/data/cgal/data/meshes/$m" ] || die "data/cgal/data/meshes/$m missing: run 'sh tools/install-deps.sh' first"
    cp "$here/data/cgal/data/meshes/$m" "$kit/models/"
    printf 'model %s (libcgal-demo data.tar.gz, meshes/) %s\n' "$m" "$(sha256sum "$kit/models/$m" | cut -d' ' -f1)" >>"$kit/MANIFEST.tmp"
  done
  mv "$kit/MANIFEST.tmp" "$kit/MANIFEST"
  echo "gpu-kit: $(ls "$kit/debs" | wc -l) packages, $(du -sh "$kit/debs" | cut -f1) in .gpu-kit/debs, $(ls "$kit/models" | wc -l) models (manifest .gpu-kit/MANIFEST)"
}

# Unpack one .deb into $2 without dpkg: the ar archive's data.tar.* member.
unpack_deb() {
  if command -v dpkg-deb >/dev/null 2>&1; then dpkg-deb -x "$1" "$2"; return; fi
  command -v ar >/dev/null 2>&1 || die "neither dpkg-deb nor ar to unpack $1"
  t=$(mktemp -d)
  (cd "$t" && ar x "$1")
  case $(ls "$t"/data.tar.*) in
    *.xz) tar -xJf "$t"/data.tar.xz -C "$2" ;;
    *.zst) zstd -dc "$t"/data.tar.zst | tar -x -C "$2" ;;
    *.gz) tar -xzf "$t"/data.tar.gz -C "$2" ;;
    *) die "$1: no data.tar member" ;;
  esac
  rm -rf "$t"
}

run() {
  random=300 device=0 out="$kit/report" reps=3 bench=1
  while [ $# -gt 0 ]; do
    case $1 in
      --random) random=$2; shift 2 ;;
      --gl-device) device=$2; shift 2 ;;
      --out) out=$2; shift 2 ;;
      --reps) reps=$2; shift 2 ;;
      --no-bench) bench=0; shift ;;
      *) die "run: unknown option '$1' (--random N, --gl-device N, --out DIR, --reps N, --no-bench)" ;;
    esac
  done
  [ -d "$kit/debs" ] && ls "$kit/debs"/*.deb >/dev/null 2>&1 || die "no packages in .gpu-kit/debs: run 'sh tools/gpu-kit.sh gather' where apt works, and bring .gpu-kit with the checkout"
  [ "$(uname -m)" = x86_64 ] || die "run needs an x86-64 machine (the packages are Debian's amd64 builds), this is $(uname -m)"
  cc=${CC:-cc}
  command -v "$cc" >/dev/null 2>&1 || die "no C compiler ('$cc'; set CC): the kit brings libraries, not a compiler"
  command -v cmake >/dev/null 2>&1 || die "no cmake on the PATH"
  for m in $MODELS; do
    [ -f "$here/data/cgal/data/meshes/$m" ] && continue
    [ -f "$kit/models/$m" ] || die "model $m neither in data/cgal/data/meshes nor in .gpu-kit/models (gather again)"
    mkdir -p "$here/data/cgal/data/meshes"
    cp "$kit/models/$m" "$here/data/cgal/data/meshes/"
  done
  prefix="$kit/prefix"
  rm -rf "$prefix" "$kit/build"
  mkdir -p "$prefix" "$out"
  for f in "$kit/debs"/*.deb; do unpack_deb "$f" "$prefix"; done
  # absolute links (/lib/x86_64-linux-gnu/libz.so.1…) point into the prefix
  find "$prefix" -type l | while read -r l; do
    t=$(readlink "$l")
    case $t in /*) ln -sfn "$prefix$t" "$l" ;; esac
  done
  # Debian 12 keeps some libraries in /lib (merged /usr): mirror them under usr/
  if [ -d "$prefix/lib/x86_64-linux-gnu" ]; then
    mkdir -p "$prefix/$ARCH_LIB"
    for f in "$prefix/lib/x86_64-linux-gnu"/*; do [ -e "$prefix/$ARCH_LIB/$(basename "$f")" ] || ln -s "$f" "$prefix/$ARCH_LIB/"; done
  fi
  lib="$prefix/$ARCH_LIB"
  mkdir -p "$kit/bin"
  # the machine's pkg-config if it has one (GPU_KIT_OWN_PKGCONF=1: the kit's pkgconf regardless)
  if [ -z "${GPU_KIT_OWN_PKGCONF:-}" ] && command -v pkg-config >/dev/null 2>&1; then pc=$(command -v pkg-config); else
    printf '#!/bin/sh\nLD_LIBRARY_PATH="%s${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" exec "%s" "$@"\n' "$lib" "$prefix/usr/bin/pkgconf" >"$kit/bin/pkg-config"
    chmod +x "$kit/bin/pkg-config"
    pc="$kit/bin/pkg-config"
  fi
  export PKG_CONFIG_LIBDIR="$lib/pkgconfig:$prefix/usr/share/pkgconfig" PKG_CONFIG_SYSROOT_DIR="$prefix"
  log="$out/report.txt"
  : >"$log"
  section() { printf '\n== %s\n' "$*" | tee -a "$log"; }
  summary="$out/.summary"
  : >"$summary"
  step() { # step TITLE command…: run, log its output and exit status, keep its last lines for the summary
    section "$1"
    title=$1
    shift
    printf '$ %s\n' "$*" >>"$log"
    set +e
    "$@" >"$out/.step" 2>&1
    rc=$?
    set -e
    cat "$out/.step" >>"$log"
    printf 'exit %d\n' "$rc" | tee -a "$log"
    { printf -- '- %s: exit %d\n' "$title" "$rc"; grep -E '^scene |planes bit-exact|planes differ|mismatch|verdict:|reference: [0-9]+ scenes|speed-up|time CPU|renderer|\[' "$out/.step" | grep -v '^reference [a-z]' | tail -n 40 | sed 's/^/    /'; } >>"$summary"
    return 0
  }
  section "machine"
  { uname -a; nproc; date -u; "$cc" --version | head -1; cmake --version | head -1; } >>"$log" 2>&1
  command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L >>"$log" 2>&1 || echo "(no nvidia-smi)" >>"$log"
  section "kit"
  cat "$kit/MANIFEST" >>"$log"
  section "build (prefix $prefix only)"
  echo "pkg-config: $pc" | tee -a "$log"
  # shellcheck disable=SC2086
  cmake -S "$here" -B "$kit/build" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DCMAKE_C_COMPILER="$cc" \
    -DCMAKE_PREFIX_PATH="$prefix/usr" -DCMAKE_INCLUDE_PATH="$prefix/usr/include" -DCMAKE_LIBRARY_PATH="$lib" \
    -DPKG_CONFIG_EXECUTABLE="$pc" >>"$log" 2>&1 || { tail -30 "$log" >&2; die "cmake failed (log: $log)"; }
  cmake --build "$kit/build" -j"$(nproc)" >>"$log" 2>&1 || { tail -30 "$log" >&2; die "build failed (log: $log)"; }
  bin="$kit/build/splatref"
  # every library of the kit found in the prefix, by CMake and by the loader
  nvlib=""
  for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do [ -d "$d" ] && nvlib="$nvlib:$d"; done
  export LD_LIBRARY_PATH="$lib$nvlib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  vend=""
  for d in /usr/local/nvidia/share/glvnd/egl_vendor.d /usr/share/glvnd/egl_vendor.d /etc/glvnd/egl_vendor.d; do [ -d "$d" ] && vend="$vend${vend:+:}$d"; done
  [ -n "$vend" ] && export __EGL_VENDOR_LIBRARY_DIRS="$vend"
  section "where the libraries came from"
  bad=0
  for l in flann png16 z zstd zip webp qhull_r cjson EGL OpenGL; do
    at=$(ldd "$bin" | awk -v l="lib$l.so" 'index($1, l) == 1 { print $3 }' | head -1)
    case $at in "$prefix"/*) printf 'lib%s: %s\n' "$l" "$at" | tee -a "$log" ;; *) printf 'lib%s: NOT FROM THE KIT (%s)\n' "$l" "${at:-not linked}" | tee -a "$log"; bad=1 ;; esac
  done
  if grep -E '^(FLANN_INCLUDE_DIR|FLANN_LIBRARY|OPENGL_egl_LIBRARY|OPENGL_opengl_LIBRARY|OPENGL_EGL_INCLUDE_DIR):' "$kit/build/CMakeCache.txt" | grep -v "$prefix" | tee -a "$log" | grep -q .; then bad=1; fi
  [ $bad = 0 ] || die "a library or header came from outside the kit (see $log)"
  echo "EGL vendor files from: ${vend:-(none found)}" | tee -a "$log"
  step "default scene, every algorithm (GL on EGL device $device)" "$bin" parity --gl-device "$device" --report "$out/parity-default"
  step "parity --random $random" "$bin" parity --random "$random" --gl-device "$device" --report "$out/parity-random" --quiet
  step "reference images" "$bin" reference --gl-device "$device"
  [ $bench = 0 ] || step "bench" "$bin" bench --scene all --reps "$reps" --gl-device "$device" --quiet
  section "summary"
  tee -a "$log" <"$summary"
  rm -f "$summary" "$out/.step"
  echo "gpu-kit: report in $log"
}

try_here() {
  [ -d "$kit/debs" ] || die "gather first"
  [ "$(id -u)" = 0 ] || die "try-here needs root (a private mount namespace)"
  t=$(mktemp -d /tmp/gpu-kit-try.XXXXXX)
  git clone -q "$here" "$t/splatref"
  mkdir -p "$t/splatref/.gpu-kit"
  cp -r "$kit/debs" "$kit/models" "$kit/MANIFEST" "$t/splatref/.gpu-kit/"
  # the headers and pkg-config files of the same packages on this system, hidden
  hide="$t/hide.sh"
  mkdir -p "$t/empty"
  : >"$t/empty.h"
  {
    echo "set -e"
    for p in $DEV_PKGS; do
      dpkg -L "$p" 2>/dev/null | while read -r f; do
        case $f in /usr/include/*) [ -f "$f" ] && [ ! -L "$f" ] && echo "mount --bind '$t/empty.h' '$f'" ;; esac
      done
    done
    for d in /usr/lib/x86_64-linux-gnu/pkgconfig /usr/share/pkgconfig /usr/lib/pkgconfig; do [ -d "$d" ] && echo "mount --bind '$t/empty' '$d'"; done
    echo 'echo "gpu-kit: $(grep -c mount "$0") system headers and pkg-config folders hidden"'
    printf 'cd %s && sh tools/gpu-kit.sh run' "$t/splatref"
    for a in "$@"; do printf " '%s'" "$a"; done
    echo
  } >"$hide"
  unshare -m sh "$hide"
  echo "gpu-kit: try-here clone in $t/splatref (report in its .gpu-kit/report unless --out)"
}

case ${1:-} in
  gather) gather ;;
  run) shift; run "$@" ;;
  try-here) shift; try_here "$@" ;;
  *) echo "usage: sh tools/gpu-kit.sh gather | run [--random N] [--gl-device N] [--out DIR] [--reps N] [--no-bench] | try-here [run's options]" >&2; exit 2 ;;
esac
