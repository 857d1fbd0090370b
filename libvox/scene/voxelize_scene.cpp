#include "libvox/scene/voxelize_scene.h"

namespace vox {

Scene voxelizeMesh(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const SceneHeader& header,
                   const VoxelizeSettings& settings) {
  return SceneBuilder(voxelizeMeshBlocks(mesh, triangleClass, header, settings), header).build();
}

}  // namespace vox
