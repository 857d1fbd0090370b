#include "formats/export/magicavoxel_writer.h"

#include <string>
#include <utility>
#include <vector>

#include "formats/export/output_file.h"

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
                                   const std::string& path) {
  const IndexBox& box = volume.box();
  MagicaVoxelResult r;
  if (!box.empty())
    r.size = {uint32_t(box.max.u - box.min.u + 1), uint32_t(box.max.w - box.min.w + 1),
              uint32_t(box.max.v - box.min.v + 1)};
  const std::array<uint32_t, 3> tiles{(r.size[0] + kTile - 1) / kTile, (r.size[1] + kTile - 1) / kTile,
                                      (r.size[2] + kTile - 1) / kTile};
  std::vector<Model> grid(size_t(tiles[0]) * tiles[1] * tiles[2]);
  for (const ClassVolume::Brick& b : volume.bricks())
    for (int i = 0; i < ClassVolume::kBrickVoxels; ++i) {
      if (!b.classes[size_t(i)]) continue;
      const Coord3 c = b.at(i);
      const uint32_t x = uint32_t(c.u - box.min.u), y = uint32_t(box.max.w - c.w), z = uint32_t(c.v - box.min.v);
      Model& m = grid[(size_t(z / kTile) * tiles[1] + y / kTile) * tiles[0] + x / kTile];
      m.voxels.push_back({uint8_t(x % kTile), uint8_t(y % kTile), uint8_t(z % kTile), indexOf(b, i)});
    }
  // Non-empty tiles in (z, y, x) tile order become the models.
  // An empty box still gets one (empty) model: readers expect a SIZE chunk.
  std::vector<Model> models;
  uint64_t total = 0;
  for (const Model& m : grid) total += m.voxels.size();
  for (uint32_t tz = 0; tz < tiles[2]; ++tz)
    for (uint32_t ty = 0; ty < tiles[1]; ++ty)
      for (uint32_t tx = 0; tx < tiles[0]; ++tx) {
        Model& m = grid[(size_t(tz) * tiles[1] + ty) * tiles[0] + tx];
        if (m.voxels.empty() && (total || tx || ty || tz)) continue;
        m.offset = {tx * kTile, ty * kTile, tz * kTile};
        std::string t;
        for (int a = 0; a < 3; ++a) {
          m.size[size_t(a)] = std::min(kTile, r.size[size_t(a)] - m.offset[size_t(a)]);
          const int64_t translation =
              int64_t(m.offset[size_t(a)]) + m.size[size_t(a)] / 2 - int64_t(r.size[size_t(a)] / 2);
          if (a) t += ' ';
          t += std::to_string(translation);
        }
        m.frame = {{"_t", t}};
        r.voxels += m.voxels.size();
        models.push_back(std::move(m));
      }
  r.models = uint32_t(models.size());

  // Chunk sizes (content, children) up front: MAIN's header counts them all.
  const uint32_t n = r.models;
  const Dict none;
  uint64_t children = 0;
  for (const Model& m : models) children += (12 + 12) + (12 + 4 + 4 * uint64_t(m.voxels.size()));
  const uint32_t rootTrn = 4 + dictBytes(none) + 4 + 4 + 4 + 4 + dictBytes(none);
  const uint32_t group = 4 + dictBytes(none) + 4 + 4 * n;
  const uint32_t shape = 4 + dictBytes(none) + 4 + 4 + dictBytes(none);
  if (n) {
    children += 12 + rootTrn + 12 + group;
    for (const Model& m : models)
      children += 12 + (4 + dictBytes(none) + 4 + 4 + 4 + 4 + dictBytes(m.frame)) + 12 + shape;
  }
  children += 12 + 256 * 4;  // RGBA

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
    chunkHeader(out, "nGRP", group, 0);
    out.i32(1), writeDict(out, none), out.u32(n);
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
