#include "tools/cli/alloc_tuning.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>

namespace voxcli {

void tuneAllocatorForShortRun() {
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

}  // namespace voxcli
