// LOD pyramid levels reduced on voxel blocks (libvox/mesh/voxel_blocks.h),
// without OpenVDB: what `vox mip` runs in the light module (vox-pack.so,
// docs/startup.md), which reads the scene as leaves and writes the pyramid
// with the direct writer (formats/scene/scene_vdb_direct.h).
//
// The rules are mip.h's (occupancy any or majority, votes summed exactly and
// saturated, colour the average of the coloured children in double in the
// children's voxel order, surface OR-ed, placement ceil(dims / 2) and voxel
// size x 2); a level reduced here holds exactly the voxels, votes, colours
// and flags reduceScene gives (tests/cli/lightmip_test.sh compares the files).
//
// This header also holds the parts of mip.h that need no scene trees (the
// occupancy rule's names, level dims and placement), so that both reductions
// share them.
#pragma once

#include <memory>
#include <vector>

#include "libvox/core/scene_header.h"
#include "libvox/mesh/voxel_blocks.h"

namespace vox {

enum class MipOccupancy { Any, Majority };

inline const char* mipOccupancyName(MipOccupancy m) { return m == MipOccupancy::Any ? "any" : "majority"; }

/// Dims of level n of a scene with level-0 dims `d`: ceil(d / 2^n) per axis.
Dims mipDims(Dims d, int level);

/// The number of levels after which the grid is one voxel: ceil(log2(max axis)).
int maxMipLevels(Dims d);

/// The header of the level one coarser than a scene with header `fine`: dims
/// halved (rounded up), voxel size doubled, same origin, classes and sources,
/// mipLevel + 1, a region part's box the coarse voxels its voxels reduce into.
SceneHeader coarserMipHeader(const SceneHeader& fine);

/// One level of a scene as blocks.
struct MipBlocksLevel {
  SceneHeader header;
  /// Any order, no two at one origin, every block with an occupied voxel, no
  /// run votes (materializeRuns), votes and colours only at occupied voxels.
  std::vector<std::unique_ptr<VoxelBlock>> blocks;
  /// The scene has a colour grid: its levels keep one, even an empty one.
  bool colorGrid = false;

  uint64_t occupiedCount() const;
};

/// One level coarser than `fine` (mip.h's reduceScene on blocks). Blocks are
/// reduced on `threads` threads, each from its children alone: the result does
/// not depend on the thread count.
MipBlocksLevel reduceBlocks(const MipBlocksLevel& fine, MipOccupancy occupancy, unsigned threads = 1);

}  // namespace vox
