#include "formats/export/magicavoxel_writer.h"

#include <algorithm>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "formats/export/output_file.h"
#include "libvox/core/error.h"

namespace vox {

namespace {

constexpr uint32_t kTile = 256;

using Dict = std::vector<std::pair<std::string, std::string>>;

uint32_t dictBytes(const Dict& d) {
  uint32_t n = 4;
  for (const auto& [k, v] : d) n += 8 + uint32_t(k.size() + v.size());
  return n;
}

void writeDict(OutputFile& out, const Dict& d) {
  out.u32(uint32_t(d.size()));
  for (const auto& [k, v] : d) {
    out.u32(uint32_t(k.size()));
    out.write(k);
    out.u32(uint32_t(v.size()));
    out.write(v);
  }
}

void chunkHeader(OutputFile& out, const char id[4], uint32_t content, uint32_t children) {
  out.write(id, 4);
  out.u32(content);
  out.u32(children);
}

struct Model {
  std::array<uint32_t, 3> offset{}, size{};
  std::vector<std::array<uint8_t, 4>> voxels;  // x, y, z, palette index
  Dict frame;                                  // {"_t": translation}
};

}  // namespace

MagicaVoxelResult writeMagicaVoxel(const ClassVolume& volume, const std::array<Rgb8, 255>& palette,
                                   const std::function<uint8_t(const ClassVolume::Brick&, int)>& indexOf,
                                   const std::string& path, const std::function<void(const MagicaVoxelPlan&)>& check) {
  const IndexBox& box = volume.box();
  MagicaVoxelResult r;
  if (!box.empty())
    r.size = {uint32_t(box.max.u - box.min.u + 1), uint32_t(box.max.w - box.min.w + 1),
              uint32_t(box.max.v - box.min.v + 1)};
  const std::array<uint64_t, 3> tiles{(r.size[0] + kTile - 1) / kTile, (r.size[1] + kTile - 1) / kTile,
                                      (r.size[2] + kTile - 1) / kTile};
  // Only tiles with voxels are kept: a wide, sparse box has far more tiles
  // than voxels. A tile's key is its index in (z, y, x) tile order, so the
  // sorted keys are the models in that order.
  auto tileKey = [&](uint32_t x, uint32_t y, uint32_t z) {
    return (uint64_t(z / kTile) * tiles[1] + y / kTile) * tiles[0] + x / kTile;
  };
  auto forEachVoxel = [&](const auto& f) {
    for (const ClassVolume::Brick& b : volume.bricks())
      for (int i = 0; i < ClassVolume::kBrickVoxels; ++i) {
        if (!b.classes[size_t(i)]) continue;
        const Coord3 c = b.at(i);
        f(b, i, uint32_t(c.u - box.min.u), uint32_t(box.max.w - c.w), uint32_t(c.v - box.min.v));
      }
  };
  // First pass: the voxels of each tile, counted, so that the file's size is
  // known (and checked) before the voxel lists are allocated, each at its size.
  // Neighbouring voxels share a tile: the last one found is tried first.
  std::unordered_map<uint64_t, uint64_t> slot;  // tile key -> its voxels, then -> its model
  uint64_t total = 0, lastKey = UINT64_MAX, *last = nullptr;
  forEachVoxel([&](const ClassVolume::Brick&, int, uint32_t x, uint32_t y, uint32_t z) {
    const uint64_t key = tileKey(x, y, z);
    if (key != lastKey) last = &slot[key], lastKey = key;
    ++*last;
    ++total;
  });
  // A box without voxels still gets one (empty) model: readers expect a SIZE chunk.
  if (!total && !box.empty()) slot[0] = 0;
  std::vector<uint64_t> keys;
  keys.reserve(slot.size());
  for (const auto& [key, count] : slot) keys.push_back(key);
  std::sort(keys.begin(), keys.end());

  std::vector<Model> models(keys.size());
  for (size_t k = 0; k < keys.size(); ++k) {
    Model& m = models[k];
    const uint64_t key = keys[k];
    const std::array<uint64_t, 3> tile{key % tiles[0], key / tiles[0] % tiles[1], key / tiles[0] / tiles[1]};
    std::string t;
    for (size_t a = 0; a < 3; ++a) {
      m.offset[a] = uint32_t(tile[a]) * kTile;
      m.size[a] = std::min(kTile, r.size[a] - m.offset[a]);
      const int64_t translation = int64_t(m.offset[a]) + m.size[a] / 2 - int64_t(r.size[a] / 2);
      if (a) t += ' ';
      t += std::to_string(translation);
    }
    m.frame = {{"_t", t}};
  }
  r.voxels = total;
  r.models = uint32_t(models.size());

  // Chunk sizes (content, children) up front: MAIN's header counts them all.
  const uint64_t n = models.size();
  const Dict none;
  uint64_t children = (12 + 12) * n + (12 + 4) * n + 4 * total;  // SIZE, XYZI
  const uint32_t rootTrn = 4 + dictBytes(none) + 4 + 4 + 4 + 4 + dictBytes(none);
  const uint64_t group = 4 + dictBytes(none) + 4 + 4 * n;
  const uint32_t shape = 4 + dictBytes(none) + 4 + 4 + dictBytes(none);
  if (n) {
    children += 12 + rootTrn + 12 + group;
    for (const Model& m : models)
      children += 12 + (4 + dictBytes(none) + 4 + 4 + 4 + 4 + dictBytes(m.frame)) + 12 + shape;
  }
  children += 12 + 256 * 4;  // RGBA

  const MagicaVoxelPlan plan{n, total, 8 + 12 + children,
                             total * 4 + n * (sizeof(Model) + 64 + 2 * sizeof(uint64_t)) + slot.size() * 48};
  if (check) check(plan);
  if (children > kMagicaVoxelMaxChunkBytes)
    throw Error(ErrorKind::BadInput, "a MagicaVoxel file of " + std::to_string(total) + " voxels in " +
                                         std::to_string(n) + " models needs a MAIN chunk of " +
                                         std::to_string(children) + " bytes; the format's chunk sizes end at " +
                                         std::to_string(kMagicaVoxelMaxChunkBytes));

  // Second pass: the voxels, in the volume's brick order within each model.
  for (size_t k = 0; k < keys.size(); ++k) {
    uint64_t& s = slot[keys[k]];
    models[k].voxels.reserve(size_t(s));
    s = k;
  }
  lastKey = UINT64_MAX;
  Model* model = nullptr;
  forEachVoxel([&](const ClassVolume::Brick& b, int i, uint32_t x, uint32_t y, uint32_t z) {
    const uint64_t key = tileKey(x, y, z);
    if (key != lastKey) model = &models[size_t(slot.find(key)->second)], lastKey = key;
    model->voxels.push_back({uint8_t(x % kTile), uint8_t(y % kTile), uint8_t(z % kTile), indexOf(b, i)});
  });

  OutputFile out(path);
  out.write("VOX ", 4);
  out.u32(150);
  chunkHeader(out, "MAIN", 0, uint32_t(children));
  for (const Model& m : models) {
    chunkHeader(out, "SIZE", 12, 0);
    for (uint32_t s : m.size) out.u32(s);
    chunkHeader(out, "XYZI", uint32_t(4 + 4 * m.voxels.size()), 0);
    out.u32(uint32_t(m.voxels.size()));
    out.write(m.voxels.data(), 4 * m.voxels.size());
  }
  if (n) {
    // Root transform (node 0) -> group (node 1) -> per model a transform
    // (node 2 + 2k) -> shape (node 3 + 2k) -> model k.
    chunkHeader(out, "nTRN", rootTrn, 0);
    out.i32(0), writeDict(out, none), out.i32(1), out.i32(-1), out.i32(-1), out.u32(1), writeDict(out, none);
    chunkHeader(out, "nGRP", uint32_t(group), 0);
    out.i32(1), writeDict(out, none), out.u32(uint32_t(n));
    for (uint32_t k = 0; k < n; ++k) out.i32(int32_t(2 + 2 * k));
    for (uint32_t k = 0; k < n; ++k) {
      chunkHeader(out, "nTRN", 4 + dictBytes(none) + 4 + 4 + 4 + 4 + dictBytes(models[k].frame), 0);
      out.i32(int32_t(2 + 2 * k)), writeDict(out, none), out.i32(int32_t(3 + 2 * k)), out.i32(-1), out.i32(0);
      out.u32(1), writeDict(out, models[k].frame);
      chunkHeader(out, "nSHP", shape, 0);
      out.i32(int32_t(3 + 2 * k)), writeDict(out, none), out.u32(1), out.i32(int32_t(k)), writeDict(out, none);
    }
  }
  chunkHeader(out, "RGBA", 256 * 4, 0);
  for (const Rgb8& c : palette) {
    const uint8_t rgba[4] = {c.r, c.g, c.b, 255};
    out.write(rgba, 4);
  }
  out.repeat(0, 4);  // the 256th entry stands for index 0 (empty) and is never used
  out.close();
  r.bytes = out.written();
  return r;
}

}  // namespace vox
