// Generalised winding number of an open triangle mesh, split as
//   w_mesh(p) = W_capped(p) - w_caps(p)
// where the caps close every boundary loop of the mesh (any surface spanning
// the loops gives the same w_mesh; a balanced triangulation of each loop),
// W_capped is the winding number of the closed, capped mesh (an exact
// integer: the voxelizer counts signed ray crossings), and w_caps is the
// solid-angle sum over the cap triangles only, evaluated here.
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
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vox {

using LatticePoint = std::array<int64_t, 3>;

struct CapTriangle {
  LatticePoint v[3];
  uint32_t sourceTriangle;  // a mesh triangle owning a boundary edge it spans (for its class)
};

/// The cap triangles closing every boundary loop of (triangles, lattice). Empty
/// for closed, consistently oriented meshes. Deterministic (order of first
/// appearance of the boundary edges in triangle order). The boundary is split
/// into closed walks; walks that come within one voxel of each other (an
/// unwelded seam: two rims side by side, running in opposite directions) are
/// joined into one by pairs of opposite bridge edges, which cancel. Each walk
/// is triangulated by cutting ears, the one leaving the shortest new edge
/// first: the caps are no wider than the hole (a seam or slit is zipped
/// across, a round hole cut in rounds doubling inwards), n - 2 triangles for n
/// edges (some of zero area). A cap triangle's sourceTriangle owns the first
/// boundary edge it spans.
std::vector<CapTriangle> capBoundaryLoops(const std::vector<std::array<uint32_t, 3>>& triangles,
                                          const std::vector<LatticePoint>& lattice);

/// Lattice steps within which distinct vertices count as one for the solid
/// fill (2^-10 voxel at 2^16 steps per voxel): float noise in a soup's shared
/// corners (an STL written from transformed coordinates) is a few steps.
constexpr int64_t kWeldSteps = 64;

/// `lattice` with every cluster of vertices closer than `steps` on every axis
/// (chained) moved onto its lowest-index member, so that a triangle soup whose
/// shared corners differ by rounding noise is closed for capBoundaryLoops and
/// the crossing count, instead of one loop per triangle. A cluster wider than
/// 4 x `steps` on some axis, or a crowd of more than 1024 distinct positions in
/// one cell of side `steps`, is left as it is: vertices then move at most
/// 4 x `steps`. Empty when nothing moves (use `lattice` itself).
/// Deterministic (no dependence on hashing or threads).
std::vector<LatticePoint> weldNearVertices(const std::vector<LatticePoint>& lattice, int64_t steps);

/// Signed solid angle of triangle (a, b, c) seen from the origin (Van
/// Oosterom-Strackee), in steradians, in (-2pi, 2pi). Inline: it is the inner
/// loop of the caps' field and of --check's reference (out of line, --check
/// took 1.4x the time). `det` gets det(a, b, c): |n| times the origin's
/// distance from the triangle's plane, n = (b - a) x (c - a), signed.
inline double triangleSolidAngle(const double a[3], const double b[3], const double c[3], double& det) {
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  const double lc = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
  const double ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
  const double den = la * lb * lc + ab * lc + bc * la + ca * lb;
  return 2.0 * std::atan2(det, den);
}
/// The same without the determinant.
inline double triangleSolidAngle(const double a[3], const double b[3], const double c[3]) {
  double det;
  return triangleSolidAngle(a, b, c, det);
}

/// The caps' solid-angle field with a bound over balls, in voxel units.
///
/// Why the bound is tight: off the caps, the gradient of a surface's solid
/// angle depends only on the surface's boundary (Biot-Savart: grad Omega(q) =
/// the line integral over the boundary of dl x (x - q) / |x - q|^3), and the
/// caps' boundary is the mesh's boundary loops (the caps' inner edges cancel).
/// So |grad w_caps(q)| <= (1 / 4pi) sum_e len_e / dist(q, e)^2 over the
/// boundary edges e, however large the caps are, and a ball far from the
/// holes' rims varies little even where it is close to a cap. Across a cap
/// triangle w_caps jumps by exactly 1 (the solid angle by 4pi); those jumps are
/// counted per point (`jumps`), so a ball may cut through caps too.
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
  /// The same reach from the caps alone, without building the field's trees
  /// (the fill's box is grown by it before the field is needed).
  static double reachOf(const std::vector<CapTriangle>& caps);

  /// w_caps(p) = sum of solid angles / 4pi over every cap triangle (exact up
  /// to double rounding, ~1e-15 per triangle). At a lattice point (voxel
  /// centres are) within 1e-9 voxel of a cap's plane, that cap counts as the
  /// fill's +z crossing count W does, whose integer jumps there: a crossing at
  /// the point's height is above it, and rays through an edge or vertex are
  /// owned by the top-left rule, so W is the capped mesh's winding number at
  /// p + eta, eta = -(eps z + delta x + delta' y), eps >> delta >> delta' > 0,
  /// and the cap's solid angle is its limit there (exact integer tests; on
  /// the cap +-2pi, on its edges and corners the tangent cone's angle). So
  /// W - w_caps(p) is w_mesh(p) also on a cap; at p itself the formula gives
  /// each cap through p half a jump or none by the sign of a rounded zero.
  double winding(const double p[3]) const;

  /// The field over the ball of points within `radius` of `centre`, as two
  /// models with rigorous bounds, for any p in the ball, d = |p - centre|:
  ///   |w_caps(p) - value - jump(p)| <= slope * d + valueError + slack
  ///   |w_caps(p) - value - jump(p) - gradient . (p - centre)|
  ///       <= curvature * d^2 + gradientError * d + valueError + slack
  /// with gap_e = dist(centre, e) - radius > 0 for every boundary edge e:
  ///   slope = (1 / 4pi) sum_e len_e / gap_e^2 (the gradient bound above),
  ///   curvature = (1 / 4pi) sum_e len_e / gap_e^3 (the Biot-Savart kernel's
  ///   derivative is at most 2 / r^3, and the Taylor remainder halves it).
  /// value and gradient sum two bounding-sphere trees (Barill et al. 2018's
  /// hierarchy, first order): near leaves exactly (every triangle's solid
  /// angle, Van Oosterom-Strackee; every edge's Biot-Savart integral in closed
  /// form), clusters farther than kFar radii by their dipole, area vector .
  /// K(m) for triangles and K(m) x (sum of edges) for edges, K(x) = (x -
  /// centre) / |x - centre|^3, whose error is at most size * r * 2 / clear^3
  /// (size: area or length, r: the cluster's radius, clear: its distance from
  /// the centre; K's derivative is at most 2 / |x|^3): valueError and
  /// gradientError sum these / 4pi; a far edge cluster bounds its edges' part
  /// of slope and curvature by length / gap^2 and / gap^3 (gap: the cluster's
  /// distance from the ball). Each is times (1 + 1e-9); slack = 1e-9 + 1e-12 *
  /// (radius * (|gradient| + slope) + |value|) covers double rounding.
  struct Ball {
    double centre[3];
    double radius;
    double value;        // w_caps(centre), within valueError
    double gradient[3];  // grad w_caps(centre), within gradientError (Euclidean norm)
    double slope, curvature, slack;
    double valueError, gradientError;  // of the far clusters' dipole approximations
    /// |w_caps(p)| <= magnitude anywhere in the ball: sum over the caps of
    /// min(2pi, A_t / D_t^2) / 4pi, with or without rims or caps in the ball.
    double magnitude;
    /// slope, curvature and the gradient hold (no rim within the ball); else
    /// they are infinite and only `magnitude` bounds the field.
    bool rimsClear;
    std::vector<uint32_t> cut;  // cap triangles the ball reaches (their jumps count)
  };
  /// Where the ball stays off every cap triangle, slope and curvature are the
  /// smaller of those and the same bounds from the caps' area: (1 / 4pi) sum_t
  /// 2 A_t / D_t^3 and 3 A_t / D_t^4 (D_t: the triangle's or its far cluster's
  /// distance from the ball; the solid angle's kernel has derivatives of at most
  /// 2 / D^3 and 6 / D^4). Why: along a seam or narrow slit the rims' terms add
  /// up although their fields cancel, while the cap between them has almost no
  /// area.
  /// A point (radius 0) gets the value alone: slope, curvature and gradient 0;
  /// a lattice point takes the caps within 1e-9 voxel of it as winding() does,
  /// with no cut triangles.
  /// A ball that reaches a boundary edge (a rim) gets rimsClear false: no
  /// gradient, infinite curvature and gradientError, the area's slope where it
  /// stays off every cap (else infinite), and `magnitude`, which holds anyway.
  /// Fills `ball` and returns true, or false when its centre lies on a cap
  /// plane it reaches (no bound: split the ball, or evaluate the point exactly)
  /// and is not a lattice point of radius 0.
  bool ballField(const double centre[3], double radius, Ball& ball) const;

  /// An upper bound on |w_caps(p)| over the ball (sum of min(2pi, A_t / D_t^2)
  /// / 4pi, clusters that clear the ball by their radius taken whole), or
  /// `limit` as soon as it reaches `limit`. Evaluates no solid angle: a cheap
  /// first test where caps are thin strips (seams) or far away.
  double magnitudeBound(const double centre[3], double radius, double limit) const;

  /// The jump of w_caps along the segment ball.centre -> p (p in the ball):
  /// -1 for each cut triangle crossed from its back (where its solid angle is
  /// positive) to its front, +1 the other way. Returns false when p or the
  /// crossing point lies within ~1e-9 voxel of a triangle's plane or edge (no
  /// reliable count: evaluate p exactly instead).
  bool jumps(const Ball& ball, const double p[3], int& jump) const;

 private:
  struct Tri {
    double v[3][3];
    double n[3];          // (v1 - v0) x (v2 - v0): front side where n.(p - v0) > 0
    double invN;          // 1 / |n|
    double invEdgeN[3];   // 1 / (|n| |v[i+1] - v[i]|)
    double s[3], r;       // bounding sphere (quick rejection)
  };
  struct Edge {
    double a[3], d[3];  // a + t d, t in [0, 1]
    double len;
  };
  /// A node of a bounding-sphere tree over triangles or edges: items
  /// [begin, end) in tree order, children left/right (0 for a leaf), and the
  /// sums a far node is approximated by: triangles: area, area vector (n / 2);
  /// edges: length, vector sum of the edges.
  struct Node {
    double m[3], r;
    uint32_t begin, end, left, right;
    double size, vec[3];
  };
  /// t's solid angle at the lattice point p as the crossing count sees it
  /// (the limit from p + eta, winding()).
  static double countedAngle(const Tri& t, const LatticePoint& p);
  template <class Item, class Points>
  static std::vector<Node> buildTree(std::vector<Item>& items, Points points);
  static constexpr uint32_t kLeafSize = 4;
  static constexpr double kFar = 3.0;
  std::vector<Tri> tris_;    // in triTree_ order
  std::vector<Edge> edges_;  // the caps' boundary: the mesh's boundary edges, in edgeTree_ order
  std::vector<Node> triTree_, edgeTree_;
  double area_ = 0;
};

}  // namespace vox
