#include "formats/pagefile/pagefile_class_volume.h"

#include <optional>

#include "libvox/core/color.h"
#include "libvox/core/error.h"
#include "libvox/core/parallel.h"

namespace vox {

namespace {

// The first voxel of a chunk whose class is not in the table.
struct UnknownClass {
  Coord3 voxel;
  uint8_t classId = 0;
};

[[noreturn]] void throwUnknownClass(const pagefile::Reader& reader, int level, const std::array<uint32_t, 3>& chunk,
                                    const UnknownClass& u) {
  const std::string& file = reader.name();
  throwBadInput(file + ": " + (level ? "level " + std::to_string(level) + ", " : std::string()) + "chunk (" +
                std::to_string(chunk[0]) + ", " + std::to_string(chunk[1]) + ", " + std::to_string(chunk[2]) +
                "), voxel " + toString(u.voxel) + ": class " + std::to_string(u.classId) +
                " has no entry in the file's class table, so the voxel has no colour; the file is damaged or was "
                "written by another tool: check it with 'vox pack-chunks --verify " + file +
                "' and pack it again from its scene (vox pack-chunks SCENE.vdb -o " + file + ")");
}

}  // namespace

ClassVolume classVolumeFromPages(const pagefile::Reader& reader, int level, const IndexBox& box,
                                 const ClassTable& classes, bool withColor, unsigned threads) {
  std::array<bool, 256> known{};
  for (const ClassInfo& c : classes.classes()) known[c.id] = true;
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
  auto inBox = [&](Coord3 c) {
    return c.u >= box.min.u && c.u <= box.max.u && c.v >= box.min.v && c.v <= box.max.v && c.w >= box.min.w &&
           c.w <= box.max.w;
  };
  std::vector<size_t> chunks;
  for (size_t i = first; i < last; ++i)
    if (!box.empty() && overlaps(reader.entries()[i].chunk())) chunks.push_back(i);
  std::vector<std::vector<ClassVolume::Brick>> perChunk(chunks.size());
  std::vector<std::optional<UnknownClass>> unknown(chunks.size());  // reported after the loop, in file order
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
      // 0 (no class) stays empty, as before; voxels outside the box are clipped unseen.
      if (v.summary[0] && !known[v.summary[0]] && !unknown[k] && inBox(b.at(i)))
        unknown[k] = UnknownClass{b.at(i), v.summary[0]};
      b.classes[size_t(i)] = v.summary[0];
      if (withColor && v.color[3] == 255)
        b.setColor(i, {srgb8ToLinear(v.color[0]), srgb8ToLinear(v.color[1]), srgb8ToLinear(v.color[2])});
    }
    perChunk[k] = std::move(bricks);
  });
  for (size_t k = 0; k < chunks.size(); ++k)
    if (unknown[k]) throwUnknownClass(reader, level, reader.entries()[chunks[k]].chunk(), *unknown[k]);
  for (auto& bricks : perChunk)
    for (ClassVolume::Brick& b : bricks) volume.add(std::move(b));
  volume.finish();
  return volume;
}

}  // namespace vox
