#include "libvox/scene/class_volume_scene.h"

#include <openvdb/openvdb.h>

#include "libvox/core/parallel.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

namespace {

bool overlaps(const openvdb::Coord& leafOrigin, const IndexBox& box) {
  const int n = ClassVolume::kBrickSide;
  return leafOrigin.x() <= box.max.u && leafOrigin.x() + n - 1 >= box.min.u && leafOrigin.y() <= box.max.v &&
         leafOrigin.y() + n - 1 >= box.min.v && leafOrigin.z() <= box.max.w && leafOrigin.z() + n - 1 >= box.min.w;
}

}  // namespace

ClassVolume classVolumeFromScene(const Scene& scene, const IndexBox& box, bool withColor, unsigned threads) {
  ClassVolume volume(box, withColor);
  const SceneGrids& g = scene.grids();
  // Readers expand tiles into voxels (Scene::forEachVoxel relies on it too):
  // every occupied voxel sits in an occupancy leaf, and an OpenVDB leaf is an
  // 8^3 block at a multiple of 8, i.e. one brick.
  std::vector<const openvdb::BoolTree::LeafNodeType*> leaves;
  for (auto leaf = g.occupancy->tree().cbeginLeaf(); leaf; ++leaf)
    if (!box.empty() && overlaps(leaf->origin(), box)) leaves.push_back(&*leaf);
  std::vector<ClassVolume::Brick> bricks(leaves.size());
  parallelForEach(leaves.size(), threads, 16, [&](size_t li) {
    const auto& occ = *leaves[li];
    const openvdb::Coord o = occ.origin();
    ClassVolume::Brick b = volume.makeBrick({o.x(), o.y(), o.z()});
    // Votes per class in ascending id order; a later class wins only with
    // strictly more votes, so ties keep the lowest id.
    std::array<int32_t, ClassVolume::kBrickVoxels> best{};
    for (const ClassGrid& cg : g.votes) {
      const auto* votes = cg.grid->tree().probeConstLeaf(o);
      if (!votes) continue;
      for (auto it = votes->cbeginValueOn(); it; ++it) {
        const openvdb::Index offset = it.pos();
        if (*it <= best[offset]) continue;
        best[offset] = *it;
        const openvdb::Coord c = openvdb::Coord(votes->offsetToLocalCoord(offset));
        b.classes[size_t(ClassVolume::voxelIndex(c.x(), c.y(), c.z()))] = cg.classId;
      }
    }
    // Vote grids are a subset of occupancy (scene_grids.h): every voxel with a
    // class is occupied, and every occupied voxel has a vote.
    if (withColor && g.color)
      if (const auto* colors = g.color->tree().probeConstLeaf(o))
        for (auto it = colors->cbeginValueOn(); it; ++it) {
          const openvdb::Coord c = openvdb::Coord(colors->offsetToLocalCoord(it.pos()));
          const int i = ClassVolume::voxelIndex(c.x(), c.y(), c.z());
          if (b.classes[size_t(i)]) b.setColor(i, {(*it)[0], (*it)[1], (*it)[2]});
        }
    bricks[li] = std::move(b);
  });
  for (ClassVolume::Brick& b : bricks) volume.add(std::move(b));
  volume.finish();
  return volume;
}

}  // namespace vox
