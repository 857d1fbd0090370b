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
  uint32_t alignment = 0;     // power of two, 8..65536 (pagefile::kMinAlignLog2 .. kMaxAlignLog2);
                              // 0: automatic, 4 KiB or 64 bytes by the payload sizes (pagefile::chooseAlignLog2)
  pagefile::Layout layout = pagefile::Layout::Bricks;
  unsigned threads = 1;       // 0: every core; any count gives the same bytes
  std::string mipOccupancy;   // recorded in the metadata ("any", "majority", "from FILE"), empty without mips
  uint32_t mipLevelsAsked = 0;  // `--levels` (0: automatic), recorded for a region part's merge
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
/// A region part (header.region set) with mips also records `region_mips` in
/// the metadata: the settings and, when it has level pagefile::kRegionSeamLevel,
/// that level's voxels in full (what `--merge` rebuilds the coarse levels from).
/// Throws vox::Error (Usage, with the Setting to change) for an unsupported
/// chunk side, alignment or layout, and for a scene the layout cannot hold
/// (columns: a coloured interior voxel); (BadInput) for dims past the format's
/// (pageFileDimsProblem).
PackResult packChunks(const std::vector<const Scene*>& levels, const PackSettings& settings);

struct SceneLeaves;

/// A page file laid out with its payloads beside it, not yet copied together:
/// pagefile::writePlannedFile writes it.
struct PlannedPack {
  pagefile::FilePlan plan;
  std::vector<pagefile::ChunkBlob> chunks;
  std::vector<PackResult::Level> levels;
};

/// packChunks of one level (no mips) read as leaves (formats/vdb/vdb_scene_leaves.h):
/// the file of packChunks of readSceneVdb's scene of the same file, byte for
/// byte, at any thread count, without OpenVDB trees. Throws as packChunks.
PlannedPack packChunks(const SceneLeaves& scene, const PackSettings& settings);

/// Why a page file cannot hold a scene of level-0 `dims` (an axis past
/// pagefile::kMaxDim, which every reader refuses), with what to do; "" when it
/// can. packChunks throws it (BadInput); commands check it before the work.
std::string pageFileDimsProblem(const Dims& dims);

/// MipSettings::levels for packing `header`'s scene with `--levels asked`
/// (0: automatic): `asked` for a whole scene; for a region part, every level
/// up to pagefile::kRegionSeamLevel (or `asked` when smaller), whatever the
/// part holds, so that a merge finds them where the world's automatic pyramid
/// goes on. Leaves an `asked` beyond the grid's levels to buildMipPyramid's check.
int mipLevelsToBuild(const SceneHeader& header, int asked);

/// The header packChunks writes for `levels` and `settings` (channel flags
/// from every level).
pagefile::Header packHeader(const std::vector<const Scene*>& levels, const PackSettings& settings);

/// The non-empty chunks of one level of a scene, encoded for `header` (its
/// layout, chunk side and flags), in Morton order; `threads` as in PackSettings.
/// What packChunks writes for that level.
std::vector<pagefile::ChunkBlob> packLevel(const Scene& scene, int level, const pagefile::Header& header,
                                           unsigned threads);

}  // namespace vox
