#!/bin/bash
# Builds and runs every libFuzzer target for a fixed time each, one after the
# other, and prints a table: target, runs, seconds, result.
#   the parsers of their own scripts: pagefile (scripts/fuzz_pagefile.sh), vdb
#     (scripts/fuzz_vdb.sh, when it exists);
#   built here (tests/fuzz/fuzz_NAME.cpp): obj ply stl gltf blockmap classes
#     camera touched classtable rendermeta atlasmeta png exr.
# The parsers under test are compiled with clang -fsanitize=fuzzer,address,undefined;
# what they call from the rest of vox is linked from the CMake build's static
# libraries (BUILD_DIR, default build: configure and build it first), which the
# fuzzer does not instrument. Seeds: tests/fuzz/seeds/NAME/ plus small files of
# tests/cli, tests/golden and ../shared/data of that kind.
# Usage: scripts/fuzz_all.sh [SECONDS_PER_TARGET=60] [TARGET...]
# Env: FUZZ_DIR (default build-fuzz), BUILD_DIR (default build), FUZZ_SEED
# (libFuzzer's -seed: a fixed seed replays the same mutations on the same
# corpus, as the ctest smoke does; unset, each run draws its own).
# Exit: 0 every target clean, 1 a target failed, 4 no clang++ or no build.
set -u
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
out=${FUZZ_DIR:-build-fuzz}
build=${BUILD_DIR:-build}
own_targets="gltf blockmap classes camera touched classtable rendermeta atlasmeta png exr"
all_targets="obj ply stl pagefile $([ -f scripts/fuzz_vdb.sh ] && echo vdb) $own_targets"
targets=${*:-$all_targets}
command -v clang++ >/dev/null || { echo "fuzz_all.sh: needs clang++ (apt-get install clang)" >&2; exit 4; }
mkdir -p "$out"

# The instrumented sources of a target (beside tests/fuzz/fuzz_NAME.cpp).
sources_of() {
  case $1 in
    obj) echo formats/mesh/obj_reader.cpp formats/mesh/mesh_input.cpp formats/mesh/polygon_triangulation.cpp formats/mesh/texture_image.cpp ;;
    ply) echo formats/mesh/ply_reader.cpp formats/mesh/mesh_input.cpp formats/mesh/polygon_triangulation.cpp ;;
    stl) echo formats/mesh/stl_reader.cpp formats/mesh/mesh_input.cpp ;;
    gltf) echo formats/mesh/gltf_reader.cpp formats/mesh/gltf_json_check.cpp formats/mesh/gltf_draco.cpp formats/mesh/gltf_meshopt.cpp formats/mesh/gltf_images.cpp formats/mesh/texture_image.cpp tests/fuzz/tinygltf_impl.cpp ;;
    blockmap) echo formats/vdb/blockmap_json.cpp ;;
    classes) echo formats/mesh/classes_json.cpp formats/scene/class_table_json.cpp ;;
    camera) echo formats/core/camera_json.cpp ;;
    touched) echo formats/image/touched_json.cpp formats/core/json_fields.cpp ;;
    classtable) echo formats/scene/class_table_json.cpp ;;
    rendermeta) echo formats/image/render_meta.cpp formats/core/camera_json.cpp formats/core/json_fields.cpp ;;
    atlasmeta) echo formats/image/atlas_meta.cpp ;;
    png) echo formats/image/image_png.cpp formats/mesh/png_fast_decode.cpp formats/image/render_meta.cpp formats/image/atlas_meta.cpp ;;
    exr) echo formats/image/image_exr.cpp formats/image/render_meta.cpp formats/image/atlas_meta.cpp ;;
  esac
}

