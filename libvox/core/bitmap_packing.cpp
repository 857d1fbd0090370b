#include "libvox/core/bitmap_packing.h"

#include <atomic>

#include "libvox/core/error.h"

namespace vox {

OccupancyBitmap::OccupancyBitmap(const AtlasLayout& layout, int bitsPerVoxel) : layout_(layout), bits_(bitsPerVoxel) {
  if (bits_ != 1 && bits_ != 2) throw Error(ErrorKind::Internal, "bitmaps have 1 or 2 bits per voxel");
  const uint32_t perByte = 8 / uint32_t(bits_);
  rowBytes_ = (layout.width + perByte - 1) / perByte;
  layers_.assign(layout.layers, std::vector<uint8_t>(size_t(rowBytes_) * layout.height, 0));
}

void OccupancyBitmap::setOccupied(const TexelAddress& t) {
  if (bits_ == 1) layers_[t.layer][size_t(t.y) * rowBytes_ + (t.x >> 3)] |= uint8_t(1u << (t.x & 7));
  else layers_[t.layer][size_t(t.y) * rowBytes_ + (t.x >> 2)] |= uint8_t(1u << (2 * (t.x & 3)));
}

void OccupancyBitmap::setOccupiedConcurrently(const TexelAddress& t) {
  const size_t byte = size_t(t.y) * rowBytes_ + (bits_ == 1 ? t.x >> 3 : t.x >> 2);
  const uint8_t bit = bits_ == 1 ? uint8_t(1u << (t.x & 7)) : uint8_t(1u << (2 * (t.x & 3)));
  std::atomic_ref<uint8_t>(layers_[t.layer][byte]).fetch_or(bit, std::memory_order_relaxed);
}

void OccupancyBitmap::setTouched(const TexelAddress& t) {
  if (bits_ != 2) throw Error(ErrorKind::Internal, "touched bits need a 2-bit bitmap");
  layers_[t.layer][size_t(t.y) * rowBytes_ + (t.x >> 2)] |= uint8_t(2u << (2 * (t.x & 3)));
}

bool OccupancyBitmap::occupied(const TexelAddress& t) const {
  if (bits_ == 1) return (layers_[t.layer][size_t(t.y) * rowBytes_ + (t.x >> 3)] >> (t.x & 7)) & 1;
  return (layers_[t.layer][size_t(t.y) * rowBytes_ + (t.x >> 2)] >> (2 * (t.x & 3))) & 1;
}

bool OccupancyBitmap::touched(const TexelAddress& t) const {
  if (bits_ != 2) return false;
  return (layers_[t.layer][size_t(t.y) * rowBytes_ + (t.x >> 2)] >> (2 * (t.x & 3) + 1)) & 1;
}

}  // namespace vox
