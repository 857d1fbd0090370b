// The exact mesh voxelizer (libvox/mesh/voxelize.h) with its blocks turned
// into an OpenVDB-backed Scene. A file of its own so that the voxelizer does not
// pull OpenVDB into the light mesh module (vox-bake.so).
#pragma once

#include "libvox/mesh/voxelize.h"
#include "libvox/scene/scene.h"

namespace vox {

/// voxelizeMeshBlocks, validated and built into a Scene (see voxelize.h for
/// the contract on `triangleClass`, votes and colour).
Scene voxelizeMesh(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const SceneHeader& header,
                   const VoxelizeSettings& settings);

}  // namespace vox
