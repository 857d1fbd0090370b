#!/bin/bash
# ctest fuzz.smoke: every libFuzzer target of scripts/fuzz_all.sh built and run
# for a few seconds (SMOKE_SECONDS, default 5) against its seeds, when clang++
# is installed; otherwise a visible SKIP (and a pass). Binaries and corpora go
# to BUILD/fuzz-smoke, so a second run only rebuilds what changed.
# Usage: smoke.sh SOURCE_DIR BUILD_DIR
src=$1
build=$2
if ! command -v clang++ >/dev/null; then
  echo "SKIP fuzz.smoke: clang++ is not installed (apt-get install clang); the regressions still run in FuzzRegressions.*"
  exit 0
fi
FUZZ_DIR=$build/fuzz-smoke BUILD_DIR=$build exec "$src/scripts/fuzz_all.sh" "${SMOKE_SECONDS:-5}"
