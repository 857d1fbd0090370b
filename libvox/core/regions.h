// Region bakes: the tiling that splits a world into parts, and the key that
// says which world a part belongs to.
//
// The tiling (`vox voxelize --region I/N`) cuts the x-z plane of the world's
// index domain; every tile spans the whole y range. Cuts fall on multiples of
// kRegionAlignVoxels voxels (the largest page-file chunk edge), so every chunk
// of every chunk size lies in exactly one tile and a part's page file holds
// whole chunks. The tiles of N are made by recursive halving:
//   tile(box, N): if N == 1, the box is tile; otherwise cut the box across its
//   longer axis in 32-voxel cells (x when equal) into a first part of
//   floor(N/2) tiles and a second of N - floor(N/2), the cut at
//   round(cells * floor(N/2) / N) cells from the low side (ties down), kept
//   at >= 1 cell per side while the axis has >= 2 cells. Tiles are numbered
//   depth first: the low side's tiles, then the high side's.
// When N exceeds the number of cells some tiles are empty: a valid empty part.
// The tiles of N are disjoint and cover the domain.
//
// Pure functions; thread-safe.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "libvox/core/scene_header.h"
#include "libvox/core/types.h"

namespace vox {

/// Tile edges fall on multiples of this many voxels (x and z).
inline constexpr uint32_t kRegionAlignVoxels = 32;

/// The largest tile count accepted (a sanity bound on `--region I/N`).
inline constexpr uint32_t kMaxRegionCount = 1u << 20;

struct RegionSpec {
  uint32_t index = 0;
  uint32_t count = 1;
};

/// Parses "I/N" (decimal, 0 <= I < N <= kMaxRegionCount). Throws vox::Error
/// (Usage) naming the text and the rule on anything else.
RegionSpec parseRegionSpec(std::string_view text);

/// Tile `index` of `count` of the domain [0, dims) (inclusive box; empty() when
/// the tile holds no voxel). Requires index < count.
IndexBox regionTile(const Dims& dims, uint32_t index, uint32_t count);

/// All `count` tiles, in index order.
std::vector<IndexBox> regionTiles(const Dims& dims, uint32_t count);

/// True when `box` (inclusive) has its edges on the tiling's cells on every
/// axis: each min a multiple of kRegionAlignVoxels, each max + 1 a multiple of
/// it or the domain's end (tiles span y whole; `--region-box` may cut y too).
bool isRegionAligned(const IndexBox& box, const Dims& dims);

/// The key of a world bake: a hex SHA-256 over the header fields that decide
/// its voxels (dims, voxel size, origin, mip level, class table, sources'
/// kinds and digests or names, block-world placement) and `settings`, a
/// canonical text of the options that change voxels (fill, rules, votes...),
/// supplied by the command. Two parts with equal keys come from the same world
/// bake. The header's own `region` is not part of the key.
std::string regionWorldKey(const SceneHeader& header, std::string_view settings);

/// One input of a merge: the file it came from (for messages) and its header.
struct RegionPart {
  std::string path;
  const SceneHeader* header = nullptr;  // not owned; dims, placement, classes and region are checked
};

/// How a set of parts joins.
enum class RegionPartSet {
  Tiles,  // every part is tile I of N of the same tiling and all N are there: the whole world
  Boxes,  // parts from `--region-box` (recorded as tile 0 of 1 with their box): disjoint boxes;
          // the union need not cover the world
};

/// Checks that `parts` join into one world, or throws vox::Error (BadInput)
/// naming the part and the fix: a part without a region record; a part of
/// another bake (world key, dims, placement, class table or mip level differ
/// from the first part's); two parts that are the same tile or whose boxes
/// overlap; a tile of N missing; a box that is not tile I of N although other
/// parts are tiles. `parts` must not be empty.
RegionPartSet checkRegionParts(const std::vector<RegionPart>& parts);

/// The part whose header a merge of `parts` keeps (its sources' paths, the
/// one thing parts of one bake may differ in): tile 0, or among
/// `--region-box` parts the one whose box starts first (z, then y, then x);
/// ties by the sources' paths. The same part whatever the order of `parts`.
/// Each part must have a region record; `parts` must not be empty.
size_t worldHeaderPart(const std::vector<RegionPart>& parts);

/// True when `box` is exactly tile `r.index` of `r.count` of `dims`.
bool isTile(const SceneRegion& r, const Dims& dims);

/// Intersection of two inclusive boxes (empty() when they do not meet).
IndexBox intersect(const IndexBox& a, const IndexBox& b);

}  // namespace vox
