// libFuzzer target for the OBJ parser: any input must either parse or throw
// vox::Error; crashes, hangs, sanitizer reports and other exceptions are bugs.
// Build and run: scripts/fuzz.sh obj [SECONDS]
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/mesh/mesh_input.h"
#include "libvox/core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> warnings;
  vox::MeshReadOptions options;
  options.dropInvalid = size % 2 == 0;  // exercise both NaN paths
  try {
    vox::Mesh m = vox::parseObj(reinterpret_cast<const char*>(data), size, "fuzz.obj", options, warnings, "/nonexistent-fuzz-dir");
    for (const auto& t : m.triangles)
      for (uint32_t i : t)
        if (i >= m.positions.size()) __builtin_trap();  // every index must be valid
  } catch (const vox::Error&) {
  }
  return 0;
}
