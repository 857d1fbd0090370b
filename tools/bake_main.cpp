// The light bake module's entry point (vox-bake.so): `vox voxelize` for meshes,
// without OpenVDB in the process (tools/voxelize_mesh.h says why and how the
// launcher chooses between this module and vox-cmds.so).
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdlib>

#include "libvox/version.h"
#include "tools/commands.h"
#include "tools/dispatch.h"
#include "tools/voxelize_mesh.h"

namespace {

// A bake is a short process that touches tens to hundreds of MB of fresh heap
// (mesh arrays, 2 KB vote blocks). With glibc's defaults that memory arrives
// 4 KB page by page (big arrays through separate mmaps, a thread arena per
// thread), and the page faults were a third of a 256^3 surface bake on the
// benchmark VM (~5000 faults). So, for this process only: one arena, big
// arrays from the heap, the heap grown in 256 MB steps of address space, and
// that range marked for transparent huge pages. Resident memory still counts
// only what is touched (in 2 MB pages: a few MB more at most).
void tuneAllocatorForBake() {
  if (std::getenv("VOX_DEFAULT_MALLOC")) return;  // to measure the difference
  mallopt(M_ARENA_MAX, 1);
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_TOP_PAD, 256 << 20);
  // Grow the heap now (a block larger than any free space), then advise it.
  void* probe = std::malloc(size_t(1) << 20);
  if (!probe) return;
  const uintptr_t huge = uintptr_t(2) << 20;
  const uintptr_t from = (reinterpret_cast<uintptr_t>(probe) + huge - 1) & ~(huge - 1);
  const uintptr_t to = reinterpret_cast<uintptr_t>(sbrk(0)) & ~(huge - 1);
  std::free(probe);
  if (to > from) madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int vox_bake_main(int argc, char** argv) {
  tuneAllocatorForBake();
  CLI::App app{voxcli::kRootDescription, "vox"};
  app.set_version_flag("-V,--version", vox::versionString());
  app.require_subcommand(1);
  std::vector<voxcli::Command> commands{voxcli::registerVoxelizeLight(app)};
  return voxcli::parseAndRun(app, commands, argc, argv);
}
