#include "formats/vdb/scene_leaves_class_volume.h"

#include <bit>

#include "libvox/core/parallel.h"

namespace vox {

namespace {

bool overlaps(const std::array<int32_t, 3>& leafOrigin, const IndexBox& box) {
  const int n = ClassVolume::kBrickSide;
  return leafOrigin[0] <= box.max.u && leafOrigin[0] + n - 1 >= box.min.u && leafOrigin[1] <= box.max.v &&
         leafOrigin[1] + n - 1 >= box.min.v && leafOrigin[2] <= box.max.w && leafOrigin[2] + n - 1 >= box.min.w;
}

/// Calls f(offset, rank) for each set bit of a leaf mask in ascending offset:
/// `rank` is the slot of that voxel's value in SceneLeaf::values.
template <typename F>
void forEachActive(const std::array<uint64_t, 8>& mask, F&& f) {
  uint32_t rank = 0;
  for (uint32_t w = 0; w < 8; ++w)
    for (uint64_t bits = mask[w]; bits; bits &= bits - 1) f(w * 64 + uint32_t(std::countr_zero(bits)), rank++);
}

/// A leaf offset (OpenVDB's order, 64 x + 8 y + z) as a brick index (x fastest).
int brickIndexOf(uint32_t offset) {
  return ClassVolume::voxelIndex(int(offset >> 6), int((offset >> 3) & 7), int(offset & 7));
}

}  // namespace

ClassVolume classVolumeFromLeaves(const SceneLeaves& scene, const IndexBox& box, bool withColor, unsigned threads) {
  ClassVolume volume(box, withColor);
  // The reader keeps only leaves (no tiles), and each is one 8^3 brick.
  std::vector<uint32_t> leaves;
  for (size_t i = 0; i < scene.occupancy.size(); ++i)
    if (!box.empty() && overlaps(scene.occupancy[i].origin, box)) leaves.push_back(uint32_t(i));
  std::vector<ClassVolume::Brick> bricks(leaves.size());
  parallelForEach(leaves.size(), threads, 16, [&](size_t li) {
    const uint32_t leaf = leaves[li];
    const auto& o = scene.occupancy[leaf].origin;
    ClassVolume::Brick b = volume.makeBrick({o[0], o[1], o[2]});
    // Votes per class in ascending id order; a later class wins only with
    // strictly more votes, so ties keep the lowest id.
    std::array<int32_t, ClassVolume::kBrickVoxels> best{};
    for (const SceneLeaves::Votes& v : scene.votes) {
      const uint32_t at = v.at[leaf];
      if (at == SceneLeaves::kNoLeaf) continue;
      const SceneLeaf<int32_t>& votes = v.leaves[at];
      forEachActive(votes.mask, [&](uint32_t offset, uint32_t rank) {
        const int32_t n = votes.values[rank];
        if (n <= best[offset]) return;
        best[offset] = n;
        b.classes[size_t(brickIndexOf(offset))] = v.classId;
      });
    }
    // Votes and colours lie at occupied voxels only (readSceneLeaves checks it).
    if (withColor && scene.hasColor && scene.colorAt[leaf] != SceneLeaves::kNoLeaf) {
      const SceneLeaf<std::array<float, 3>>& colors = scene.colorLeaves[scene.colorAt[leaf]];
      forEachActive(colors.mask, [&](uint32_t offset, uint32_t rank) {
        const int i = brickIndexOf(offset);
        const std::array<float, 3>& c = colors.values[rank];
        if (b.classes[size_t(i)]) b.setColor(i, {c[0], c[1], c[2]});
      });
    }
    bricks[li] = std::move(b);
  });
  for (ClassVolume::Brick& b : bricks) volume.add(std::move(b));
  volume.finish();
  return volume;
}

}  // namespace vox
