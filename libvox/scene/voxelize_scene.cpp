#include "libvox/scene/voxelize_scene.h"

namespace vox {

Scene voxelizeMesh(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const SceneHeader& header,
                   const VoxelizeSettings& settings) {
  SceneBuilder builder(voxelizeMeshBlocks(mesh, triangleClass, header, settings), header);
  if (settings.leaveOutClassesWithoutVotes) builder.leaveOutClassesWithoutVotes(*settings.leaveOutClassesWithoutVotes);
  return std::move(builder).build();
}

}  // namespace vox
