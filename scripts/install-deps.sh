#!/bin/sh
# Installs voxbake's dependencies from Debian 12's packages. Idempotent: packages
# already present are left alone. Runs as root or through sudo. Set
# VOX_SKIP_INSTALL=1 to skip (e.g. on a machine you manage).
#
#   scripts/install-deps.sh demo   what building vox and running the demo bake needs
#   scripts/install-deps.sh        that, plus the test suite's and benchmarks' tools
#                                  (GoogleTest, Google Benchmark, OpenVDB and
#                                  OpenImageIO command-line peers, hyperfine, clang
#                                  for the fuzzers, gnuplot for the study plot; numpy,
#                                  node and Chromium for the export checks; Draco's
#                                  draco_transcoder and WebP's cwebp for the glTF
#                                  extension tests; Slurm and MUNGE for the
#                                  one-node cluster of tests/slurm/)
set -eu
[ "${VOX_SKIP_INSTALL:-0}" = 1 ] && exit 0
profile=${1:-all}

# Building vox and running scripts/demo.mk.
BUILD="build-essential cmake pkg-config ccache ninja-build make
libopenvdb-dev libboost-dev libboost-iostreams-dev libtbb-dev libblosc-dev liblz4-dev zlib1g-dev
libopenexr-dev libimath-dev libpng-dev libdeflate-dev
libcli11-dev nlohmann-json3-dev libtinygltf-dev libstb-dev libdraco-dev libmeshoptimizer-dev libwebp-dev libjpeg62-turbo-dev"
# The test suite (scripts/test.sh) and the benchmark scripts.
TEST="libgtest-dev libgmock-dev libbenchmark-dev python3 python3-numpy
libopenvdb-tools openimageio-tools hyperfine gnuplot-nox clang chromium draco webp"
# The region bake on Slurm (tests/slurm/): slurmctld, slurmd, the client
# commands and munged. The tests do not use the packages' services: their
# cluster runs from a generated configuration in a temporary directory.
TEST="$TEST slurm-wlm munge"
# clang's sanitizer and libFuzzer runtimes are only a recommendation of clang:
# without them -fsanitize=fuzzer,address does not link (tests/fuzz/smoke.sh).
TEST="$TEST libclang-rt-dev"
# The export tests check vox's files with others' readers from npm
# (tests/export/setup.sh); any node with npm will do, Debian's if there is none.
command -v npm >/dev/null 2>&1 || TEST="$TEST nodejs npm"
# npm reaches its registry over HTTPS: without recommends, Debian's npm lacks the CA bundle.
TEST="$TEST ca-certificates"

case $profile in
  demo) PKGS=$BUILD ;;
  all) PKGS="$BUILD $TEST" ;;
  *) echo "install-deps: unknown profile '$profile' (expected demo, or nothing for everything)" >&2; exit 2 ;;
esac

missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && { echo "install-deps: all $profile packages present"; exit 0; }

SUDO=""
if [ "$(id -u)" != 0 ]; then
  command -v sudo >/dev/null 2>&1 || { echo "install-deps: need root or sudo to install:$missing" >&2; exit 4; }
  SUDO="sudo"
fi
echo "install-deps: installing:$missing"
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -q
# shellcheck disable=SC2086
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $missing
