// libFuzzer target of the `vox:canonical` entry of renders
// (formats/image/render_meta.cpp, parseRenderMeta), then the camera it gives
// for a 64 x 48 image (renderCamera), as vox diff and verify-bijection use it.
#include <string>

#include "formats/image/render_meta.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

VOX_FUZZ_TARGET(rendermeta) {
  try {
    const vox::RenderMeta meta = vox::parseRenderMeta(std::string(reinterpret_cast<const char*>(data), size), "fuzz.png");
    vox::Image image;
    // The entry's own size (another is refused before the matrices are read).
    image.width = meta.width;
    image.height = meta.height;
    image.channels = 4;
    vox::renderCamera(meta, image, "fuzz.png", "");
  } catch (const vox::Error&) {
  }
  return 0;
}
