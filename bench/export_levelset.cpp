// vox_export_levelset SCENE.vdb OUT.vdb [--fog]: the occupancy of a vox scene as
// a narrow-band level set (FloatGrid "surface", OpenVDB's topologyToLevelSet)
// or, with --fog, a fog volume (1 inside occupied voxels), in the scene's world
// placement, so that vdb_render can render the same voxels vox render-canonical
// does (scripts/bench_render.sh). A benchmarking aid, not part of vox.
#include <openvdb/openvdb.h>
#include <openvdb/tools/TopologyToLevelSet.h>

#include <cstdio>
#include <cstring>

#include "formats/vdb/scene_vdb.h"
#include "libvox/scene/scene_grids.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: vox_export_levelset SCENE.vdb OUT.vdb [--fog]\n");
    return 2;
  }
  const bool fog = argc > 3 && std::strcmp(argv[3], "--fog") == 0;
  try {
    const vox::Scene scene = vox::readSceneVdb(argv[1]);
    const vox::SceneHeader& h = scene.header();
    openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(h.voxelSize);
    xf->postTranslate(openvdb::Vec3d(h.origin[0] + h.voxelSize / 2, h.origin[1] + h.voxelSize / 2,
                                     h.origin[2] + h.voxelSize / 2));
    openvdb::FloatGrid::Ptr out;
    if (fog) {
      out = openvdb::FloatGrid::create(0.f);
      out->tree().topologyUnion(scene.grids().occupancy->tree());
      for (auto it = out->tree().beginValueOn(); it; ++it) it.setValue(1.f);
      out->setGridClass(openvdb::GRID_FOG_VOLUME);
      out->setName("density");
    } else {
      // topologyToLevelSet measures distances with the input's transform.
      openvdb::BoolGrid::Ptr occ = scene.grids().occupancy->deepCopy();
      occ->setTransform(xf);
      out = openvdb::tools::topologyToLevelSet(*occ, 3, 0, 0, 0);
      out->setName("surface");
    }
    out->setTransform(xf);
    openvdb::io::File(argv[2]).write({out});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vox_export_levelset: %s\n", e.what());
    return 3;
  }
  return 0;
}
