#!/bin/sh
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer: builds
# vox and its tests with -DVOX_SANITIZE=ON into BUILD_DIR (default build-asan)
# and runs CTest there. Any ASan report (leaks included) or undefined behaviour
# fails the test that hit it: the defaults compiled into the binaries
# (tests/sanitizers/default_options.cpp) halt on the first report, and
# tests/sanitizers/ubsan.supp names the reports that come from Debian's
# library headers, each with why.
#
# Left out, and why:
#   fuzz.smoke   its fuzzers carry their own ASan+UBSan build (scripts/fuzz_all.sh);
#   export.pixel_match
#                it drives headless Chromium (its own process, not vox) over the
#                .glb files the other export tests write under the sanitizers;
#   signals.*    they time a signal into a phase of a run; ASan's 2-5x slowdown
#                moves the phases, and signal handling is not memory safety;
#   memguard.*, city.cli, fusespeed.reuse
#                they assert a process's resident memory and a refusal's CPU time
#                (under 1 s); ASan's shadow memory makes a process 140-740 MB
#                resident before it reads anything and refusals take 4-5x the
#                CPU, so the figures are the sanitizer's, not vox's. The guards'
#                code runs in the other tests (every bake estimates first);
#   slurm.*, make.bake
#                they test the scheduler scripts (sbatch arrays, make -j) around
#                the same region bakes and merges regionbake.cli and
#                pagemerge.cli run under the sanitizers; left out for CI's time.
# Run one of them anyway by naming it: scripts/test-sanitizers.sh -R memguard.oom
# (arguments replace the exclusions and go to ctest).
# Usage: scripts/test-sanitizers.sh [ctest arguments...]   e.g. -R cli.
# Env: BUILD_DIR (default build-asan), VOX_SKIP_INSTALL as in install-deps.sh.
set -eu
cd "$(dirname "$0")/.."
scripts/install-deps.sh
BUILD_DIR=${BUILD_DIR:-build-asan}
export BUILD_DIR
scripts/build.sh -DVOX_SANITIZE=ON -DVOX_BUILD_TESTS=ON
root=$(pwd)
cd "$BUILD_DIR"
if [ $# -eq 0 ]; then
  set -- -E '^(fuzz\.smoke|export\.pixel_match$|signals\.|memguard\.|city\.cli$|fusespeed\.reuse$|slurm\.|make\.bake$)'
fi
junit="$(pwd)/sanitizers-junit.xml"
if ctest --output-on-failure -j"$(nproc)" --output-junit "$junit" "$@"; then
  exit 0
fi
# LeakSanitizer's exit-time tracer sometimes dies of a segfault of its own
# (google/sanitizers#1353; docs/reliability.md "Sanitizers in CI"; the one
# cause found, #1409, is avoided by vox's sanitizer defaults). A test
# that failed only that way runs once more and must pass then; any other
# failure, a real leak or sanitizer report included, fails here.
# By name: --rerun-failed maps numbers from the filtered run onto other tests.
rerun=$(python3 "$root/scripts/sanitizer_failures.py" "$junit") || exit 1
ctest --output-on-failure -R "$rerun"
