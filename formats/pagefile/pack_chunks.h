// Cutting a scene (and its mips) into C^3 chunks for a page file
// (formats/pagefile/PAGEFILE.md; the container is formats/pagefile/pagefile.h,
// the payload layouts formats/pagefile/layouts.h).
//
// Per occupied voxel a chunk carries the summary bytes (cls, conf, obs, mrg of
// libvox/core/summary_bytes.h), the sRGB8 colour when the scene has colour, and the
// surface flag when the scene has interior voxels. Chunks are computed
// independently (in parallel) and written in (level, Morton key) order, so the
// file is byte-identical at any thread count.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "formats/pagefile/pagefile.h"
#include "libvox/scene/scene.h"

namespace vox {

/// How to pack; the defaults are those of `vox pack-chunks`.
struct PackSettings {
  uint32_t chunkSide = 16;    // 8, 16 or 32 (pagefile::kMinChunkLog2 .. kMaxChunkLog2)
  uint32_t alignment = 4096;  // power of two, 8..65536 (pagefile::kMinAlignLog2 .. kMaxAlignLog2)
  pagefile::Layout layout = pagefile::Layout::Bricks;
  unsigned threads = 1;       // 0: every core; any count gives the same bytes
  std::string mipOccupancy;   // recorded in the metadata ("any", "majority", "from FILE"), empty without mips
};

struct PackResult {
  std::vector<uint8_t> bytes;  // the whole file
  struct Level {
    int level = 0;
    uint64_t chunks = 0, fullChunks = 0, voxels = 0, payloadBytes = 0;
  };
  std::vector<Level> levels;
};

/// Packs `levels` (level 0 first, then 1, 2, ... as buildMipPyramid makes them).
/// Throws vox::Error (Usage, with the Setting to change) for an unsupported
/// chunk side, alignment or layout, and for a scene the layout cannot hold
/// (columns: a coloured interior voxel).
PackResult packChunks(const std::vector<const Scene*>& levels, const PackSettings& settings);

}  // namespace vox
