// Scene leaves -> RayGrid and summary lookups (render_scene.cpp without OpenVDB).
#include "formats/vdb/vdb_leaves_render.h"

#include "libvox/core/bits.h"
#include "libvox/core/color.h"

namespace vox {

namespace {

uint64_t leafKey(uint32_t x, uint32_t y, uint32_t z) {
  return uint64_t(x >> 3) << 42 | uint64_t(y >> 3) << 21 | uint64_t(z >> 3);
}

/// Index of bit `bit` among the set bits of `mask` (the value's slot in a SceneLeaf).
size_t rankOf(const std::array<uint64_t, 8>& mask, uint32_t bit) {
  size_t r = 0;
  for (uint32_t w = 0; w < bit >> 6; ++w) r += size_t(bitCount(mask[w]));
  return r + size_t(bitCount(mask[bit >> 6] & ((uint64_t(1) << (bit & 63)) - 1)));
}

bool has(const std::array<uint64_t, 8>& mask, uint32_t bit) { return (mask[bit >> 6] >> (bit & 63)) & 1; }

}  // namespace

RayGrid rayGridFromLeaves(const SceneLeaves& scene) {
  RayGrid grid(scene.header.dims);
  for (const OccupancyLeaf& l : scene.occupancy) {
    const auto& o = l.origin;
    if (o[0] < 0 || o[1] < 0 || o[2] < 0) continue;  // as rayGridFromScene: never occupied in a valid scene
    grid.addBrick(uint32_t(o[0]) >> 3, uint32_t(o[1]) >> 3, uint32_t(o[2]) >> 3, l.mask);
  }
  grid.finish();
  return grid;
}

SceneLeavesLookup::SceneLeavesLookup(const SceneLeaves& scene) : s_(scene) {
  byOrigin_.reserve(scene.occupancy.size());
  for (size_t i = 0; i < scene.occupancy.size(); ++i) {
    const auto& o = scene.occupancy[i].origin;
    // Leaves with voxels lie in [0, 2^24) (readSceneLeaves checks it); others hold nothing to find.
    if (o[0] < 0 || o[1] < 0 || o[2] < 0) continue;
    byOrigin_.emplace(leafKey(uint32_t(o[0]), uint32_t(o[1]), uint32_t(o[2])), uint32_t(i));
  }
}

bool SceneLeavesLookup::find(const Coord3& c, uint32_t& leaf, uint32_t& bit) const {
  if (c.u < 0 || c.v < 0 || c.w < 0 || c.u >= (1 << 24) || c.v >= (1 << 24) || c.w >= (1 << 24)) return false;
  const auto it = byOrigin_.find(leafKey(uint32_t(c.u), uint32_t(c.v), uint32_t(c.w)));
  if (it == byOrigin_.end()) return false;
  leaf = it->second;
  bit = uint32_t(RayGrid::bitOf(uint32_t(c.u) & 7, uint32_t(c.v) & 7, uint32_t(c.w) & 7));
  return has(s_.occupancy[leaf].mask, bit);
}

std::vector<SummaryTexel> SceneLeavesLookup::summaries(std::span<const Coord3> voxels) const {
  std::vector<SummaryTexel> out(voxels.size());
  std::vector<ClassVotes> votes;
  for (size_t i = 0; i < voxels.size(); ++i) {
    uint32_t leaf, bit;
    if (!find(voxels[i], leaf, bit)) continue;
    votes.clear();
    for (const SceneLeaves::Votes& v : s_.votes) {  // by class id, as the scene's vote grids
      const uint32_t at = v.at[leaf];
      if (at == SceneLeaves::kNoLeaf || !has(v.leaves[at].mask, bit)) continue;
      votes.push_back({v.classId, uint32_t(v.leaves[at].values[rankOf(v.leaves[at].mask, bit)])});  // >= 1: checked
    }
    out[i] = summarize(votes);
  }
  return out;
}

std::vector<VoxelColor8> SceneLeavesLookup::colors(std::span<const Coord3> voxels) const {
  std::vector<VoxelColor8> out(voxels.size(), VoxelColor8{0, 0, 0, 0});
  if (!s_.hasColor) return out;
  for (size_t i = 0; i < voxels.size(); ++i) {
    uint32_t leaf, bit;
    if (!find(voxels[i], leaf, bit)) continue;
    const uint32_t at = s_.colorAt[leaf];
    if (at == SceneLeaves::kNoLeaf) continue;
    const SceneLeaf<std::array<float, 3>>& l = s_.colorLeaves[at];
    if (!has(l.mask, bit)) continue;
    const std::array<float, 3>& c = l.values[rankOf(l.mask, bit)];
    out[i] = {linearToSrgb8(c[0]), linearToSrgb8(c[1]), linearToSrgb8(c[2]), 255};
  }
  return out;
}

}  // namespace vox
