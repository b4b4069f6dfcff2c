#!/bin/sh
# Idempotent dependency installer for splatref (Debian 12, run as root).
# Installs every package the build, the tests and the main job need, then
# extracts the CGAL demo models the tests use into data/cgal/ (ignored by git).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)

pkgs="build-essential cmake pkg-config ca-certificates \
  libflann-dev liblz4-dev check libsubunit-dev \
  libpng-dev zlib1g-dev libzstd-dev libzip-dev libwebp-dev \
  python3-numpy python3-pil python3-pytest python3-venv python3-pip python3-junitparser libxml2-utils \
  jupyter-nbconvert python3-ipykernel python3-matplotlib \
  libegl-dev libgl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri mesa-vulkan-drivers \
  libqhull-dev libcjson-dev libxml2-dev libcgal-demo \
  clang libclang-rt-14-dev libomp-14-dev \
  chromium nodejs"
# npm: Debian's package on a fresh machine; a nodejs that ships its own npm (NodeSource's) needs none
command -v npm >/dev/null 2>&1 || pkgs="$pkgs npm"

missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  export DEBIAN_FRONTEND=noninteractive
  apt-get update
  # shellcheck disable=SC2086
  apt-get install -y --no-install-recommends $missing
fi

# The real test models (SPEC §1): extracted once, kept out of git.
data="$here/data/cgal"
tarball=/usr/share/doc/libcgal-dev/data.tar.gz
[ -f "$tarball" ] || tarball=$(dpkg -L libcgal-demo | grep -m1 '/data\.tar\.gz$' || true)
if [ ! -f "$data/.extracted" ]; then
  [ -n "$tarball" ] && [ -f "$tarball" ] || { echo "install-deps: CGAL data archive not found (package libcgal-demo)" >&2; exit 1; }
  mkdir -p "$data"
  tar -xzf "$tarball" -C "$data" \
    --wildcards '*meshes/bunny00.off' '*meshes/armadillo.off' \
    '*meshes/ChineseDragon-10kv.off' '*meshes/refined_elephant.off' '*points_3/*'
  touch "$data/.extracted"
fi

# The web viewers the CTest `viewers` runs (tests/viewers): their npm packages at the versions
# package-lock.json pins, installed again only when the lock file changed.
viewers="$here/tests/viewers"
if ! cmp -s "$viewers/package-lock.json" "$viewers/node_modules/.splatref-lock" 2>/dev/null; then
  (cd "$viewers" && npm ci --no-audit --no-fund) && cp "$viewers/package-lock.json" "$viewers/node_modules/.splatref-lock"
fi
