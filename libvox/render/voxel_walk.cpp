// The plain voxel walk (voxel_walk.h). Every axis the ray moves down is
// mirrored by negation (plane p -> -p, origin o -> -o, dir d -> -d, cell
// i -> -i - 1): negation is exact and rounding symmetric, so a plane's time is
// bit for bit the one computed in the original frame, and the walk only ever
// steps up.
#include "libvox/render/voxel_walk.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vox {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

uint64_t brickKey(int64_t u, int64_t v, int64_t w) {
  return (uint64_t(u >> 3) << 42) | (uint64_t(v >> 3) << 21) | uint64_t(w >> 3);
}
int brickBit(int64_t u, int64_t v, int64_t w) { return int(((u & 7) << 6) | ((v & 7) << 3) | (w & 7)); }

// One axis of the walk, in the mirrored frame where the ray moves up (or not at all).
struct Axis {
  bool moving = false, mirrored = false;
  double origin = 0, dir = 0, inv = 0;
  int64_t lo = 0, hi = 0;  // the occupied box on this axis, cells [lo, hi), mirrored when `mirrored`
  int64_t cell = 0;        // moving: the cell the ray is in (lo - 1 before the box)
  int64_t fixedLo = 0, fixedHi = -1;  // not moving: the cells whose closed slab holds the origin, clipped
  double time(int64_t plane) const { return (double(plane) - origin) * inv; }
  int64_t gridIndex(int64_t i) const { return mirrored ? -i - 1 : i; }
};

}  // namespace

void VoxelWalk::add(int64_t u, int64_t v, int64_t w) {
  const uint64_t key = brickKey(u, v, w);
  if (key != lastKey_) {  // neighbouring voxels come together: one hash lookup per brick, mostly
    lastKey_ = key;
    last_ = &bricks_.try_emplace(key, Brick{}).first->second;
  }
  const int bit = brickBit(u, v, w);
  (*last_)[size_t(bit >> 6)] |= uint64_t(1) << (bit & 63);
  const int64_t p[3] = {u, v, w};
  for (size_t a = 0; a < 3; ++a) {
    boxMin_[a] = empty_ ? p[a] : std::min(boxMin_[a], p[a]);
    boxEnd_[a] = empty_ ? p[a] + 1 : std::max(boxEnd_[a], p[a] + 1);
  }
  empty_ = false;
}

VoxelWalk::VoxelWalk(std::span<const Coord3> occupied) {
  for (const Coord3& c : occupied) add(c.u, c.v, c.w);
  last_ = nullptr;
}

VoxelWalk::VoxelWalk(const RayGrid& grid) {
  grid.forEachOccupied([this](uint32_t u, uint32_t v, uint32_t w) { add(u, v, w); });
  last_ = nullptr;
}

bool VoxelWalk::occupied(int64_t u, int64_t v, int64_t w) const {
  if (u < 0 || v < 0 || w < 0) return false;
  const auto it = bricks_.find(brickKey(u, v, w));
  const int bit = brickBit(u, v, w);
  return it != bricks_.end() && ((it->second[size_t(bit >> 6)] >> (bit & 63)) & 1);
}

