// A scene's occupied voxels visited in parallel, in pieces of whole leaves.
#pragma once

#include <cstddef>
#include <functional>

#include "libvox/scene/scene.h"

namespace vox {

/// Visits the voxels of Scene::forEachVoxel split into `pieces` runs of whole
/// 8^3 leaves, on up to `threads` workers (0 = every core): fn(view, piece) is
/// called for the voxels of piece p in forEachVoxel's order, and the pieces,
/// taken in index order, are forEachVoxel's order.
///
/// Thread safety: `fn` runs concurrently with itself. Keep per-piece results
/// and merge them in piece order, or write only what a voxel owns (an atlas
/// texel). pieces == 0 means one piece per worker: use it only when the merged
/// result does not depend on where the pieces end (sums, minima, maxima).
/// Defined in scene.cpp beside forEachVoxel, whose leaf walk it shares.
void forEachVoxelInPieces(const Scene& scene, unsigned threads, size_t pieces,
                          const std::function<void(const VoxelView&, size_t piece)>& fn);

}  // namespace vox
