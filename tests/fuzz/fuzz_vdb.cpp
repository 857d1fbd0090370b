// libFuzzer target for the whole .vdb read path: the structure walk
// (formats/vdb/vdb_structure.h) and, through CheckedVdbFile, OpenVDB's reader
// as voxbake drives it for scenes and pyramids (readPyramidVdb, which reads a
// scene file whole, and readPyramidMetadata) and foreign level sets and fog
// volumes (readVdbGridAsScene). Any input must read or throw vox::Error; a
// crash, a sanitizer report, a leak, a hang or another exception is a bug.
// Build and run: scripts/fuzz_vdb.sh [SECONDS]
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "formats/vdb/pyramid_vdb.h"
#include "formats/vdb/vdb_grid_input.h"
#include "libvox/core/error.h"

namespace {

/// The readers take paths: each input is written to one file per process.
const std::string& inputPath() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir && *dir ? dir : "/tmp") + "/fuzz_vdb." + std::to_string(getpid()) + ".vdb";
  }();
  return path;
}

template <typename Fn>
void expectVoxErrorOnly(Fn&& fn) {
  try {
    fn();
  } catch (const vox::Error& e) {
    if (e.kind != vox::ErrorKind::BadInput && e.kind != vox::ErrorKind::Usage) {
      std::fprintf(stderr, "unexpected error kind: %s\n", e.what());
      std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = inputPath();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(data, 1, size, f) != size || std::fclose(f) != 0) std::abort();
  // readPyramidVdb reads a scene file whole (every grid, then level 0's checks,
  // then each level's), so it covers readSceneVdb; the occupancy-only read is
  // the same path with fewer grids.
  expectVoxErrorOnly([&] { vox::readPyramidMetadata(path); });
  expectVoxErrorOnly([&] { vox::readPyramidVdb(path); });
  // Without a threshold (level sets read) and with one (fog volumes read).
  for (const bool fog : {false, true})
    expectVoxErrorOnly([&] {
      vox::VdbGridInputOptions o;
      o.resolution = 12;
      if (fog) o.threshold = 0.5;
      vox::readVdbGridAsScene(path, o);
    });
  return 0;
}