# Compiles each source once into $out/obj (again only when it or a header of
# the repository is newer than its object), then links the target.
compile() {
  local src=$1 obj=$out/obj/${1//\//_}.o
  if [ ! -f "$obj" ] || [ -n "$(find "$src" formats libvox tests/fuzz -name '*.h' -newer "$obj" -print -quit 2>/dev/null)" ] ||
     [ "$src" -nt "$obj" ]; then
    clang++ -std=c++20 -O1 -g -fsanitize=fuzzer-no-link,address,undefined -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION \
      -I. -I/usr/include/Imath -I/usr/include/OpenEXR \
      -I/usr/include/stb -c "$src" -o "$obj" || return 4
  fi
  echo "$obj"
}

build_target() {
  local name=$1 objs="" src obj
  [ -f "$build/libvox.a" ] || { echo "fuzz_all.sh: no $build/libvox.a; build vox first (BUILD_DIR)" >&2; return 4; }
  mkdir -p "$out/obj"
  for src in tests/fuzz/fuzz_$name.cpp $(sources_of "$name"); do
    obj=$(compile "$src") || return 4
    objs+="$obj "
  done
  local libs
  libs=$(sed -n '/^build bin\/vox_unit_tests /,/LINK_LIBRARIES/p' "$build/build.ninja" | sed -n 's/^ *LINK_LIBRARIES = //p' |
         tr ' ' '\n' | grep -v -e gtest -e '^$' | sed "s|^lib\(vox[a-z]*\)\.a$|$build/lib\1.a|" | tr '\n' ' ')
  # shellcheck disable=SC2086
  clang++ -fsanitize=fuzzer,address,undefined $objs $libs -lstb -o "$out/fuzz_$name"
}

# Seeds: the committed ones, and the project's small inputs of the kind.
seed_target() {
  local name=$1 corpus=$out/corpus-$1 f
  mkdir -p "$corpus"
  cp tests/fuzz/seeds/"$name"/* "$corpus/" 2>/dev/null
  local globs=""
  case $name in
    obj|ply|stl) globs="tests/cli/*.$name ../shared/data/*/*.$name" ;;
    gltf) globs="tests/cli/*.gltf tests/cli/*.glb ../shared/data/gltf/*/*.gltf ../shared/data/gltf/*/*.glb" ;;
    blockmap) globs="tests/cli/map*.json" ;;
    png) globs="tests/golden/*/*.png tests/cli/*.png" ;;
    exr) globs="tests/golden/*/*.exr tests/cli/*.exr" ;;
  esac
  for f in $globs; do
    [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 50000 ] && cp "$f" "$corpus/"
  done
  return 0
}

# Runs a libFuzzer binary; its log is $out/log-NAME.txt.
run_target() {
  local name=$1
  mkdir -p "$out/artifacts-$name"
  nice -n 10 "$out/fuzz_$name" -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
    ${FUZZ_SEED:+-seed="$FUZZ_SEED"} -artifact_prefix="$out/artifacts-$name/" "$out/corpus-$name" >"$out/log-$name.txt" 2>&1
}

table=""
failed=0
for name in $targets; do
  start=$(date +%s)
  rc=0
  case $name in
    pagefile) FUZZ_DIR=$out scripts/fuzz_pagefile.sh "$seconds" >"$out/log-$name.txt" 2>&1 || rc=$? ;;
    vdb) FUZZ_DIR=$out scripts/fuzz_vdb.sh "$seconds" >"$out/log-$name.txt" 2>&1 || rc=$? ;;
    *) if build_target "$name" >"$out/build-$name.txt" 2>&1; then seed_target "$name"; run_target "$name" || rc=$?
       else rc=4; cp "$out/build-$name.txt" "$out/log-$name.txt"; fi ;;
  esac
  took=$(( $(date +%s) - start ))
  runs=$(grep -o '^Done [0-9]* runs' "$out/log-$name.txt" | tail -1 | awk '{print $2}')
  [ -n "$runs" ] || runs=$(grep -o '^#[0-9]*' "$out/log-$name.txt" | tail -1 | tr -d '#')
  if [ "$rc" = 0 ]; then result=clean
  elif [ "$rc" = 4 ]; then result="build failed ($out/log-$name.txt)"; failed=1
  else result="FAILED ($out/log-$name.txt, artifacts in $out/artifacts-$name)"; failed=1; fi
  table+=$(printf '%-11s %12s %8s  %s' "$name" "${runs:-?}" "$took" "$result")$'\n'
  printf '%-11s %12s %8s  %s\n' "$name" "${runs:-?}" "$took" "$result" >&2
done
printf '%-11s %12s %8s  %s\n' target runs seconds result
printf '%s' "$table"
exit $failed
