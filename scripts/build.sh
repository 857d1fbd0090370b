#!/bin/sh
# Configures and builds voxbake (Release) into ./build. Extra arguments go to
# cmake, e.g.  scripts/build.sh -DVOX_SANITIZE=ON   (use BUILD_DIR=build-asan).
set -eu
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=${BUILD_TYPE:-Release} "$@" >/dev/null
cmake --build "$BUILD_DIR"
echo "build: $BUILD_DIR/bin/vox"
