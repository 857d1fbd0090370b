// The voxel <-> texel bijection of atlases: the UVW atlas layout
// (formats/image/ATLAS.md), generalised to any dims.
//
// Spaces: voxel index (u, v, w) in [0, X) x [0, Y) x [0, Z); texel (layer, x, y)
// with x in [0, width), y in [0, height), layer in [0, layers).
//
// Each w-slice is one X x Y tile; tiles run T per row (left to right), rows run
// top to bottom (y = 0 is the first row of texels), and when the tile rows do
// not fit under the maximum texture side they continue in further array layers:
//     col = w % T,  row = w / T,  layer = row / R,  rowInLayer = row % R
//     x = col * X + u,  y = rowInLayer * Y + v
// with R = tile rows per layer. For 256^3 with the default choice (T = 16,
// 4096 x 4096, one layer) this is the UVW atlas layout's voxel_to_atlas exactly:
// x = ((w & 15) << 8) | u, y = ((w >> 4) << 8) | v.
//
// Texels past the last tile (the padding of the last tile row, or of the last
// layer) belong to no voxel; toVoxel reports them as nullopt, never aliased.
//
// Default T: among the T whose atlas fits in one layer (T*X and rows*Y within the
// maximum side), the one with the smallest area; ties go to the most square
// (smallest |width - height|), then to the smaller T. When no T fits one layer,
// T is as large as the maximum side allows and R likewise, with as many layers
// as needed. Thread-safe (immutable after make()).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "libvox/core/types.h"

namespace vox {

struct TexelAddress {
  uint32_t layer = 0, x = 0, y = 0;
  bool operator==(const TexelAddress&) const = default;
};

/// The largest texture side an atlas uses unless told otherwise (16384: what
/// current GPUs allow for 2D textures).
inline constexpr uint32_t kDefaultAtlasMaxSide = 16384;
/// The largest maximum side a layout may have: 2^31 - 1, the largest side of a
/// PNG (and of an EXR data window), so every side fits an int32.
inline constexpr uint32_t kMaxAtlasSide = 0x7fffffff;

struct AtlasLayout {
  Dims dims;                   // X, Y, Z
  uint32_t tilesPerRow = 0;    // T
  uint32_t tileRows = 0;       // ceil(Z / T), over all layers
  uint32_t rowsPerLayer = 0;   // R
  uint32_t layers = 0;         // ceil(tileRows / R)
  uint32_t width = 0, height = 0;  // per layer: T * X, R * Y (the last layer may be partly padding)
  uint32_t maxSide = kDefaultAtlasMaxSide;

  /// Throws vox::Error (Usage) when X or Y exceed maxSide, maxSide is 0 or past
  /// kMaxAtlasSide, a forced T is too wide, or the dims are 0 (tilesPerRow 0:
  /// the default T). Takes at most about 2 sqrt(Z) steps, whatever maxSide.
  static AtlasLayout make(Dims dims, uint32_t tilesPerRow = 0, uint32_t maxSide = kDefaultAtlasMaxSide);

  TexelAddress toTexel(uint32_t u, uint32_t v, uint32_t w) const {
    const uint32_t col = w % tilesPerRow, row = w / tilesPerRow;
    return {row / rowsPerLayer, col * dims.x + u, (row % rowsPerLayer) * dims.y + v};
  }
  std::optional<Coord3> toVoxel(uint32_t layer, uint32_t x, uint32_t y) const {
    if (layer >= layers || x >= width || y >= height) return std::nullopt;
    const uint32_t col = x / dims.x, rowInLayer = y / dims.y;
    const uint64_t w = (uint64_t(layer) * rowsPerLayer + rowInLayer) * tilesPerRow + col;
    if (w >= dims.z) return std::nullopt;
    return Coord3{int32_t(x - col * dims.x), int32_t(y - rowInLayer * dims.y), int32_t(w)};
  }
  uint64_t texelsPerLayer() const { return uint64_t(width) * height; }
  bool operator==(const AtlasLayout&) const = default;

  /// {"dims":[X,Y,Z],"tiles_per_row":T,"rows_per_layer":R,"layers":L,"width":W,"height":H,"max_side":S}
  std::string toJson() const;
  /// Parses toJson()'s output and checks it is consistent (tiles_per_row >= 1,
  /// the sizes make() gives for dims, tiles_per_row and max_side); throws
  /// vox::Error (BadInput) with `context` (file name) on anything else.
  static AtlasLayout fromJson(const std::string& json, const std::string& context);
};

/// The UVW atlas layout's 256^3 mapping as its authors write it, bit for bit, for tests.
inline TexelAddress uvw256VoxelToAtlas(uint32_t u, uint32_t v, uint32_t w) {
  return {0, ((w & 15) << 8) | u, ((w >> 4) << 8) | v};
}
inline Coord3 uvw256AtlasToVoxel(uint32_t x, uint32_t y) {
  return {int32_t(x & 255), int32_t(y & 255), int32_t((y >> 8) * 16 + (x >> 8))};
}

}  // namespace vox
