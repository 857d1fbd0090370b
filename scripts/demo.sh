#!/bin/sh
# One command from a fresh Debian 12 machine to the demo bake: installs the
# dependencies, builds, bakes the built-in hamlet (and a block map)
# through every subcommand that exists, and prints where the outputs are.
# OUT=dir changes the output directory (default ./out); RES=N the resolution.
set -eu
cd "$(dirname "$0")/.."
scripts/install-deps.sh demo
scripts/build.sh -DVOX_BUILD_TESTS=OFF
OUT=${OUT:-out}
make -f scripts/demo.mk VOX="$(pwd)/build/bin/vox" OUT="$OUT" RES="${RES:-256}"
