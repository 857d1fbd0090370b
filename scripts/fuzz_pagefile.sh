#!/bin/sh
# Builds and runs the libFuzzer target of the page file reader
# (clang, -fsanitize=fuzzer,address,undefined). Seeds are small page files made
# by the vox binary of BUILD_DIR (default build) when it exists.
# Usage: scripts/fuzz_pagefile.sh [SECONDS=60]   (corpus in $FUZZ_DIR/corpus-pagefile)
# Env: FUZZ_DIR (default build-fuzz), BUILD_DIR (default build).
set -eu
cd "$(dirname "$0")/.."
seconds=${1:-60}
out=${FUZZ_DIR:-build-fuzz}
corpus=$out/corpus-pagefile
mkdir -p "$corpus"
command -v clang++ >/dev/null || { echo "fuzz_pagefile.sh: needs clang++ (apt-get install clang)" >&2; exit 4; }
# The container, every layout (formats/pagefile/*_layout.cpp: a layout's encoder
# and decoder are one file) and the metadata reader, with what they use from
# libvox/core and formats/scene.
clang++ -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION -I. \
  tests/fuzz/fuzz_pagefile.cpp formats/pagefile/pagefile.cpp formats/pagefile/layouts.cpp \
  formats/pagefile/*_layout.cpp formats/pagefile/pagefile_meta.cpp formats/scene/scene_meta.cpp formats/scene/class_table_json.cpp formats/core/file_util.cpp \
  libvox/core/crc32c.cpp libvox/core/summary_bytes.cpp libvox/core/color.cpp libvox/core/classes.cpp \
  -o "$out/fuzz_pagefile"
vox=${BUILD_DIR:-build}/bin/vox
if [ -x "$vox" ] && [ -z "$(ls -A "$corpus")" ]; then
  tmp=$(mktemp -d)
  "$vox" voxelize demo:hamlet --res 12 -o "$tmp/h.vdb" --quiet
  "$vox" pack-chunks "$tmp/h.vdb" -o "$corpus/h8.vpk" --chunk 8 --align 8 --mips --quiet
  "$vox" pack-chunks "$tmp/h.vdb" -o "$corpus/h16.vpk" --chunk 16 --align 16 --quiet
  rm -rf "$tmp"
fi
# Seeds of every layout `vox pack-chunks --layout` knows (added to an existing
# corpus too, for layouts it has no seed of yet).
if [ -x "$vox" ]; then
  layouts=$("$vox" pack-chunks --help | sed -n 's/.*--layout \([a-z|]*\)=.*/\1/p' | tr '|' ' ')
  tmp=$(mktemp -d)
  for layout in $layouts; do
    [ -e "$corpus/${layout}32.vpk" ] && continue
    [ -e "$tmp/h.vdb" ] || "$vox" voxelize demo:hamlet --res 12 -o "$tmp/h.vdb" --quiet
    "$vox" pack-chunks "$tmp/h.vdb" -o "$corpus/${layout}8.vpk" --layout $layout --chunk 8 --align 8 --mips --quiet
    "$vox" pack-chunks "$tmp/h.vdb" -o "$corpus/${layout}16.vpk" --layout $layout --chunk 16 --align 8 --quiet
    "$vox" pack-chunks "$tmp/h.vdb" -o "$corpus/${layout}32.vpk" --layout $layout --chunk 32 --align 8 --quiet
  done
  rm -rf "$tmp"
fi
"$out/fuzz_pagefile" -max_total_time="$seconds" -max_len=65536 -timeout=10 "$corpus"
