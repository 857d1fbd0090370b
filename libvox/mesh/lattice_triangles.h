// A mesh's triangles as the exact voxelizer (voxelize.h) decides on them:
// every vertex snapped to the lattice (grid x 2^kSubvoxelBits, integers), and
// the triangles that reach beyond the lattice's range clipped to a box around
// the grid.
//
// Range: the voxelizer's integer arithmetic holds lattice points within
// kMaxLatticeDistance voxels of the grid's origin. A triangle with a vertex
// beyond (a city's ground plane under a small --bounds crop, a stray vertex,
// a fine voxel size) is, for a surface fill:
//   * dropped when it misses the clip box: the grid grown by kFarClipMargin
//     voxels on every side;
//   * else replaced by its part inside the clip box (clipped in long double
//     from the vertices' grid coordinates), fan-triangulated from the
//     polygon's first vertex, the new vertices snapped like any other.
// Every voxel of the grid lies inside the clip box, so it meets the clipped
// part exactly where it meets the whole triangle; the new edges lie
// kFarClipMargin voxels outside the grid, where no voxel sees them. Bound:
// every vertex the clip makes lies on the clip box's boundary (that
// coordinate exact) and within 2^-56 R of a point of the original triangle
// (the long double clip's rounding, generously counted; R the largest grid
// coordinate of the triangle: under 2^-20 voxel while R < 2^36), and
// snapping moves it by at most half a lattice step (2^-17 voxel) per axis.
// A fan triangle's points are convex combinations of its vertices, so the
// clipped surface inside the grid lies within 2^-17 voxel (plus that
// rounding) of the original triangle: the bound snapping sets for every
// triangle. (A far vertex's own grid coordinate, (world - origin) /
// voxelSize in double, is uncertain by R 2^-53 already.) Votes: each fan
// triangle rounds its own area in a voxel, so a voxel's votes from a clipped
// triangle are its area to within one vote (2^-16 voxel face) per fan
// triangle there; colours and texture coordinates are interpolated in the
// original triangle (LatticeTriangles::toSource).
//
// A solid fill decides inside by every triangle (rays to infinity, winding
// numbers), so clipping would change it: it refuses a vertex beyond the range,
// naming the vertex and the fixes.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "libvox/core/scene_header.h"
#include "libvox/mesh/mesh.h"

namespace vox {

/// How far a vertex may lie from the grid's origin, in voxels along each
/// axis, to be snapped as it is.
inline constexpr double kMaxLatticeDistance = double(1 << 20);
/// How far the clip box reaches beyond the grid on every side, in voxels
/// (8 blocks of 8^3).
inline constexpr double kFarClipMargin = 64;

/// What becomes of the triangles with a vertex beyond kMaxLatticeDistance.
enum class FarTriangles {
  Clip,    // dropped or clipped to the box around the grid (a surface fill)
  Refuse,  // refused, naming the first such vertex (a solid fill)
};

struct LatticeTriangles {
  /// Per vertex, in lattice units: the mesh's vertices (those beyond the
  /// range, referenced by no triangle here, are 0), then those the clip made.
  std::vector<std::array<int64_t, 3>> lattice;
  /// Whether any triangle was dropped or clipped; when not, the triangles
  /// are the mesh's own and the members below are empty.
  bool clipped = false;
  /// With `clipped`: the triangles (into `lattice`), the mesh's kept ones in
  /// their order, then the clip's fans from firstFan on.
  std::vector<std::array<uint32_t, 3>> triangles;
  /// With `clipped`: per triangle, the mesh triangle it is or is part of.
  std::vector<uint32_t> source;
  size_t firstFan = 0;
  /// With `clipped`: per fan triangle (from firstFan), the barycentric
  /// coordinates of each of its corners in the source triangle (for its
  /// colours and texture coordinates).
  std::vector<std::array<std::array<double, 3>, 3>> fanWeights;
  size_t dropped = 0;  // mesh triangles dropped (outside the clip box)

  /// Triangle t's vertices (into `lattice`), t < size().
  const std::array<uint32_t, 3>& corners(const Mesh& mesh, size_t t) const {
    return clipped ? triangles[t] : mesh.triangles[t];
  }
  size_t size(const Mesh& mesh) const { return clipped ? triangles.size() : mesh.triangles.size(); }
  uint32_t sourceOf(size_t t) const { return clipped ? source[t] : uint32_t(t); }
  /// Barycentric coordinates (l0, l1, l2) in triangle t turned into the same
  /// point's in its source triangle (unchanged for the mesh's own triangles).
  void toSource(size_t t, double& l0, double& l1, double& l2) const {
    if (!clipped || t < firstFan) return;
    const auto& w = fanWeights[t - firstFan];
    const double a = l0, b = l1, c = l2;
    l0 = a * w[0][0] + b * w[1][0] + c * w[2][0];
    l1 = a * w[0][1] + b * w[1][1] + c * w[2][1];
    l2 = a * w[0][2] + b * w[1][2] + c * w[2][2];
  }
};

/// `mesh`'s triangles on the lattice of `header`'s grid (see the top of this
/// file). Refuses (vox::Error BadInput) a non-finite vertex, and with
/// FarTriangles::Refuse a vertex beyond the range.
LatticeTriangles latticeTriangles(const Mesh& mesh, const SceneHeader& header, FarTriangles far);

}  // namespace vox
