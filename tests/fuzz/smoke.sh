#!/bin/bash
# ctest fuzz.smoke: the libFuzzer targets scripts/fuzz_all.sh builds itself
# (gltf blockmap classes camera touched classtable rendermeta atlasmeta png exr)
# built and run for SMOKE_SECONDS (default 3) each against their seeds, when
# clang++ is installed and links a fuzzer; otherwise a visible SKIP (and a pass). The older
# targets (obj ply stl pagefile), whose scripts rebuild from scratch each time,
# are left out to keep the test under 3 minutes; SMOKE_TARGETS="..." picks others.
# The mutations are seeded (FUZZ_SEED, default 1) so that the test is a gate
# that fails on a change, not on a lucky draw; finding new bugs is the job of
# long runs of scripts/fuzz_all.sh, which draw a fresh seed each time.
# Objects, binaries and corpora go to BUILD/fuzz-smoke, so a second run only
# recompiles what changed.
# Usage: smoke.sh SOURCE_DIR BUILD_DIR
src=$1
build=$2
if ! command -v clang++ >/dev/null; then
  echo "SKIP fuzz.smoke: clang++ is not installed (apt-get install clang); the regressions still run in FuzzRegressions.*"
  exit 0
fi
# clang without its runtimes (libclang-rt-dev, only recommended by clang)
# compiles but cannot link a fuzzer: say so plainly instead of "build failed".
probe=$(mktemp -d)
trap 'rm -rf "$probe"' EXIT
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' >"$probe/p.cpp"
if ! clang++ -fsanitize=fuzzer,address,undefined "$probe/p.cpp" -o "$probe/p" 2>"$probe/err"; then
  echo "SKIP fuzz.smoke: clang++ cannot link a libFuzzer target (apt-get install libclang-rt-dev):"
  sed 's/^/  /' "$probe/err" | head -5
  exit 0
fi
targets=${SMOKE_TARGETS:-gltf blockmap classes camera touched classtable rendermeta atlasmeta png exr}
# shellcheck disable=SC2086
FUZZ_SEED=${FUZZ_SEED:-1} FUZZ_DIR=$build/fuzz-smoke BUILD_DIR=$build "$src/scripts/fuzz_all.sh" "${SMOKE_SECONDS:-3}" $targets
