// OBJ and PLY faces with more than 3 corners cut into triangles. A fan from
// the first corner is a triangulation only of a convex polygon: on a concave
// one (an L, a U, a star, a text outline) its triangles cover area outside the
// polygon, and the voxelizer fills voxels there. So convex polygons keep the
// fan (exact, cheapest, and the triangles files always gave), and the others
// are cut by ear clipping.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vox {

/// Buffers triangulatePolygon reuses from one polygon to the next (a reader
/// keeps one: no allocation per face).
struct PolygonScratch {
  std::vector<std::array<double, 2>> at;
  std::vector<uint32_t> prev, next, reflex, cellStart, cellFill, cellItems;
  std::vector<uint8_t> convex, removed;
};

/// The polygon's triangles, appended to `out` as triples of corner indices
/// (0 .. n-1, into `corners`), each wound as the polygon: n - 2 of them for
/// n >= 3 corners (none for fewer), so shared edges stay shared and a closed
/// mesh stays closed. Decided on the corners' coordinates alone, with exact
/// orientation tests: the same triangles on every machine, at any thread count.
///
/// * The polygon is seen in 2D along the largest axis of its Newell normal (the
///   coordinates the file gives, no rounding: for a planar polygon an affine
///   view of its plane, so convexity, simplicity and winding are kept, and
///   every decision below, an orientation sign, is the same along any axis:
///   a planar polygon's triangles do not depend on the axis chosen). Not the
///   projection onto the normal's plane itself, whose rounded coordinates
///   would make collinear corners merely nearly so.
/// * Convex there (every corner turns the same way or not at all, no corner
///   turns back, and the boundary goes round once): the fan (0, k, k+1), as
///   before. Collinear and repeated corners are convex corners that do not
///   turn; a non-planar polygon is convex or not as seen so (a slightly
///   twisted quad keeps its fan).
/// * A non-convex quad (a dart) is cut along the diagonal through its reflex
///   corner: the fan where that is corner 0 or 2 (the fan is then valid, and
///   kept), else (1, 2, 3), (1, 3, 0).
/// * Otherwise ear clipping (Meisters' two-ears theorem; the corners walked in
///   order, a corner cut off when it turns the polygon's way and no corner that
///   does not (reflex, collinear or repeated) lies in or on its triangle).
///   Every simple polygon has such ears, so this covers exactly the polygon.
/// * When no corner is such an ear (a self-intersecting polygon; collinear
///   corners left over), the first corner in the walk that does not turn is cut
///   off (a zero-area triangle), else the first one turning the polygon's way,
///   else the corner the walk is at. A self-intersecting polygon (a pentagram,
///   a bow tie) has no inside that tools agree on: it gets n - 2 triangles
///   this way, which may overlap or leave out parts that another tool fills.
///   Past 32 n + 1024 ear tests (simple polygons take about 2 n; scrambled
///   self-intersecting ones n per triangle) the corners left are fanned, so a
///   face costs at most about n^1.5, never n^2 walks.
/// * No Newell normal (every corner on one line or point), a coordinate that is
///   not finite (--drop-invalid then drops the triangles touching it), or a
///   coordinate beyond the exact tests' range (|x| > 1e150 or 0 < |x| < 1e-150):
///   the fan.
void triangulatePolygon(const std::array<double, 3>* corners, size_t n, std::vector<std::array<uint32_t, 3>>& out,
                        PolygonScratch& scratch);

}  // namespace vox
