// libFuzzer target of the glTF read path: the spec-range check of the JSON
// (gltf_json_check.cpp), tinygltf's container parser (.gltf JSON and .glb,
// data-URI buffers and images) and the accessor and node walk of
// gltf_reader.cpp, and the KHR_draco_mesh_compression and
// EXT_meshopt_compression decodes (gltf_draco.cpp, gltf_meshopt.cpp; Debian's
// libdraco and libmeshoptimizer themselves are not instrumented; seeds
// draco_grid.glb, meshopt_box.glb), all from memory (readGltfMemory). An input starting with
// the GLB magic "glTF" is read as .glb, any other as .gltf. External URIs point
// into a directory that does not exist. Every triangle index must name a vertex.
#include <string>
#include <vector>

#include "formats/mesh/gltf_reader.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

VOX_FUZZ_TARGET(gltf) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const bool isBinary = bytes.compare(0, 4, "glTF") == 0;
  vox::MeshReadOptions options;
  options.dropInvalid = size % 2 == 0;            // both NaN paths
  options.ignoreMissingMaterials = size % 3 == 0;  // both missing-image paths
  std::vector<std::string> warnings;
  try {
    const vox::Mesh m = vox::readGltfMemory(bytes, isBinary ? "/nonexistent-fuzz-dir/fuzz.glb" : "/nonexistent-fuzz-dir/fuzz.gltf",
                                            isBinary, options, warnings);
    for (const auto& t : m.triangles)
      for (uint32_t i : t) VOX_FUZZ_REQUIRE(i < m.positions.size());
  } catch (const vox::Error&) {
  }
  return 0;
}
