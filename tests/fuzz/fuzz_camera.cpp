// libFuzzer target of camera files (formats/core/camera_json.cpp,
// parseCameraJson): the block-map format's metadata.json, one look-at camera,
// or {"cameras": [...]}. Every other input is read with a size override.
#include <string>

#include "formats/core/camera_json.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

VOX_FUZZ_TARGET(camera) {
  std::optional<std::pair<uint32_t, uint32_t>> sizeOverride;
  if (size % 2) sizeOverride = std::make_pair(uint32_t(64), uint32_t(48));
  try {
    vox::parseCameraJson(std::string(reinterpret_cast<const char*>(data), size), "fuzz-camera.json", sizeOverride);
  } catch (const vox::Error&) {
  }
  return 0;
}
