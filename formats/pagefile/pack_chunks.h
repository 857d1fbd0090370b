// Cutting a scene (and its mips) into C^3 chunks for a page file
// (formats/pagefile/PAGEFILE.md; the byte format is formats/pagefile/pagefile.h).
//
// Per occupied voxel a chunk carries the summary bytes (cls, conf, obs, mrg of
// libvox/core/summary_bytes.h), the sRGB8 colour when the scene has colour, and the
// surface flag when the scene has interior voxels. Chunks are computed
// independently (in parallel) and written in (level, Morton key) order, so the
// file is byte-identical at any thread count.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/pagefile/pagefile.h"
#include "libvox/scene/scene.h"

namespace vox {

struct PackSettings {
  uint32_t chunkSide = 16;  // 8, 16 or 32
  uint32_t alignment = 4096;  // power of two, 8..65536
  pagefile::Layout layout = pagefile::Layout::Bricks;
  unsigned threads = 1;
  std::string mipOccupancy;  // recorded in the metadata ("any"/"majority"), empty without mips
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
/// Throws vox::Error (Usage) for an unsupported chunk side or alignment, and for
/// a scene the layout cannot hold (columns: a coloured interior voxel).
PackResult packChunks(const std::vector<const Scene*>& levels, const PackSettings& settings);

namespace packdetail {

/// One chunk's voxels, dense, at the chunk-local index k = x + C * (y + C * z)
/// (the bricks layout's order). Filled by packChunks, encoded by the layouts
/// (formats/pagefile/pack_svo.h, formats/pagefile/pack_columns.h).
struct ChunkVoxels {
  uint32_t side = 0;   // C
  uint32_t count = 0;  // occupied voxels
  std::vector<uint64_t> bits;  // C^3 / 64 words, bit k % 64 of word k / 64
  std::vector<std::array<uint8_t, 4>> summary;  // cls, conf, obs, mrg
  std::vector<std::array<uint8_t, 4>> color;    // sRGB8 + alpha 255, or 0,0,0,0 without colour
  std::vector<uint8_t> surface;                 // 1: surface voxel
  // Only with `withVotes` (the svo layout sums them into its mip bricks):
  bool withVotes = false;
  std::vector<uint32_t> voteBegin, voteEnd;  // range of voxel k in `votes`
  std::vector<ClassVotes> votes;
  std::vector<std::array<float, 3>> linear;  // linear colour of voxel k when color[k][3] == 255

  bool occupied(uint32_t k) const { return (bits[k >> 6] >> (k & 63)) & 1; }
};

/// Where a chunk is, for error messages.
struct ChunkPlace {
  int level = 0;
  std::array<uint32_t, 3> chunk{};
};

}  // namespace packdetail

}  // namespace vox
