// libFuzzer target of the EXR reader (formats/image/image_exr.cpp, readExr)
// and the text entries read from it (`vox:atlas`, `vox:canonical`). OpenEXR
// reads files, so each input is written to one scratch file first (in
// TMPDIR, else /dev/shm, else /tmp: on the disk of the test machine /tmp gave
// 40 runs/s, /dev/shm 130); slower than an in-memory reader but exactly the
// path vox info, diff and verify-bijection take.
#include <unistd.h>

#include <cstdio>
#include <string>

#include "formats/image/atlas_meta.h"
#include "formats/image/image.h"
#include "formats/image/render_meta.h"
#include "libvox/core/error.h"
#include "tests/fuzz/fuzz_entry.h"

namespace {
std::string scratchPath() {
  const char* dir = std::getenv("TMPDIR");
  const bool shm = access("/dev/shm", W_OK) == 0;
  return std::string(dir && *dir ? dir : shm ? "/dev/shm" : "/tmp") + "/vox-fuzz-exr-" + std::to_string(getpid()) + ".exr";
}
}  // namespace

VOX_FUZZ_TARGET(exr) {
  static const std::string path = scratchPath();
  {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) return 0;
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    const vox::Image image = vox::readExr(path);
    VOX_FUZZ_REQUIRE(image.pixels.size() == image.rowBytes() * image.height);
    const std::string atlas = image.textValue(vox::kAtlasTextKey);
    if (!atlas.empty()) {
      try {
        vox::atlasInfoFromJson(atlas, "fuzz.exr: vox:atlas");
      } catch (const vox::Error&) {
      }
    }
    if (const auto meta = vox::readRenderMeta(image, "fuzz.exr")) vox::renderCamera(*meta, image, "fuzz.exr", "");
  } catch (const vox::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}
