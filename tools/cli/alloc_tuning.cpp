#include "tools/cli/alloc_tuning.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>

namespace voxcli {

namespace {
constexpr int kHeapPad = 256 << 20;  // address space the heap grows by, advised for huge pages
void* volatile heapSpacer = nullptr;  // see tuneAllocatorForShortRun (volatile: the store is kept)
}  // namespace

void tuneAllocatorForShortRun() {
  if (std::getenv("VOX_DEFAULT_MALLOC")) return;  // to measure the difference
  mallopt(M_ARENA_MAX, 1);
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_TOP_PAD, kHeapPad);
  // Grow the heap now (a block larger than any free space), then advise it.
  constexpr size_t kProbe = size_t(1) << 20;
  void* probe = std::malloc(kProbe);
  if (!probe) return;
  const uintptr_t start = reinterpret_cast<uintptr_t>(probe);
  // Advise from the first 2 MB boundary past the probe and the header glibc
  // wrote after it: a 2 MB range with any 4 KB page in it (that header,
  // written before the advice) never gets a huge page.
  const uintptr_t huge = uintptr_t(2) << 20;
  const uintptr_t from = (start + kProbe + 4096 + huge - 1) & ~(huge - 1);
  const uintptr_t to = reinterpret_cast<uintptr_t>(sbrk(0)) & ~(huge - 1);
  std::free(probe);
  if (to <= from) return;
  madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);
  // The freed probe rejoined the top of the heap, below `from`, where pages
  // are 4 KB: the bake's first MBs (the mesh) would fault in there page by
  // page, each fault costing several microseconds on a VM. A spacer up to
  // `from` (address space only: untouched past its header, never freed)
  // starts the top at the advised range. It is kept in a volatile global: a
  // malloc whose result goes unused may be removed by the compiler.
  heapSpacer = std::malloc(from - start - 64);
}

void growAdvisedHeap(uint64_t expectedPeakBytes) {
  if (std::getenv("VOX_DEFAULT_MALLOC")) return;
  // mallopt takes ints; past this the rest of the heap grows in 4 KB pages as before.
  constexpr uint64_t kMaxAdvised = uint64_t(1536) << 20;
  constexpr uint64_t kShortRunPad = uint64_t(kHeapPad);  // what tuneAllocatorForShortRun advised
  const uint64_t target = std::min(expectedPeakBytes, kMaxAdvised);
  if (target <= kShortRunPad) return;
  // Keep what is grown (no trimming back to the pad when a large block is
  // freed), then grow the heap once by `target`: a block just larger than the
  // free space at its top makes glibc extend it by the block and the pad.
  mallopt(M_TRIM_THRESHOLD, int(target + kShortRunPad));
  mallopt(M_TOP_PAD, int(target));
  const uintptr_t before = reinterpret_cast<uintptr_t>(sbrk(0));
  void* probe = std::malloc(mallinfo2().keepcost + (size_t(1) << 20));
  const uintptr_t after = reinterpret_cast<uintptr_t>(sbrk(0));
  std::free(probe);  // back into the top of the heap, which now reaches `after`
  mallopt(M_TOP_PAD, kHeapPad);
  if (!probe || after <= before) return;  // grown elsewhere (mmap), or not at all: nothing to advise
  const uintptr_t from = (before + 4095) & ~uintptr_t(4095);  // madvise takes whole pages
  if (after > from) madvise(reinterpret_cast<void*>(from), after - from, MADV_HUGEPAGE);
}

}  // namespace voxcli
