// Error of a voxelization against exact references (the command line reports
// it under "error" when asked to check a mesh bake).
//
// Surface: the brute-force oracle tests every (snapped) triangle against every
// voxel of its bounding box with the exact closed-box SAT, independently of the
// voxelizer's candidate search. With all triangles checked it reports both
// voxels missed (oracle has, scene lacks) and extra (scene has, oracle lacks);
// with a sample, only missed voxels can be attributed and extra is not reported.
//
// Solid: the mesh's enclosed volume (divergence theorem, in world units^3,
// exact up to double rounding of the input) against the occupied voxel volume,
// and IoU of occupancy against the generalised winding number of the voxel
// centre (inside when > 0.5; the brute-force sum of solid angles over all
// triangles) on a deterministic sample of voxel centres of the mesh's box.
#pragma once

#include <cstdint>
#include <optional>

#include "libvox/mesh/mesh.h"
#include "libvox/scene/scene.h"

namespace vox {

struct SurfaceCheck {
  uint64_t trianglesChecked = 0;
  uint64_t oracleVoxels = 0;  // voxels the checked triangles touch
  uint64_t missed = 0;        // oracle voxels the scene lacks
  std::optional<uint64_t> extra;  // scene voxels no triangle touches (full checks only)
};

/// Checks every triangle when `maxTriangles` >= the triangle count, otherwise an
/// evenly spaced sample of `maxTriangles` triangles.
SurfaceCheck checkSurface(const Mesh& mesh, const Scene& scene, uint64_t maxTriangles);

struct SolidCheck {
  double meshVolume = 0;    // enclosed volume, world units^3 (signed sum, absolute value)
  double voxelVolume = 0;   // occupied voxels * voxelSize^3
  double relativeVolumeError = 0;
  uint64_t samples = 0;
  double iou = 0;           // |occupied AND inside| / |occupied OR inside| over the samples
};

SolidCheck checkSolid(const Mesh& mesh, const Scene& scene, uint64_t samples);

/// Generalised winding number of `p` (world space) with respect to the mesh.
double windingNumber(const Mesh& mesh, const std::array<double, 3>& p);

}  // namespace vox
