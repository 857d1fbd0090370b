#include "libvox/render/touched_voxels.h"

#include <algorithm>

#include "libvox/core/morton.h"

namespace vox {

namespace {

// 21 bits per axis: RayGrid domains are at most 2^20 voxels per axis.
uint64_t voxelKey(int32_t u, int32_t v, int32_t w) {
  return (uint64_t(uint32_t(w)) << 42) | (uint64_t(uint32_t(v)) << 21) | uint64_t(uint32_t(u));
}
Coord3 keyVoxel(uint64_t k) { return {int32_t(k & 0x1fffff), int32_t((k >> 21) & 0x1fffff), int32_t(k >> 42)}; }

}  // namespace

TouchedVoxels::TouchedVoxels(std::span<const ViewHits> views) {
  for (const ViewHits& h : views)
    for (const PixelHit& p : h.pixels)
      if (p.hit) keys_.push_back(voxelKey(p.u, p.v, p.w));
  std::sort(keys_.begin(), keys_.end());
  keys_.erase(std::unique(keys_.begin(), keys_.end()), keys_.end());
}

Coord3 TouchedVoxels::voxel(size_t i) const { return keyVoxel(keys_[i]); }

std::vector<Coord3> TouchedVoxels::voxels() const {
  std::vector<Coord3> out(keys_.size());
  for (size_t i = 0; i < keys_.size(); ++i) out[i] = keyVoxel(keys_[i]);
  return out;
}

size_t TouchedVoxels::indexOf(const PixelHit& hit) const {
  return size_t(std::lower_bound(keys_.begin(), keys_.end(), voxelKey(hit.u, hit.v, hit.w)) - keys_.begin());
}

std::vector<TouchedChunk> touchedChunks(const TouchedVoxels& touched, uint32_t chunkSide) {
  std::vector<std::pair<uint64_t, std::array<uint32_t, 3>>> chunkOfVoxel;  // (Morton key, chunk)
  chunkOfVoxel.reserve(touched.size());
  for (size_t i = 0; i < touched.size(); ++i) {
    const Coord3 c = touched.voxel(i);
    const std::array<uint32_t, 3> chunk{uint32_t(c.u) / chunkSide, uint32_t(c.v) / chunkSide, uint32_t(c.w) / chunkSide};
    chunkOfVoxel.push_back({mortonEncode(chunk[0], chunk[1], chunk[2]), chunk});
  }
  std::sort(chunkOfVoxel.begin(), chunkOfVoxel.end());
  std::vector<TouchedChunk> chunks;
  for (size_t i = 0; i < chunkOfVoxel.size();) {
    size_t j = i;
    while (j < chunkOfVoxel.size() && chunkOfVoxel[j].first == chunkOfVoxel[i].first) ++j;
    chunks.push_back({chunkOfVoxel[i].second, chunkOfVoxel[i].first, j - i});
    i = j;
  }
  return chunks;
}

OccupancyBitmap touchedBitmap(const RayGrid& grid, const TouchedVoxels& touched, const AtlasLayout& layout) {
  OccupancyBitmap bitmap(layout, 2);
  grid.forEachOccupied([&](uint32_t u, uint32_t v, uint32_t w) { bitmap.setOccupied(layout.toTexel(u, v, w)); });
  for (size_t i = 0; i < touched.size(); ++i) {
    const Coord3 c = touched.voxel(i);
    bitmap.setTouched(layout.toTexel(uint32_t(c.u), uint32_t(c.v), uint32_t(c.w)));
  }
  return bitmap;
}

}  // namespace vox
