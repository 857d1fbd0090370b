// Generalised winding number of an open triangle mesh, split as
//   w_mesh(p) = W_capped(p) - w_caps(p)
// where the caps close every boundary loop of the mesh (a fan of each loop
// around its centroid), W_capped is the winding number of the closed, capped
// mesh (an exact integer: the voxelizer counts signed ray crossings), and
// w_caps is the solid-angle sum over the cap triangles only (few: they span
// the holes), evaluated here.
//
// Units: grid space in lattice steps (2^-kSubvoxelBits voxel, as
// libvox/mesh/voxelize.h snaps vertices); points as doubles in voxel units.
//
// Boundary: the mesh's net directed edges (count(a->b) - count(b->a) != 0)
// after welding vertices with equal lattice coordinates, so triangle soups
// (STL) whose triangles share positions but not indices count as closed. The
// caps' boundary is exactly minus the mesh's, so mesh + caps has no boundary
// and W_capped is an integer everywhere off the surface.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vox {

using LatticePoint = std::array<int64_t, 3>;

struct CapTriangle {
  LatticePoint v[3];
  uint32_t sourceTriangle;  // a mesh triangle owning the boundary edge (for its class)
};

/// The cap triangles closing every boundary loop of (triangles, lattice). Empty
/// for closed, consistently oriented meshes. Deterministic (order of first
/// appearance of the boundary edges in triangle order).
std::vector<CapTriangle> capBoundaryLoops(const std::vector<std::array<uint32_t, 3>>& triangles,
                                          const std::vector<LatticePoint>& lattice);

/// Signed solid angle of triangle (a, b, c) seen from the origin (Van
/// Oosterom-Strackee), in steradians, in (-2pi, 2pi).
double triangleSolidAngle(const double a[3], const double b[3], const double c[3]);

/// The caps' solid-angle field with a far-field bound, in voxel units.
class CapField {
 public:
  explicit CapField(const std::vector<CapTriangle>& caps);
  bool empty() const { return tris_.empty(); }
  size_t size() const { return tris_.size(); }
  /// Distance (voxels) from the caps beyond which |w_caps| < 0.5: since
  /// |Omega_t(p)| <= A_t / d^2, |w_caps| <= A / (4 pi d^2) < 0.5 once d^2 > A / (2 pi).
  /// Outside the capped mesh's bounding box the integer part is 0, so |w| > 0.5
  /// needs a point within this distance of the box.
  double reach() const;

  /// w_caps(p) = sum of solid angles / 4pi over the triangles in `which` (all when null).
  double winding(const double p[3], const std::vector<uint32_t>* which = nullptr) const;

  /// Splits the triangles for a block of points within distance `radius` of
  /// `centre`: far ones (the block's ball does not reach their bounding
  /// sphere) are summed at the centre into `farValue` with `farBound` bounding
  /// |w_far(p) - w_far(centre)| over the block; the rest go to `near`.
  /// Bound: |grad Omega_t(p)| <= 2 A_t / d^3 (the integrand's gradient
  /// |-n + 3 (r.n) r / |r|^2| / |r|^3 <= 2 / |r|^3), d >= |centre - s_t| - r_t -
  /// radius from the triangle's bounding sphere (s_t, r_t), so
  /// |dw| <= radius * sum_t 2 A_t / (4 pi d^3), plus 1e-9 for rounding.
  void splitForBlock(const double centre[3], double radius, double& farValue, double& farBound,
                     std::vector<uint32_t>& near) const;

 private:
  struct Tri {
    double v[3][3];
    double s[3];
    double r, area;
  };
  std::vector<Tri> tris_;
};

}  // namespace vox
