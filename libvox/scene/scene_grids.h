// Direct access to the OpenVDB trees behind a Scene. Include only where bulk
// voxel work needs it: this pulls in OpenVDB's heavy headers.
//
// Invariants (checked by SceneBuilder::build and the .vdb reader):
//   * occupancy: active voxels are exactly the occupied voxels; the value of an
//     active voxel is its surface flag. Background false.
//   * votes[i].grid: active voxels are the voxels where class votes[i].classId has
//     >= 1 vote, value = that count (1..2^31-1); a subset of occupancy's topology.
//     Sorted by classId; only classes present.
//   * color: null when the scene has no colour; otherwise active voxels (a subset of
//     occupancy) hold linear RGB in [0, 1].
// All grids use the identity index transform; world placement is in SceneHeader.
#pragma once

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <vector>

namespace vox {

struct ClassGrid {
  uint8_t classId = 0;
  openvdb::Int32Grid::Ptr grid;
};

struct SceneGrids {
  openvdb::BoolGrid::Ptr occupancy;
  std::vector<ClassGrid> votes;
  openvdb::Vec3SGrid::Ptr color;
};

/// openvdb::initialize() once, thread-safe.
void ensureOpenVdbInitialized();

/// The index-to-world transform of a scene's grids: voxel (i,j,k) centred at
/// origin + (i + 0.5, j + 0.5, k + 0.5) * voxelSize. voxelSize must be at least
/// kMinVoxelSize (libvox/core/scene_header.h), as placementProblem checks.
openvdb::math::Transform::Ptr voxelCentreTransform(double voxelSize, const std::array<double, 3>& origin);

}  // namespace vox
