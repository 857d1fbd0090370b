// The second reference for render checks: a plain voxel-by-voxel walk
// (Amanatides and Woo's DDA) over the occupancy, written to be read, not to
// be fast, and sharing no code with the hierarchical caster (raycast.cpp) or
// its RayGrid: its own occupancy table, its own plane times, its own walk.
//
// It answers the definition in raycast.h exactly (the first occupied voxel by
// max(enter, 0), ties to the larger exit, then the smallest (w, v, u)), so a
// check can compare every pixel voxel for voxel. Why the walk is exact:
//   * Time of plane p on a moving axis a: (p - origin[a]) * (1 / dir[a]),
//     the definition's own expression; it is monotone in p.
//   * The walk visits "events": the time t0 at which the ray enters the box of
//     occupied voxels, then every plane crossing in increasing time. At an
//     event t it tests every voxel whose per-axis intervals all contain t: on
//     each moving axis the current cell plus the cells whose entry plane time
//     equals t (more than one when plane times collide, far from the grid), on
//     an axis the ray does not move along the one or two cells whose closed
//     slab holds the origin.
//   * An occupied voxel with key k is tested at the event k (k is t0 or one of
//     its entry plane times), and a voxel tested at event t with a key below t
//     was tested, empty, at an earlier event. So the first event with an
//     occupied voxel holds exactly the occupied voxels of the smallest key,
//     and the tie rule picks among them.
// Its cost is the number of voxels the ray crosses inside the occupied box
// (no empty-space skipping): a few hundred steps per ray on a 256^3 scene.
//
// Thread safety: immutable after construction; cast() may run on any number
// of threads.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <unordered_map>

#include "libvox/core/types.h"
#include "libvox/render/raycast.h"

namespace vox {

class VoxelWalk {
 public:
  /// The walker over `occupied` (grid coordinates, any order; repeats are harmless).
  explicit VoxelWalk(std::span<const Coord3> occupied);

  /// The first occupied voxel along `ray` (grid space), with t, exit and the
  /// entry face as castRay reports them; `steps` counts the events visited.
  RayHit cast(const Ray& ray) const;

  bool occupied(int64_t u, int64_t v, int64_t w) const;

 private:
  // Occupancy in 4^3 blocks of 64 bits, found by hashing the block's coordinates.
  std::unordered_map<uint64_t, uint64_t> blocks_;
  std::array<int64_t, 3> boxMin_{}, boxEnd_{};  // the occupied voxels' bounding box
  bool empty_ = true;
};

}  // namespace vox
