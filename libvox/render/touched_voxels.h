// The voxels a camera path touches: every voxel some pixel of some view hit,
// the chunks that hold them (the working set a streamer must fetch for the
// path), and the 2-bit occupied + touched atlas bitmap of them.
// formats/image/RENDER.md specifies the touched-set file; formats/image/ATLAS.md
// the bitmap.
//
// Thread safety: immutable after construction.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "libvox/core/bitmap_packing.h"
#include "libvox/render/render.h"

namespace vox {

/// The distinct voxels hit by any pixel of some views, in (w, v, u) order.
class TouchedVoxels {
 public:
  TouchedVoxels() = default;
  explicit TouchedVoxels(std::span<const ViewHits> views);

  size_t size() const { return keys_.size(); }
  bool empty() const { return keys_.empty(); }
  /// The i-th voxel, grid space.
  Coord3 voxel(size_t i) const;
  std::vector<Coord3> voxels() const;
  /// The position of the voxel `hit` hit (a hit of one of the views).
  size_t indexOf(const PixelHit& hit) const;

 private:
  std::vector<uint64_t> keys_;  // (w << 42) | (v << 21) | u, sorted, unique
};

/// A chunk of C^3 voxels holding touched voxels.
struct TouchedChunk {
  std::array<uint32_t, 3> chunk{};  // chunk coordinates: voxel / C
  uint64_t morton = 0;              // mortonEncode(chunk): the page file's index order
  uint64_t voxels = 0;              // distinct touched voxels inside
  bool operator==(const TouchedChunk&) const = default;
};

/// The chunks of side `chunkSide` holding `touched`, sorted by Morton key.
std::vector<TouchedChunk> touchedChunks(const TouchedVoxels& touched, uint32_t chunkSide);

/// The 2-bit bitmap at the atlas addresses of `layout`: occupied for every
/// voxel of `grid`, touched for every voxel of `touched`.
OccupancyBitmap touchedBitmap(const RayGrid& grid, const TouchedVoxels& touched, const AtlasLayout& layout);

}  // namespace vox
