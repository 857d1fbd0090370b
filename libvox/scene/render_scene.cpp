// Scene -> RayGrid and summary lookups (the OpenVDB side of render_scene.h).
#include <openvdb/openvdb.h>

#include "libvox/core/color.h"
#include "libvox/scene/render_scene.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

RayGrid rayGridFromScene(const Scene& scene) {
  RayGrid grid(scene.header().dims);
  const openvdb::BoolTree& tree = scene.grids().occupancy->tree();
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
    const openvdb::Coord o = leaf->origin();
    if (o.x() < 0 || o.y() < 0 || o.z() < 0) continue;  // outside the domain: never occupied in a valid scene
    RayGrid::Mask512 m;
    const auto& vm = leaf->getValueMask();
    for (int i = 0; i < 8; ++i) m[size_t(i)] = vm.template getWord<openvdb::Index64>(openvdb::Index(i));
    grid.addBrick(uint32_t(o.x()) >> 3, uint32_t(o.y()) >> 3, uint32_t(o.z()) >> 3, m);
  }
  // Active tiles (constant blocks of 8^3 or more): every brick they cover is full.
  RayGrid::Mask512 full;
  full.fill(~uint64_t(0));
  auto it = tree.cbeginValueOn();
  it.setMaxDepth(openvdb::BoolTree::ValueOnCIter::LEAF_DEPTH - 1);  // tiles only, not every voxel
  for (; it; ++it) {
    if (it.isVoxelValue()) continue;
    const openvdb::CoordBBox b = it.getBoundingBox();
    const openvdb::Coord lo = openvdb::Coord::maxComponent(b.min(), openvdb::Coord(0));
    for (int x = lo.x() >> 3; x <= b.max().x() >> 3; ++x)
      for (int y = lo.y() >> 3; y <= b.max().y() >> 3; ++y)
        for (int z = lo.z() >> 3; z <= b.max().z() >> 3; ++z) grid.addBrick(uint32_t(x), uint32_t(y), uint32_t(z), full);
  }
  grid.finish();
  return grid;
}

std::vector<SummaryTexel> sceneSummaries(const Scene& scene, std::span<const Coord3> voxels) {
  const SceneGrids& g = scene.grids();
  auto occ = g.occupancy->getConstAccessor();
  std::vector<openvdb::Int32Grid::ConstAccessor> acc;
  for (const ClassGrid& cg : g.votes) acc.push_back(cg.grid->getConstAccessor());
  std::vector<SummaryTexel> out(voxels.size());
  std::vector<ClassVotes> votes;
  for (size_t i = 0; i < voxels.size(); ++i) {
    const openvdb::Coord c(voxels[i].u, voxels[i].v, voxels[i].w);
    if (!occ.isValueOn(c)) continue;
    votes.clear();
    for (size_t k = 0; k < acc.size(); ++k) {
      int32_t n = 0;
      if (acc[k].probeValue(c, n) && n > 0) votes.push_back({g.votes[k].classId, uint32_t(n)});
    }
    out[i] = summarize(votes);
  }
  return out;
}

std::vector<VoxelColor8> sceneColors(const Scene& scene, std::span<const Coord3> voxels) {
  std::vector<VoxelColor8> out(voxels.size(), VoxelColor8{0, 0, 0, 0});
  const SceneGrids& g = scene.grids();
  if (!g.color) return out;
  auto acc = g.color->getConstAccessor();
  for (size_t i = 0; i < voxels.size(); ++i) {
    openvdb::Vec3s c;
    if (!acc.probeValue(openvdb::Coord(voxels[i].u, voxels[i].v, voxels[i].w), c)) continue;
    out[i] = {linearToSrgb8(c[0]), linearToSrgb8(c[1]), linearToSrgb8(c[2]), 255};
  }
  return out;
}

}  // namespace vox
