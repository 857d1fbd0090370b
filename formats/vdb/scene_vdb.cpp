#include "formats/vdb/scene_vdb.h"

#include <fstream>

#include "formats/vdb/vdb_scene_grids.h"
#include "libvox/scene/scene_grids.h"

namespace vox {

void writeSceneVdb(const Scene& scene, const std::string& path) {
  ensureOpenVdbInitialized();
  openvdb::GridPtrVec grids;
  appendSceneGrids(scene, "", {}, grids);
  openvdb::MetaMap meta;
  insertVdbMetadata(meta, sceneFileMetadata(scene.header()));
  writeVdbFile(path, grids, meta, "scene");
}

Scene readSceneVdb(const std::string& path) { return readSceneVdb(path, SceneParts::All); }

Scene readSceneVdb(const std::string& path, SceneParts parts) {
  const bool occupancyOnly = parts == SceneParts::OccupancyOnly;
  VdbSceneFile file = readVdbSceneFile(path, occupancyOnly);
  Scene scene;
  scene.header() = std::move(file.header);
  scene.grids() = levelGridsFromVdb(file.grids, "", scene.header(), path, /*checkTopology=*/!occupancyOnly);
  return scene;
}

Scene readSceneVdb(VdbTopologyWalk& walked) {
  const std::string path = walked.path();
  VdbSceneFile file = readVdbSceneFile(walked, /*occupancyOnly=*/false);
  Scene scene;
  scene.header() = std::move(file.header);
  scene.grids() = levelGridsFromVdb(file.grids, "", scene.header(), path, /*checkTopology=*/true);
  return scene;
}

}  // namespace vox
