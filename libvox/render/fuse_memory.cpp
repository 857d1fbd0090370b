#include "libvox/render/fuse_memory.h"

#include <algorithm>

namespace vox {

MemoryEstimate estimateFuseMemory(const FuseMemoryInputs& in) {
  MemoryEstimate e;
  const double pixels = double(in.pixelsPerView);
  const double threads = double(std::max(1u, in.threads));
  // The first view is read before the estimate (the caller's resident
  // memory holds it); the views after it are decoded `threads` at a time.
  if (in.views > 1) e.add("decoded views", std::min(threads, double(in.views - 1)) * pixels * 24.0);
  if (in.countFree && in.freeScope == FreeScope::Voted)
    e.add("kept views", std::min(double(in.keptBudget), double(in.views) * double(in.keptBytesPerView)));
  const double X = double(in.dims.x), Y = double(in.dims.y), Z = double(in.dims.z);
  const double voted = std::min({double(in.views) * pixels, X * Y + Y * Z + X * Z, X * Y * Z});
  e.add("votes", (threads + 1) * voted * 64.0);
  if (in.countFree && in.freeScope == FreeScope::All) e.add("free counts", threads * X * Y * Z * 4.0);
  return e;
}

}  // namespace vox
