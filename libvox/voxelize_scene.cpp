// voxelizeMesh: the block voxelizer (voxelize.cpp) turned into an OpenVDB scene.
// A file of its own so that voxelize.o does not pull OpenVDB into the light
// mesh module (vox-bake.so).
#include "libvox/voxelize.h"

namespace vox {

Scene voxelizeMesh(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const SceneHeader& header,
                   const VoxelizeSettings& settings) {
  return SceneBuilder(voxelizeMeshBlocks(mesh, triangleClass, header, settings), header).build();
}

}  // namespace vox
