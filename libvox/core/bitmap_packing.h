// Occupancy bitmaps at atlas addresses (the UVW atlas layout's 1- and 2-bit
// bitmaps), one image per layer.
//
// 1 bit per voxel ("occupancy"): 8 voxels per byte along x; the image is
//   ceil(W / 8) x H bytes (an R8 image, loads as R8UI); texel (x, y) is
//   byte (x >> 3, y), bit (x & 7), with bit 0 the least significant (the
//   smallest x). 1 = occupied.
// 2 bits per voxel ("occupancy2": occupied + touched): 4 voxels per byte along
//   x; the image is ceil(W / 4) x H bytes; texel (x, y) is byte (x >> 2, y),
//   bits 2 * (x & 3) (occupied) and 2 * (x & 3) + 1 (touched, set by a
//   streamer or by render-canonical for the voxels a camera path hit).
// Padding texels (outside the voxel domain) are always 0.
#pragma once

#include <cstdint>
#include <vector>

#include "libvox/core/atlas_mapping.h"

namespace vox {

class OccupancyBitmap {
 public:
  OccupancyBitmap(const AtlasLayout& layout, int bitsPerVoxel);  // 1 or 2

  int bitsPerVoxel() const { return bits_; }
  uint32_t rowBytes() const { return rowBytes_; }
  uint32_t height() const { return layout_.height; }
  const AtlasLayout& layout() const { return layout_; }
  std::vector<uint8_t>& layerBytes(uint32_t layer) { return layers_[layer]; }
  const std::vector<uint8_t>& layerBytes(uint32_t layer) const { return layers_[layer]; }

  void setOccupied(const TexelAddress& t);
  /// As setOccupied, and safe to call concurrently with itself (an atomic OR
  /// of the texel's bit into its byte, so the bytes do not depend on the order).
  void setOccupiedConcurrently(const TexelAddress& t);
  void setTouched(const TexelAddress& t);  // 2-bit bitmaps only
  bool occupied(const TexelAddress& t) const;
  bool touched(const TexelAddress& t) const;

 private:
  AtlasLayout layout_;
  int bits_;
  uint32_t rowBytes_;
  std::vector<std::vector<uint8_t>> layers_;
};

}  // namespace vox
