// Mesh -> scene through OpenVDB's meshToVolume (a narrow-band signed distance
// field): an alternative to the exact voxelizer (VoxelizeMethod::Sdf on the
// command line), so reports can set its error and run time beside the exact one's.
//
// A voxel is a surface voxel when the distance from its centre to the mesh is
// at most half its diagonal (sqrt(3)/2 voxel: every voxel a triangle touches,
// and some it does not); solid fill adds the voxels whose centre OpenVDB's
// sign computation puts inside. Each voxel gets kInteriorVotes votes for the
// class of its closest triangle (OpenVDB's closest-polygon index). No colour.
// Meshes that are not closed get whatever sign OpenVDB's flood fill decides.
#pragma once

#include <vector>

#include "libvox/scene/voxelize_scene.h"

namespace vox {

Scene voxelizeMeshSdf(const Mesh& mesh, const std::vector<uint8_t>& triangleClass, const SceneHeader& header,
                      const VoxelizeSettings& settings);

}  // namespace vox
