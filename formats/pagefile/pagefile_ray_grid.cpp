// Page file -> RayGrid and summary lookups (no OpenVDB).
#include <algorithm>
#include <map>

#include "formats/pagefile/pagefile_ray_grid.h"

namespace vox {

RayGrid rayGridFromPages(const pagefile::Reader& reader, int level) {
  const pagefile::Header& h = reader.header();
  const auto d = h.levelDims(level);
  RayGrid grid(Dims{d[0], d[1], d[2]});
  const uint32_t C = h.chunkSide(), B = C / 8;  // bricks per chunk side
  std::vector<RayGrid::Mask512> bricks(size_t(B) * B * B);
  const auto [first, last] = reader.levelRange(level);
  for (size_t i = first; i < last; ++i) {
    const auto chunk = reader.entries()[i].chunk();
    for (auto& b : bricks) b.fill(0);
    for (const pagefile::DecodedVoxel& v : reader.decode(i)) {
      const uint32_t x = v.index % C, y = (v.index / C) % C, z = v.index / (C * C);
      const int bit = RayGrid::bitOf(x & 7, y & 7, z & 7);
      bricks[size_t(((x >> 3) * B + (y >> 3)) * B + (z >> 3))][size_t(bit >> 6)] |= uint64_t(1) << (bit & 63);
    }
    for (uint32_t bx = 0; bx < B; ++bx)
      for (uint32_t by = 0; by < B; ++by)
        for (uint32_t bz = 0; bz < B; ++bz) {
          const RayGrid::Mask512& m = bricks[size_t((bx * B + by) * B + bz)];
          bool any = false;
          for (uint64_t w : m) any |= w != 0;
          if (any) grid.addBrick(chunk[0] * B + bx, chunk[1] * B + by, chunk[2] * B + bz, m);
        }
  }
  grid.finish();
  return grid;
}

namespace {

// Calls fn(i, decoded voxel) for every request i of `voxels` that is occupied;
// each chunk is decoded once.
template <typename Fn>
void forEachStoredVoxel(const pagefile::Reader& reader, int level, std::span<const Coord3> voxels, Fn&& fn) {
  const uint32_t C = reader.header().chunkSide();
  // Group the requests by chunk so that each chunk is decoded once.
  std::map<const pagefile::IndexEntry*, std::vector<size_t>> byChunk;
  for (size_t i = 0; i < voxels.size(); ++i) {
    const Coord3& c = voxels[i];
    if (c.u < 0 || c.v < 0 || c.w < 0) continue;
    const pagefile::IndexEntry* e = reader.find(level, uint32_t(c.u) / C, uint32_t(c.v) / C, uint32_t(c.w) / C);
    if (e) byChunk[e].push_back(i);
  }
  for (const auto& [entry, requests] : byChunk) {
    const size_t index = size_t(entry - reader.entries().data());
    std::vector<pagefile::DecodedVoxel> decoded = reader.decode(index);
    auto byIndex = [](const pagefile::DecodedVoxel& a, const pagefile::DecodedVoxel& b) { return a.index < b.index; };
    if (!std::is_sorted(decoded.begin(), decoded.end(), byIndex)) std::sort(decoded.begin(), decoded.end(), byIndex);
    for (size_t i : requests) {
      const Coord3& c = voxels[i];
      const uint32_t local = uint32_t(c.u) % C + C * (uint32_t(c.v) % C + C * (uint32_t(c.w) % C));
      const auto it = std::lower_bound(decoded.begin(), decoded.end(), local,
                                       [](const pagefile::DecodedVoxel& d, uint32_t k) { return d.index < k; });
      if (it != decoded.end() && it->index == local) fn(i, *it);
    }
  }
}

}  // namespace

std::vector<SummaryTexel> pageSummaries(const pagefile::Reader& reader, int level, std::span<const Coord3> voxels) {
  std::vector<SummaryTexel> out(voxels.size());
  forEachStoredVoxel(reader, level, voxels, [&](size_t i, const pagefile::DecodedVoxel& d) {
    out[i] = {d.summary[0], d.summary[1], d.summary[2], d.summary[3]};
  });
  return out;
}

std::vector<std::array<uint8_t, 4>> pageColors(const pagefile::Reader& reader, int level,
                                               std::span<const Coord3> voxels) {
  std::vector<std::array<uint8_t, 4>> out(voxels.size(), std::array<uint8_t, 4>{0, 0, 0, 0});
  if (!(reader.header().flags & pagefile::kFlagColor)) return out;
  forEachStoredVoxel(reader, level, voxels, [&](size_t i, const pagefile::DecodedVoxel& d) {
    if (d.color[3] == 255) out[i] = d.color;
  });
  return out;
}

}  // namespace vox
