// The memory a fusion (`vox fuse`, fuse.h) plans for: the estimate the memory
// guard (libvox/core/memory_budget.h) checks before the work.
//
// Known before the work: the grid, the views' count and size, the threads,
// the free-count scope. Not known: how many voxels the views vote for, which
// is bounded by the pixels and, for a scene seen from outside, of the order
// of its surface; the estimate takes min(pixels, XY + YZ + XZ) (three grid
// cross-sections). Parts, in bytes (calibrated with /usr/bin/time peaks,
// docs/bench-fuse.md "Memory"):
//   * decoding: the views decoded ahead, one per thread, after the first
//     (read before the estimate: in the caller's resident memory, counted
//     once): 24 bytes per pixel (its arrays: depth 8, class 1, face 1,
//     colour 4, weight 2, plus the decoded images: float depth 4, label and
//     normal).
//   * kept views: the views' walked pixels the second pass reuses
//     (FreeScope::Voted, FuseWalks: 10 bytes per walked pixel), up to
//     `keptBudget`; the first view's stand for every view's.
//   * votes: per worker piece and once more for the merge and the scene,
//     64 bytes per voted voxel (the vote table at load <= 1/2 with its growth
//     copy, and the free bricks of the tracked voxels).
//   * free counts (FreeScope::All): every voxel a ray crosses may get a count:
//     4 bytes per voxel of the grid (its 8^3 bricks of uint32), per piece.
#pragma once

#include <cstdint>

#include "libvox/core/memory_budget.h"
#include "libvox/core/types.h"
#include "libvox/render/fuse.h"

namespace vox {

struct FuseMemoryInputs {
  Dims dims;
  uint64_t views = 0;
  uint64_t pixelsPerView = 0;  // width x height of a view (the largest, when they differ)
  unsigned threads = 1;
  bool countFree = true;
  FreeScope freeScope = FreeScope::Voted;
  uint64_t keptBudget = 0;  // what the second pass may keep of the views (0 = nothing kept)
  uint64_t keptBytesPerView = 0;  // FuseWalks::bytes() of one view (the first's)
};

/// The parts above, without the process's resident memory (the caller adds it,
/// measured with the first view read).
MemoryEstimate estimateFuseMemory(const FuseMemoryInputs& in);

}  // namespace vox
