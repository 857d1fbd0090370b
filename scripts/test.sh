#!/bin/sh
# One command from a fresh Debian 12 machine to a full test run: installs the
# dependencies, builds, runs every test through CTest. Exit status is CTest's.
set -eu
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh -DVOX_BUILD_TESTS=ON "$@"
BUILD_DIR=${BUILD_DIR:-build}
cd "$BUILD_DIR"
ctest --output-on-failure -j"$(nproc)"
