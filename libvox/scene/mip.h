// LOD pyramids: level n of a scene has voxels 2^n wide (formats/scene/SCENE.md, "Pyramids").
//
// Level n is reduced from level n-1, one 2x2x2 block of children per voxel:
//   * occupancy: `Any` — occupied when at least one child is (conservative, for
//     empty-space skipping); `Majority` — occupied when at least half of the
//     children that lie inside the level n-1 domain are occupied (a tie keeps the
//     voxel, so a one-voxel wall survives); children outside the domain (odd
//     dims) do not count.
//   * votes: per class, the exact sum over the occupied children, in 64-bit
//     integers, then saturated at kMaxVotesPerClass (2^31-1) because the scene
//     format stores int32 counts. With Majority, a voxel that is dropped keeps no
//     votes (its votes are not pushed elsewhere).
//   * colour: the plain average over the children that have a colour (empty and
//     uncoloured interior children do not darken it), summed in double in a
//     fixed child order; a voxel none of whose children has colour has none.
//   * surface flag: OR of the children's flags.
// Placement: dims = ceil(dims / 2) per axis, voxel size x 2, same origin, so
// level n has dims ceil(dims0 / 2^n) and voxel size voxelSize0 * 2^n; the class
// table, sources and block-world placement are kept; mipLevel = n.
//
// Deterministic: every coarse 8^3 leaf is computed from its children alone, in
// a fixed order, so the result does not depend on the thread count.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libvox/core/progress.h"
#include "libvox/scene/mip_blocks.h"  // MipOccupancy, mipDims, maxMipLevels, coarserMipHeader
#include "libvox/scene/scene.h"

namespace vox {

/// One level coarser than `fine` (fine.header().mipLevel + 1).
Scene reduceScene(const Scene& fine, MipOccupancy occupancy, unsigned threads = 1);

/// Occupied voxels whose surface flag is set (a quick count on the trees).
uint64_t surfaceCount(const Scene& scene);

struct MipSettings {
  MipOccupancy occupancy = MipOccupancy::Any;
  /// Levels to build (1..maxMipLevels). 0 = automatic: stop at one voxel, or
  /// after the first level with at most one occupied voxel (further levels
  /// would repeat it), or at an empty level (Majority can empty a sparse scene).
  int levels = 0;
  unsigned threads = 1;
  /// Called after each level with (level, the new scene, seconds it took).
  std::function<void(int, const Scene&, double)> onLevel;
};

/// Levels 1..n of `base` (a level-0 scene or any level: the first result is one
/// level coarser than `base`). Throws vox::Error (Usage) when `levels` exceeds
/// maxMipLevels of base's dims.
std::vector<Scene> buildMipPyramid(const Scene& base, const MipSettings& settings);

/// How a mip level differs from a direct voxelization at the same placement.
struct MipComparison {
  uint64_t mipVoxels = 0, referenceVoxels = 0;
  uint64_t both = 0, onlyMip = 0, onlyReference = 0;
  uint64_t classDisagree = 0;  // among `both`: argmax class (ties: lowest id) differs
  double iou = 1.0;            // both / (both + onlyMip + onlyReference); 1 when both are empty
  double classDisagreement = 0.0;  // classDisagree / both (0 when both == 0)
};

/// Returns an empty string when `a` and `b` have the same placement (dims,
/// voxel size, origin), else what differs.
std::string placementMismatch(const SceneHeader& a, const SceneHeader& b);

/// Compares occupancy and winning class voxel by voxel. Class ids are compared
/// by name through the two class tables (a class missing in one counts as a
/// disagreement).
MipComparison compareWithReference(const Scene& mip, const Scene& reference);

}  // namespace vox
