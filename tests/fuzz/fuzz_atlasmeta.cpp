// libFuzzer target of atlas metadata (formats/image/atlas_meta.cpp): the same
// text through the `vox:atlas` entry reader (atlasInfoFromJson) and the
// STEM.atlas.json sidecar reader (atlasSidecarFromJson).
#include <string>

#include "formats/image/atlas_meta.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

VOX_FUZZ_TARGET(atlasmeta) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    vox::atlasInfoFromJson(text, "fuzz.png: vox:atlas");
  } catch (const vox::Error&) {
  }
  try {
    vox::atlasSidecarFromJson(text, "fuzz.atlas.json");
  } catch (const vox::Error&) {
  }
  return 0;
}
