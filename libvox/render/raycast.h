// Exact ray casting into a voxel grid: the first voxel a ray enters.
//
// Space: grid space, where voxel (u, v, w) is the closed box [u, u+1] x [v, v+1]
// x [w, w+1] (a scene's world position p maps to (p - origin) / voxelSize).
// A ray is origin + t * dir for t >= 0; dir need not be normalised (the
// renderer passes a world-unit direction divided by the voxel size, so t is a
// world distance).
//
// The definition both casters implement, in floating point exactly as written:
//   * For axis a with dir[a] != 0, the ray crosses the plane a = p at
//         time(a, p) = (p - origin[a]) * (1.0 / dir[a])      (IEEE double)
//     which is monotone in p, so the voxel's interval on axis a is
//     [min, max] of time(a, i), time(a, i + 1). With dir[a] == 0 the interval is
//     (-inf, +inf) when i <= origin[a] <= i + 1, else empty.
//   * enter = max over axes of the interval starts, exit = min of the ends; the
//     ray touches the voxel when enter <= exit and exit >= 0. Its key is
//     max(enter, 0).
//   * The hit is the occupied voxel with the smallest key; ties (the ray passes
//     exactly through an edge or a corner, or runs along a face) go to the
//     larger exit (the voxel the ray goes into rather than grazes), then to the
//     smallest (w, v, u).
// castRay finds it with a hierarchical DDA over a RayGrid (it jumps over empty
// 512^3, 64^3 and 8^3 boxes and visits only the plane crossings in between);
// castRayBruteForce tests every occupied voxel. They agree bit for bit (the
// DDA evaluates the same time() values; see raycast.cpp for the argument), which
// the tests check on random scenes and cameras.
//
// Thread-safe: both are pure functions of their arguments.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>

#include "libvox/render/ray_grid.h"
#include "libvox/core/types.h"

namespace vox {

struct Ray {
  std::array<double, 3> origin{};  // grid space
  std::array<double, 3> dir{};     // not all zero, finite
};

struct RayHit {
  bool hit = false;
  Coord3 voxel;         // valid when hit
  double t = 0;         // the key: max(enter, 0)
  double exit = 0;      // the voxel's exit time
  int faceAxis = -1;    // axis of the face the ray entered through; -1 when it starts inside the voxel
  int faceSign = 0;     // outward normal of that face: -1 or +1 along faceAxis
  uint32_t steps = 0;   // DDA events visited (castRay only)
};

/// The first occupied voxel of `grid` along `ray` (see the header comment).
RayHit castRay(const RayGrid& grid, const Ray& ray);
/// The same, reusing `cursor` (of the same grid) across rays: neighbouring
/// rays then find their first cells in cache. One cursor per thread.
RayHit castRay(const RayGrid& grid, const Ray& ray, RayGrid::Cursor& cursor);
/// The same, starting the walk at time `tStart` (>= 0): the caller guarantees
/// that the ray touches no occupied voxel at any t < tStart (ray_bundle.h
/// certifies such times for a pixel tile). The hit is the same as from 0; only
/// `steps` is smaller.
RayHit castRay(const RayGrid& grid, const Ray& ray, RayGrid::Cursor& cursor, double tStart);

/// The same answer by testing every voxel in `occupied` (any order).
RayHit castRayBruteForce(std::span<const Coord3> occupied, const Ray& ray);

/// The ray both casters actually trace: direction components below 1e-200 of
/// the largest (or below 1e-290) become 0, so that 1 / dir stays finite.
/// Inline: `vox fuse` calls it twice per pixel.
inline Ray sanitizeRay(const Ray& ray) {
  Ray r = ray;
  double m = 0;
  for (double d : r.dir) m = std::max(m, std::fabs(d));
  for (double& d : r.dir)
    if (std::fabs(d) < m * 1e-200 || std::fabs(d) < 1e-290) d = 0;
  return r;
}

/// enter/exit of one voxel as defined above (for a sanitized ray); false when
/// the ray misses it.
bool rayVoxelInterval(const Ray& ray, const Coord3& voxel, double& enter, double& exit);

}  // namespace vox
