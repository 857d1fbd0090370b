#!/bin/sh
# Builds and runs a libFuzzer target (clang, -fsanitize=fuzzer,address,undefined)
# for one of the hand-written parsers: obj, ply or stl.
# Usage: scripts/fuzz.sh obj|ply|stl [SECONDS=60]   (corpus in build-fuzz/corpus-NAME)
set -eu
cd "$(dirname "$0")/.."
name=$1
seconds=${2:-60}
out=build-fuzz
mkdir -p "$out/corpus-$name"
command -v clang++ >/dev/null || { echo "fuzz.sh: needs clang++ (apt-get install clang)" >&2; exit 4; }
srcs="tests/fuzz/fuzz_$name.cpp formats/mesh/mesh_input.cpp formats/mesh/obj_reader.cpp formats/mesh/stl_reader.cpp formats/mesh/ply_reader.cpp formats/core/file_util.cpp libvox/mesh/mesh.cpp"
# glTF is not fuzzed here (tinygltf's JSON parser is not ours); a stub keeps mesh_input linking.
cat > "$out/gltf_stub.cpp" <<'STUB'
#include "formats/mesh/gltf_reader.h"
#include "libvox/core/error.h"
namespace vox {
Mesh readGltf(const std::string& path, const MeshReadOptions&, std::vector<std::string>&) {
  throwBadInput(path + ": glTF is not part of this fuzz build");
}
}  // namespace vox
STUB
clang++ -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -I. $srcs "$out/gltf_stub.cpp" -lstb -o "$out/fuzz_$name"
# Seeds: the project's small test inputs of that kind.
for f in tests/cli/*.$name ../shared/data/*/*.$name; do [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 200000 ] && cp "$f" "$out/corpus-$name/" || true; done
"$out/fuzz_$name" -max_total_time="$seconds" -max_len=65536 -timeout=10 "$out/corpus-$name"
