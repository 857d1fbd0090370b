// Error of a voxelization against exact references (the command line reports
// it under "error" when asked to check a mesh bake).
//
// Surface: the brute-force oracle tests every (snapped) triangle against every
// voxel of its bounding box (a triangle reaching more than 2^20 voxels from the
// grid: its part near the grid, clipped as the bake clips it,
// libvox/mesh/lattice_triangles.h) with the exact closed-box SAT, independently of the
// voxelizer's candidate search. With all triangles checked it reports both
// voxels missed (oracle has, scene lacks) and extra (scene has, oracle lacks);
// with a sample, only missed voxels can be attributed and extra is not reported.
//
// Solid: the mesh's enclosed volume (divergence theorem, in world units^3,
// exact up to double rounding of the input) against the occupied voxel volume,
// and the interior IoU: over the voxels that are not surface voxels of the
// scene (those are occupied by definition), occupancy against |generalised
// winding number| > 0.5 at the voxel centre (the brute-force sum of solid
// angles over all triangles, in long double), at every voxel centre of the
// occupied bounds grown by one voxel when `samples` covers them, otherwise on
// an evenly strided lattice of about `samples` centres.
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
  uint64_t samples = 0;      // interior (non-surface) centres compared
  int32_t stride = 1;        // 1: every centre of the box
  double iou = 0;            // |occupied AND inside| / |occupied OR inside| over the samples
  uint64_t missed = 0;       // inside, not occupied
  uint64_t extra = 0;        // occupied (interior), not inside
};

SolidCheck checkSolid(const Mesh& mesh, const Scene& scene, uint64_t samples, unsigned threads = 1);

/// Generalised winding number of `p` (world space) with respect to the mesh
/// (Van Oosterom-Strackee solid angles summed in long double).
double windingNumber(const Mesh& mesh, const std::array<double, 3>& p);

/// |windingNumber(mesh, p)| > 0.5, the reference checkSolid compares with:
/// summed in double, and in long double only where the double sum is within
/// 1e-6 of 0.5 (its error is ~1e-15 per triangle for points off the surface),
/// so the answer is the long double one's at about a fifth of the cost.
bool insideByWinding(const Mesh& mesh, const std::array<double, 3>& p);

}  // namespace vox
