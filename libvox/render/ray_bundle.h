// Empty space shared by a bundle of rays: the rays of a pixel tile leave one
// eye in nearly the same direction, so one march through the brick distance
// field can certify, for all of them at once, how far they run before they
// could touch an occupied voxel. Each ray then starts its exact DDA there
// (castRay's tStart) instead of walking the same empty cells again, and a tile
// whose rays all miss the occupied box casts no ray at all.
//
// Space and rays as in raycast.h (grid space, ray = origin + t * dir).
// Thread-safe: pure functions of their arguments.
#pragma once

#include <array>
#include <limits>
#include <span>

#include "libvox/render/ray_grid.h"

namespace vox {

/// A time T such that, for every direction d in the convex hull of `dirs`
/// (not all zero, finite), the ray origin + t d touches no occupied voxel of
/// `grid` for 0 <= t < T (in exact arithmetic, with half a voxel of margin for
/// rounding). +infinity when such rays touch no occupied voxel at all.
/// 0 when nothing can be certified. Conservative: any smaller T is as true.
///
/// How: sphere tracing with the L-infinity metric along the bundle's mean
/// direction c. Every ray of the bundle is within t * w of c's point at time
/// t (w = max |d - c|, largest at a corner of the hull); the empty radius
/// around c's point (distance to the content box outside it, the brick
/// distance field inside) bounds how far the whole bundle may advance.
double bundleEmptyUntil(const RayGrid& grid, const std::array<double, 3>& origin,
                        std::span<const std::array<double, 3>> dirs);

}  // namespace vox
