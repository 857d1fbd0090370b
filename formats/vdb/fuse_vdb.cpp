#include "formats/vdb/fuse_vdb.h"

#include "formats/vdb/vdb_scene_grids.h"
#include "libvox/core/error.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

void writeFusedSceneVdb(const Scene& scene, FuseCounts&& free, const std::string& path) {
  ensureOpenVdbInitialized();
  const SceneHeader& h = scene.header();
  openvdb::GridPtrVec grids;
  appendSceneGrids(scene, "", {}, grids);
  openvdb::Int32Grid::Ptr grid = openvdb::Int32Grid::create(0);
  grid->setName(kFreeGridName);
  grid->setTransform(voxelCentreTransform(h.voxelSize, h.origin));
  // The counts' 8^3 bricks are OpenVDB's leaves, voxel for voxel.
  free.drainFreeBricks([&](Coord3 o, const uint32_t* n) {
    openvdb::Int32Tree::LeafNodeType* leaf = nullptr;
    for (openvdb::Index i = 0; i < 512; ++i) {
      if (!n[i]) continue;
      if (!leaf) leaf = grid->tree().touchLeaf(openvdb::Coord(o.u, o.v, o.w));
      leaf->setValueOn(i, int32_t(std::min<uint32_t>(n[i], 0x7fffffffu)));
    }
  });
  grids.push_back(grid);
  openvdb::MetaMap meta;
  insertVdbMetadata(meta, sceneFileMetadata(h));
  writeVdbFile(path, grids, meta, "scene");
}

void readFreeGrid(const std::string& path, FuseCounts& into) {
  ensureOpenVdbInitialized();
  VdbSceneFile file = readVdbSceneFile(path, /*occupancyOnly=*/false);
  for (const openvdb::GridBase::Ptr& g : file.grids) {
    if (g->getName() != kFreeGridName) continue;
    auto grid = openvdb::GridBase::grid<openvdb::Int32Grid>(g);
    if (!grid) throwBadInput(path + ": grid 'free' must be int32 (the free-space counts `vox fuse` writes)");
    grid->tree().voxelizeActiveTiles();
    const Dims d = file.header.dims;
    for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
      const openvdb::Coord o = leaf->origin();
      uint32_t* brick = nullptr;
      for (auto it = leaf->cbeginValueOn(); it; ++it) {
        const openvdb::Coord c = it.getCoord();
        const Coord3 at{c.x(), c.y(), c.z()};
        if (*it <= 0)
          throwBadInput(path + ": grid 'free' holds " + std::to_string(*it) + " at " + toString(at) +
                        "; free counts are >= 1");
        if (c.x() < 0 || c.y() < 0 || c.z() < 0 || uint32_t(c.x()) >= d.x || uint32_t(c.y()) >= d.y ||
            uint32_t(c.z()) >= d.z)
          throwBadInput(path + ": grid 'free' has a voxel " + toString(at) + " outside the dims " + toString(d));
        if (!brick) brick = into.freeBrick(Coord3{o.x(), o.y(), o.z()});
        uint32_t& n = brick[it.pos()];
        n = uint32_t(std::min<uint64_t>(uint64_t(n) + uint64_t(*it), UINT32_MAX));
      }
    }
  }
}

}  // namespace vox
