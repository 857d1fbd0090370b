#include "formats/pagefile/pagefile_class_volume.h"

#include "libvox/core/color.h"
#include "libvox/core/parallel.h"

namespace vox {

ClassVolume classVolumeFromPages(const pagefile::Reader& reader, int level, const IndexBox& box, bool withColor,
                                 unsigned threads) {
  ClassVolume volume(box, withColor);
  const uint32_t C = reader.header().chunkSide();
  const uint32_t B = C / ClassVolume::kBrickSide;  // bricks per chunk side
  const auto [first, last] = reader.levelRange(level);
  auto overlaps = [&](const std::array<uint32_t, 3>& chunk) {
    for (int a = 0; a < 3; ++a) {
      const int64_t lo = int64_t(chunk[size_t(a)]) * C, hi = lo + C - 1;
      const int64_t bmin = a == 0 ? box.min.u : a == 1 ? box.min.v : box.min.w;
      const int64_t bmax = a == 0 ? box.max.u : a == 1 ? box.max.v : box.max.w;
      if (hi < bmin || lo > bmax) return false;
    }
    return true;
  };
  std::vector<size_t> chunks;
  for (size_t i = first; i < last; ++i)
    if (!box.empty() && overlaps(reader.entries()[i].chunk())) chunks.push_back(i);
  std::vector<std::vector<ClassVolume::Brick>> perChunk(chunks.size());
  parallelForEach(chunks.size(), threads, 1, [&](size_t k) {
    const auto chunk = reader.entries()[chunks[k]].chunk();
    std::vector<ClassVolume::Brick> bricks;
    bricks.reserve(size_t(B) * B * B);
    for (uint32_t bz = 0; bz < B; ++bz)
      for (uint32_t by = 0; by < B; ++by)
        for (uint32_t bx = 0; bx < B; ++bx)
          bricks.push_back(volume.makeBrick({int32_t(chunk[0] * C + bx * 8), int32_t(chunk[1] * C + by * 8),
                                             int32_t(chunk[2] * C + bz * 8)}));
    for (const pagefile::DecodedVoxel& v : reader.decode(chunks[k])) {
      const uint32_t x = v.index % C, y = (v.index / C) % C, z = v.index / (C * C);
      ClassVolume::Brick& b = bricks[size_t(((z >> 3) * B + (y >> 3)) * B + (x >> 3))];
      const int i = ClassVolume::voxelIndex(int(x & 7), int(y & 7), int(z & 7));
      b.classes[size_t(i)] = v.summary[0];
      if (withColor && v.color[3] == 255)
        b.setColor(i, {srgb8ToLinear(v.color[0]), srgb8ToLinear(v.color[1]), srgb8ToLinear(v.color[2])});
    }
    perChunk[k] = std::move(bricks);
  });
  for (auto& bricks : perChunk)
    for (ClassVolume::Brick& b : bricks) volume.add(std::move(b));
  volume.finish();
  return volume;
}

}  // namespace vox
