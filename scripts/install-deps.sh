#!/bin/sh
# Installs every build, test and benchmark dependency of voxbake from Debian 12's
# packages. Idempotent: packages already present are left alone. Runs as root or
# through sudo. Set VOX_SKIP_INSTALL=1 to skip (e.g. on a machine you manage).
set -eu
[ "${VOX_SKIP_INSTALL:-0}" = 1 ] && exit 0

PKGS="build-essential cmake git pkg-config ccache ninja-build
libopenvdb-dev libboost-dev libboost-iostreams-dev libtbb-dev libblosc-dev zlib1g-dev
libopenimageio-dev openimageio-tools libopenexr-dev libimath-dev libpng-dev
libcli11-dev nlohmann-json3-dev libtinygltf-dev libstb-dev
libgtest-dev libgmock-dev libbenchmark-dev
libopenvdb-tools hyperfine python3 python3-numpy gnuplot-nox clang"
# The export tests check vox's files with others' readers from npm
# (tests/export/setup.sh); any node with npm will do, Debian's if there is none.
command -v npm >/dev/null 2>&1 || PKGS="$PKGS nodejs npm"

missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && { echo "install-deps: all packages present"; exit 0; }

SUDO=""
if [ "$(id -u)" != 0 ]; then
  command -v sudo >/dev/null 2>&1 || { echo "install-deps: need root or sudo to install:$missing" >&2; exit 4; }
  SUDO="sudo"
fi
echo "install-deps: installing:$missing"
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -q
# shellcheck disable=SC2086
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $missing
