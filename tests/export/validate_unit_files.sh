#!/bin/sh
# Runs the glTF writer's unit tests keeping the files they write, then checks
# every one with the Khronos glTF validator (0 errors, 0 warnings).
# Usage: validate_unit_files.sh UNIT_TEST_BINARY TOOLS_DIR
set -eu
here=$(cd "$(dirname "$0")" && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
VOX_EXPORT_KEEP_DIR=$dir "$1" --gtest_filter='GltfWriter.*' >"$dir/gtest.log" 2>&1 || { cat "$dir/gtest.log"; exit 1; }
files=$(find "$dir" -name '*.glb' -o -name '*.gltf' | sort)
[ -n "$files" ] || { echo "no glTF file was kept" >&2; exit 1; }
# shellcheck disable=SC2086
NODE_PATH="$2/node_modules" node "$here/validate_gltf.mjs" $files
