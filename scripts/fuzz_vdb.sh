#!/bin/sh
# Builds and runs the libFuzzer target of the .vdb read path
# (tests/fuzz/fuzz_vdb.cpp; clang, -fsanitize=fuzzer,address,undefined).
# The .vdb readers (formats/vdb/*.cpp), the scene metadata and scene code they
# call (formats/scene/*.cpp, libvox/scene/scene.cpp) and the OpenVDB tree code
# they instantiate are compiled instrumented; the rest of voxbake comes from the
# static libraries of BUILD_DIR (default build, built first with cmake), and
# OpenVDB's own library is the system's (not instrumented).
# Seeds: tests/fuzz/vdb_seeds/ (scenes and a pyramid written by vox, a level set
# and a fog volume written by OpenVDB), copied into the corpus on first run.
# Usage: scripts/fuzz_vdb.sh [SECONDS=60 (0: build only)] [extra libFuzzer options...]
# Env: FUZZ_DIR (default build-fuzz), BUILD_DIR (default build).
set -eu
cd "$(dirname "$0")/.."
seconds=${1:-60}
[ $# -gt 0 ] && shift
out=${FUZZ_DIR:-build-fuzz}
build=${BUILD_DIR:-build}
corpus=$out/corpus-vdb
mkdir -p "$corpus" "$out/obj-vdb"
command -v clang++ >/dev/null || { echo "fuzz_vdb.sh: needs clang++ (apt-get install clang)" >&2; exit 4; }
for lib in vox voxmesh voxcore; do
  [ -f "$build/lib$lib.a" ] || { echo "fuzz_vdb.sh: $build/lib$lib.a missing; build with cmake first" >&2; exit 4; }
done
flags="-std=c++20 -O1 -g -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize=vptr -I. -I/usr/include/openvdb/.."
# Comparison tracing (which lets the fuzzer solve magic values) only where
# the file's bytes are parsed: the walk, CheckedVdbFile and the target. In the
# scene code it traced OpenVDB's loops over 32768-entry node masks, a third
# of the run time.
objdir=$out/obj-vdb-2
mkdir -p "$objdir"
objs=""
for src in tests/fuzz/fuzz_vdb.cpp formats/vdb/*.cpp formats/scene/scene_meta.cpp formats/scene/class_table_json.cpp \
           libvox/scene/scene.cpp; do
  obj=$objdir/$(echo "$src" | tr '/' '_' | sed 's/\.cpp$/.o/')
  case $src in
    tests/fuzz/*|formats/vdb/vdb_structure.cpp|formats/vdb/vdb_checked_file.cpp) extra="" ;;
    *) extra="-fno-sanitize-coverage=trace-cmp" ;;
  esac
  if [ ! -f "$obj" ] || [ "$src" -nt "$obj" ] || [ -n "$(find formats/vdb formats/scene libvox/scene -name '*.h' -newer "$obj")" ]; then
    echo "fuzz_vdb.sh: compiling $src" >&2
    clang++ $flags $extra -c "$src" -o "$obj"
  fi
  objs="$objs $obj"
done
clang++ -fsanitize=fuzzer,address,undefined $objs -Wl,--start-group "$build/libvox.a" "$build/libvoxmesh.a" \
  "$build/libvoxcore.a" -Wl,--end-group -lopenvdb -ltbb -lblosc -lz -lpng -lOpenEXR -lImath -lstb -lpthread \
  -o "$out/fuzz_vdb.new" && mv "$out/fuzz_vdb.new" "$out/fuzz_vdb"
[ "$seconds" = 0 ] && exit 0  # build only
[ -n "$(ls -A "$corpus")" ] || cp tests/fuzz/vdb_seeds/* "$corpus/"
# Any undefined behaviour stops the run (except a oneTBB idiom, see the file);
# short allocation stacks (allocation bookkeeping was a tenth of the run time).
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$PWD/tests/fuzz/ubsan_vdb.supp${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
export ASAN_OPTIONS="malloc_context_size=5${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
"$out/fuzz_vdb" -max_total_time="$seconds" -max_len=100000 -timeout=20 -rss_limit_mb=4096 "$@" "$corpus"
