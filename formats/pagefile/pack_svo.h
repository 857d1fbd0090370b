// The `svo` page-file layout (formats/pagefile/PAGEFILE.md, seeds 001/003): per chunk a
// pointerless octree of 64-bit nodes over 8^3 bricks, breadth first; every node
// owns one brick of the brick pool (leaves: the voxels; inner nodes: a mip
// brick, the node's region reduced to 8^3 the way `vox mip --occupancy any`
// reduces a scene), and the per-voxel data of the bricks' occupied voxels.
#pragma once

#include <cstdint>
#include <vector>

#include "formats/pagefile/pack_chunks.h"

namespace vox::packdetail {

/// The payload of one chunk. `chunk.withVotes` must be set (mip bricks sum votes).
std::vector<uint8_t> encodeSvo(const ChunkVoxels& chunk, uint32_t flags);

}  // namespace vox::packdetail
