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
// The occupancy is read once, voxel by voxel, into a hash table of 8^3 bit
// bricks (64 bytes per non-empty brick).
//
// Thread safety: immutable after construction; cast() may run on any number
// of threads.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <unordered_map>

#include "libvox/core/types.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/raycast.h"

namespace vox {

class VoxelWalk {
 public:
  /// The walker over `occupied` (grid coordinates, any order; repeats are harmless).
  explicit VoxelWalk(std::span<const Coord3> occupied);
  /// The walker over the occupied voxels of `grid`, read voxel by voxel
  /// (RayGrid::forEachOccupied, as the brute force's voxel list is): only the
  /// occupancy is shared with the hierarchical caster, not the walk.
  explicit VoxelWalk(const RayGrid& grid);

  /// The first occupied voxel along `ray` (grid space), with t, exit and the
  /// entry face as castRay reports them; `steps` counts the events visited.
  RayHit cast(const Ray& ray) const;

  bool occupied(int64_t u, int64_t v, int64_t w) const;

 private:
  using Brick = std::array<uint64_t, 8>;  // bit (x << 6) | (y << 3) | z of an 8^3 brick
  void add(int64_t u, int64_t v, int64_t w);
  // Occupancy in 8^3 bricks, found by hashing the brick's coordinates.
  std::unordered_map<uint64_t, Brick> bricks_;
  uint64_t lastKey_ = ~uint64_t(0);
  Brick* last_ = nullptr;  // while adding
  std::array<int64_t, 3> boxMin_{}, boxEnd_{};  // the occupied voxels' bounding box
  bool empty_ = true;
};

}  // namespace vox
