// libFuzzer target of the PNG reader (formats/image/image_png.cpp,
// readPngMemory: the decoder readPng shares) and of the text entries info,
// diff and verify-bijection read from it: `vox:atlas` (atlas_meta.cpp) and
// `vox:canonical` (render_meta.cpp). A decoded image holds exactly
// width x height x channels samples.
#include <string>

#include "formats/image/atlas_meta.h"
#include "formats/image/png_memory.h"
#include "formats/image/render_meta.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

VOX_FUZZ_TARGET(png) {
  try {
    const vox::Image image = vox::readPngMemory(data, size, "fuzz.png");
    VOX_FUZZ_REQUIRE(image.pixels.size() == image.rowBytes() * image.height);
    const std::string atlas = image.textValue(vox::kAtlasTextKey);
    if (!atlas.empty()) {
      try {
        vox::atlasInfoFromJson(atlas, "fuzz.png: vox:atlas");
      } catch (const vox::Error&) {
      }
    }
    if (const auto meta = vox::readRenderMeta(image, "fuzz.png")) vox::renderCamera(*meta, image, "fuzz.png", "");
  } catch (const vox::Error&) {
  }
  return 0;
}