RayHit VoxelWalk::cast(const Ray& rayIn) const {
  RayHit result;
  if (empty_) return result;
  // The definition's sanitising: components negligible against the largest become 0.
  Ray ray = rayIn;
  double largest = 0;
  for (double d : ray.dir) largest = std::max(largest, std::fabs(d));
  for (double& d : ray.dir)
    if (std::fabs(d) < largest * 1e-200 || std::fabs(d) < 1e-290) d = 0;

  Axis ax[3];
  double t0 = -kInf, tExit = kInf;
  for (size_t a = 0; a < 3; ++a) {
    Axis& x = ax[a];
    const double d = ray.dir[a], o = ray.origin[a];
    if (d == 0) {
      // Closed slabs [c, c + 1] holding o: floor(o), and o - 1 too when o is on a plane.
      const double f = std::floor(o);
      if (!(f >= double(boxMin_[a]) - 1 && f <= double(boxEnd_[a]))) return result;
      x.fixedLo = std::max<int64_t>(boxMin_[a], int64_t(f) - (f == o ? 1 : 0));
      x.fixedHi = std::min<int64_t>(boxEnd_[a] - 1, int64_t(f));
      if (x.fixedLo > x.fixedHi) return result;
      continue;
    }
    x.moving = true;
    x.mirrored = d < 0;
    x.origin = x.mirrored ? -o : o;
    x.dir = x.mirrored ? -d : d;
    x.inv = 1.0 / x.dir;
    x.lo = x.mirrored ? -boxEnd_[a] : boxMin_[a];
    x.hi = x.mirrored ? -boxMin_[a] : boxEnd_[a];
    t0 = std::max(t0, x.time(x.lo));
    tExit = std::min(tExit, x.time(x.hi));
  }
  if (t0 > tExit || tExit < 0) return result;
  t0 = std::max(t0, 0.0);

  // On each moving axis, the first cell (from lo - 1) whose exit plane time is >= t0.
  for (Axis& x : ax) {
    if (!x.moving) continue;
    const double guess = std::floor(x.origin + t0 * x.dir) - 1;
    int64_t c = guess < double(x.lo - 1) ? x.lo - 1 : guess > double(x.hi - 1) ? x.hi - 1 : int64_t(guess);
    while (c > x.lo - 1 && x.time(c) >= t0) --c;
    while (x.time(c + 1) < t0) ++c;
    x.cell = c;
  }

  uint64_t cachedKey = ~uint64_t(0);
  const Brick* cached = nullptr;
  auto isOccupied = [&](int64_t u, int64_t v, int64_t w) -> bool {
    const uint64_t key = brickKey(u, v, w);
    if (key != cachedKey) {
      cachedKey = key;
      const auto it = bricks_.find(key);
      cached = it == bricks_.end() ? nullptr : &it->second;
    }
    if (!cached) return false;
    const int bit = brickBit(u, v, w);
    return ((*cached)[size_t(bit >> 6)] >> (bit & 63)) & 1;
  };

  double t = t0;
  for (;;) {
    ++result.steps;
    // The cells of each axis whose interval holds t: [first, last] (mirrored frame).
    int64_t first[3], last[3];
    for (size_t a = 0; a < 3; ++a) {
      const Axis& x = ax[a];
      if (!x.moving) {
        first[a] = x.fixedLo;
        last[a] = x.fixedHi;
        continue;
      }
      int64_t e = x.cell;
      while (e + 1 <= x.hi - 1 && x.time(e + 1) == t) ++e;
      first[a] = std::max(x.cell, x.lo);
      last[a] = e;
    }
    // Every occupied voxel among them, by the definition's order.
    bool found = false;
    Coord3 best{};
    double bestKey = 0, bestExit = 0;
    for (int64_t i = first[0]; i <= last[0]; ++i)
      for (int64_t j = first[1]; j <= last[1]; ++j)
        for (int64_t k = first[2]; k <= last[2]; ++k) {
          const int64_t cell[3] = {i, j, k};
          const Coord3 g{int32_t(ax[0].moving ? ax[0].gridIndex(i) : i), int32_t(ax[1].moving ? ax[1].gridIndex(j) : j),
                         int32_t(ax[2].moving ? ax[2].gridIndex(k) : k)};
          if (!isOccupied(g.u, g.v, g.w)) continue;
          double enter = -kInf, exit = kInf;
          for (size_t a = 0; a < 3; ++a) {
            if (!ax[a].moving) continue;
            enter = std::max(enter, ax[a].time(cell[a]));
            exit = std::min(exit, ax[a].time(cell[a] + 1));
          }
          const double key = std::max(enter, 0.0);
          const bool better = !found || key < bestKey ||
                              (key == bestKey && (exit != bestExit ? exit > bestExit
                                                  : g.w != best.w  ? g.w < best.w
                                                  : g.v != best.v  ? g.v < best.v
                                                                   : g.u < best.u));
          if (better) {
            found = true;
            best = g;
            bestKey = key;
            bestExit = exit;
          }
        }
    if (found) {
      result.hit = true;
      result.voxel = best;
      result.t = bestKey;
      result.exit = bestExit;
      // The entry face: among moving axes whose entry plane time is the key, the most head-on, then the lowest.
      double headOn = -1;
      const int64_t g[3] = {best.u, best.v, best.w};
      for (int a = 0; a < 3; ++a) {
        const Axis& x = ax[size_t(a)];
        if (!x.moving) continue;
        const int64_t cell = x.mirrored ? -g[a] - 1 : g[a];
        if (x.time(cell) == bestKey && x.dir > headOn) {
          headOn = x.dir;
          result.faceAxis = a;
          result.faceSign = x.mirrored ? 1 : -1;
        }
      }
      return result;
    }
    // Move into the last cell of each range, then on to the next plane crossing.
    double next = kInf;
    for (size_t a = 0; a < 3; ++a) {
      Axis& x = ax[a];
      if (!x.moving) continue;
      x.cell = last[a];
      next = std::min(next, x.time(x.cell + 1));
    }
    if (!(next > t) || next > tExit) return result;  // out of the occupied box
    t = next;
  }
}

}  // namespace vox
