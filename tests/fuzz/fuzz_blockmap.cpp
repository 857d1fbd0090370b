// libFuzzer target of the block-map reader (formats/vdb/blockmap_json.cpp,
// parseBlockMap: map.json text to a Scene). The whole parse is fuzzed, Scene
// included: the scene is vox's own voxel store (libvox/scene, linked from the
// build, not instrumented), so the target needs no OpenVDB headers. A grid of
// 64 x 48 x 64 (the format's default) or, for every other input, 8 x 8 x 8 so
// the out-of-grid checks are reached often.
#include <string>

#include "formats/vdb/blockmap_json.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

VOX_FUZZ_TARGET(blockmap) {
  vox::BlockMapOptions options;
  if (size % 2) options.gridSize = {8, 8, 8};
  try {
    vox::parseBlockMap(std::string(reinterpret_cast<const char*>(data), size), "fuzz-map.json", options);
  } catch (const vox::Error&) {
  }
  return 0;
}
