#include "libvox/render/fuse.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>

#include "libvox/core/color.h"
#include "libvox/core/error.h"
#include "libvox/core/floor_int.h"
#include "libvox/core/parallel.h"
#include "libvox/render/ray_bundle.h"

namespace vox {

FuseCounts::Brick* FuseCounts::brickFor(int64_t bu, int64_t bv, int64_t bw, uint64_t key) {
  const uint64_t blockKey = brickKey(bu >> 4, bv >> 4, bw >> 4);
  if (blockKey != lastBlockKey_) {
    std::unique_ptr<Block>& b = blocks_[blockKey];
    if (!b) b = std::make_unique<Block>(Block{});
    lastBlock_ = b.get();
    lastBlockKey_ = blockKey;
  }
  Brick*& p = (*lastBlock_)[size_t(((bu & 15) << 8) | ((bv & 15) << 4) | (bw & 15))];
  if (!p) {
    std::unique_ptr<Brick>& owned = free_[key];
    if (!owned) owned = std::make_unique<Brick>(Brick{});
    p = owned.get();
  }
  return p;
}

namespace {
// Linear light of each 8-bit sRGB value in 1/2^24 units.
const std::array<uint32_t, 256>& linearTable() {
  static const std::array<uint32_t, 256> t = [] {
    std::array<uint32_t, 256> a{};
    for (int i = 0; i < 256; ++i) a[size_t(i)] = uint32_t(std::lround(double(srgb8ToLinear(uint8_t(i))) * 16777216.0));
    return a;
  }();
  return t;
}
}  // namespace

void FuseCounts::addColor(Coord3 c, uint32_t rgb) {
  const std::array<uint32_t, 256>& t = linearTable();
  ColorSum& s = colors_[voxelKey(c)];
  s.r += t[(rgb >> 16) & 0xFF];
  s.g += t[(rgb >> 8) & 0xFF];
  s.b += t[rgb & 0xFF];
  ++s.n;
}

void FuseCounts::merge(FuseCounts&& other) {
  // Pointer blocks are rebuilt on demand (brickFor finds merged bricks in free_).
  blocks_.clear();
  lastBlockKey_ = ~uint64_t(0);
  lastBlock_ = nullptr;
  other.blocks_.clear();
  other.lastBlockKey_ = ~uint64_t(0);
  other.lastBlock_ = nullptr;
  for (auto& [key, brick] : other.free_) {
    std::unique_ptr<Brick>& mine = free_[key];
    if (!mine) {
      mine = std::move(brick);
      continue;
    }
    for (size_t i = 0; i < 512; ++i) {
      const uint64_t s = uint64_t((*mine)[i]) + (*brick)[i];
      (*mine)[i] = uint32_t(std::min<uint64_t>(s, UINT32_MAX));
    }
  }
  if (votes_.empty()) std::swap(votes_, other.votes_);
  else votes_.merge(other.votes_);
  for (const auto& [key, c] : other.colors_) {
    ColorSum& m = colors_[key];
    m.r += c.r;
    m.g += c.g;
    m.b += c.b;
    m.n += c.n;
  }
  other.colors_.clear();
  other.free_.clear();
  other.votes_.clear();
  other.lastKey_ = ~uint64_t(0);
  other.last_ = nullptr;
  lastKey_ = ~uint64_t(0);
  last_ = nullptr;
}

void FuseCounts::addFreeCount(Coord3 c, uint64_t n) {
  std::unique_ptr<Brick>& b = free_[brickKey(c.u >> 3, c.v >> 3, c.w >> 3)];
  if (!b) b = std::make_unique<Brick>(Brick{});
  uint32_t& x = (*b)[size_t(((c.u & 7) << 6) | ((c.v & 7) << 3) | (c.w & 7))];
  x = uint32_t(std::min<uint64_t>(uint64_t(x) + n, UINT32_MAX));
  lastKey_ = ~uint64_t(0);
  last_ = nullptr;
}

uint32_t* FuseCounts::freeBrick(Coord3 o) {
  std::unique_ptr<Brick>& b = free_[brickKey(o.u >> 3, o.v >> 3, o.w >> 3)];
  if (!b) b = std::make_unique<Brick>(Brick{});
  lastKey_ = ~uint64_t(0);
  last_ = nullptr;
  return b->data();
}

uint32_t FuseCounts::freeAt(Coord3 c) const {
  const auto it = free_.find(brickKey(c.u >> 3, c.v >> 3, c.w >> 3));
  return it == free_.end() ? 0 : (*it->second)[size_t(((c.u & 7) << 6) | ((c.v & 7) << 3) | (c.w & 7))];
}

void FuseCounts::setFree(Coord3 c, uint32_t n) {
  const auto it = free_.find(brickKey(c.u >> 3, c.v >> 3, c.w >> 3));
  if (it == free_.end()) {
    if (n) addFreeCount(c, n);
    return;
  }
  (*it->second)[size_t(((c.u & 7) << 6) | ((c.v & 7) << 3) | (c.w & 7))] = n;
}

std::vector<uint64_t> FuseCounts::sortedBrickKeys() const {
  std::vector<uint64_t> keys;
  keys.reserve(free_.size());
  for (const auto& [key, brick] : free_) keys.push_back(key);
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::vector<std::pair<Coord3, uint32_t>> FuseCounts::freeVoxels() const {
  const std::vector<uint64_t> keys = sortedBrickKeys();
  std::vector<std::pair<Coord3, uint32_t>> out;
  for (uint64_t key : keys) {
    const Brick& b = *free_.at(key);
    const int32_t bu = int32_t(key >> 42) * 8, bv = int32_t((key >> 21) & 0x1FFFFF) * 8, bw = int32_t(key & 0x1FFFFF) * 8;
    for (int i = 0; i < 512; ++i)
      if (b[size_t(i)]) out.push_back({Coord3{bu + (i >> 6), bv + ((i >> 3) & 7), bw + (i & 7)}, b[size_t(i)]});
  }
  return out;
}

std::vector<FuseCounts::Vote> FuseCounts::votes() const {
  const std::vector<VoteTable::Entry> all = votes_.sorted();
  std::vector<Vote> out;
  out.reserve(all.size());
  for (const VoteTable::Entry& e : all) out.push_back({voxelOfKey(e.voxel), e.classId, e.votes});
  return out;
}

namespace {

// The stored-depth value of the crossing at ray parameter t (header comment):
// render-canonical's PixelRays::worldDistance, t * |dir| * voxelSize in that
// order, rounded to float when the image stores float32.
struct KeyOf {
  double length = 1, voxelSize = 1;
  bool z = false, float32 = true;
  double operator()(double t) const {
    const double d = z ? t : t * length * voxelSize;
    return float32 ? double(float(d)) : d;
  }
};

/// Hands the accumulators of `pieces` to tasks: a task takes one, fills it and
/// gives it back. Which rows land in which accumulator varies with scheduling;
/// the sums do not. A deque, so adding one keeps the slots others hold in place.
class CountsPool {
 public:
  explicit CountsPool(std::deque<FuseCounts>& pieces) : pieces_(pieces) {
    for (size_t i = 0; i < pieces_.size(); ++i) idle_.push_back(i);
  }
  size_t take() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (idle_.empty()) {
      pieces_.emplace_back();
      return pieces_.size() - 1;
    }
    const size_t slot = idle_.back();
    idle_.pop_back();
    return slot;
  }
  FuseCounts& operator[](size_t slot) { return pieces_[slot]; }
  void giveBack(size_t slot) {
    std::lock_guard<std::mutex> lock(mutex_);
    idle_.push_back(slot);
  }

 private:
  std::deque<FuseCounts>& pieces_;
  std::mutex mutex_;
  std::vector<size_t> idle_;
};

}  // namespace

FuseRayResult fuseRay(const Ray& original, double voxelSize, const DepthMeasure& measure, double depth, const Dims& dims,
                      FuseCounts* free, int faceAxis, const RayGrid* tracked, RayGrid::Cursor* cursor,
                      double tEmpty) {
  if (!free || !cursor) tracked = nullptr;
  FuseRayResult out;
  KeyOf key;
  key.length = std::sqrt(original.dir[0] * original.dir[0] + original.dir[1] * original.dir[1] +
                         original.dir[2] * original.dir[2]);
  key.voxelSize = voxelSize;
  key.z = measure.kind == DepthKind::Z;
  key.float32 = measure.float32;
  const Ray ray = sanitizeRay(original);
  const double inf = std::numeric_limits<double>::infinity();
  const int64_t D[3] = {dims.x, dims.y, dims.z};
  double inv[3] = {0, 0, 0};
  bool moving[3];
  double tEnter = 0, tExit = inf;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[size_t(a)], d = ray.dir[size_t(a)];
    moving[a] = d != 0;
    if (!moving[a]) {
      if (!(o >= 0 && o <= double(D[a]))) return out;  // the ray runs beside the grid
      continue;
    }
    inv[a] = 1.0 / d;
    const double t0 = (0 - o) * inv[a], t1 = (double(D[a]) - o) * inv[a];
    tEnter = std::max(tEnter, std::min(t0, t1));
    tExit = std::min(tExit, std::max(t0, t1));
  }
  if (tEnter > tExit) return out;                 // misses the grid
  if (!(key(tEnter) <= depth)) return out;        // the depth lies before the grid
  auto time = [&](int a, int64_t p) { return (double(p) - ray.origin[size_t(a)]) * inv[a]; };
  // Crossings before tLow have keys strictly below the depth (a margin of
  // 1e-6 relative, far above float32's rounding of 6e-8): the walk skips key()
  // there and evaluates it exactly only near the depth. Without free counts
  // it starts at tLow: no crossing before it can be the hit or tie with it.
  const double tLow = (key.z ? depth : depth / (key.length * key.voxelSize)) * (1 - 1e-6);
  // With tracked voxels only, cells left before tEmpty hold none of them: the
  // walk may start there as it starts at a jump's target (no crossing before
  // tLow is a hit or ties with it).
  const double tSkip = !free ? tLow : tracked ? std::min(tEmpty, tLow) : 0;
  const double tStart = tSkip > tEnter ? tSkip : tEnter;
  if (tStart > tExit) return out;  // the ray leaves the grid before the depth

  // The cell the ray is in at tStart (entered at or before it), per axis.
  int64_t c[3];
  bool inPlane = false;
  int step[3] = {0, 0, 0};
  double next[3] = {inf, inf, inf};
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[size_t(a)];
    if (!moving[a]) {
      // Inside a grid plane: the lower cell (ceil(o) - 1), else the cell holding o.
      // The ray touches the cells on both sides alike: no depth tells them apart.
      if (o > 0 && o < double(D[a]) && o == std::floor(o)) inPlane = true;
      int64_t cell = int64_t(std::ceil(o)) - 1;
      c[a] = std::clamp<int64_t>(cell, 0, D[a] - 1);
      continue;
    }
    const double p = o + tStart * ray.dir[size_t(a)];
    int64_t cell = std::isfinite(p) ? floorToInt(std::clamp(p, -1.0, double(D[a]) + 1)) : 0;
    cell = std::clamp<int64_t>(cell, 0, D[a] - 1);
    if (ray.dir[size_t(a)] > 0) {
      step[a] = 1;
      while (cell + 1 < D[a] && time(a, cell + 1) <= tStart) ++cell;
      while (cell > 0 && time(a, cell) > tStart) --cell;
      next[a] = time(a, cell + 1);
    } else {
      step[a] = -1;
      while (cell > 0 && time(a, cell) <= tStart) --cell;
      while (cell + 1 < D[a] && time(a, cell + 1) > tStart) ++cell;
      next[a] = time(a, cell);
    }
    c[a] = cell;
  }

  // Crossings whose key equals the depth: a tie group (header comment).
  int tied = 0;
  bool chosen = false, chosenMulti = false, lastMulti = false;
  Coord3 chosenCell;
  if (tStart == tEnter && tEnter > 0 && key(tEnter) == depth) {
    tied = 1;
    int axes = 0;
    bool faceCrossed = false;
    for (int a = 0; a < 3; ++a)
      if (moving[a] && std::min(time(a, 0), time(a, D[a])) == tEnter) {
        ++axes;
        faceCrossed |= a == faceAxis;
      }
    lastMulti = axes > 1;
    if (faceCrossed) {
      chosen = true;
      chosenMulti = lastMulti;
      chosenCell = Coord3{int32_t(c[0]), int32_t(c[1]), int32_t(c[2])};
    }
  }
  bool enteredBelow = key(tStart) < depth;  // the crossing that entered the current cell has key < depth
  // Tracked walk: jumps to the first cell after every crossing at or before
  // `target` on each axis (the state the step-by-step walk has there: on each
  // axis the planes crossed are exactly those whose time is <= target, as
  // time() is monotone along an axis). Returns true when the ray left the grid.
  auto jumpTo = [&](double target) {
    bool left = false;
    for (int a = 0; a < 3; ++a) {
      if (!moving[a] || next[a] > target) continue;
      const double p = ray.origin[size_t(a)] + target * ray.dir[size_t(a)];
      int64_t cell;
      if (step[a] > 0) {
        cell = std::isfinite(p) ? floorToInt(std::clamp(p, double(c[a]), double(D[a]))) : c[a];
        while (cell < D[a] && time(a, cell + 1) <= target) ++cell;
        while (cell > c[a] && time(a, cell) > target) --cell;
        next[a] = time(a, cell + 1);
        left |= cell >= D[a];
      } else {
        cell = std::isfinite(p) ? floorToInt(std::clamp(p, -1.0, double(c[a]))) : c[a];
        while (cell >= 0 && time(a, cell) <= target) --cell;
        while (cell < c[a] && time(a, cell + 1) > target) ++cell;
        next[a] = time(a, cell);
        left |= cell < 0;
      }
      c[a] = cell;
    }
    return left;
  };
  // The time the ray leaves box [lo, hi) (voxels, per axis), which holds the current cell.
  auto boxExit = [&](const int64_t lo[3], const int64_t hi[3]) {
    double t = inf;
    for (int a = 0; a < 3; ++a)
      if (moving[a]) t = std::min(t, time(a, step[a] > 0 ? hi[a] : lo[a]));
    return t;
  };
  const int64_t brickEnd[3] = {(D[0] + 7) >> 3, (D[1] + 7) >> 3, (D[2] + 7) >> 3};
  const bool distanceField = tracked && tracked->hasDistanceField();
  for (;;) {
    bool isTracked = true;
    if (tracked) {
      bool occ = false;
      // With the distance field, one byte tells an empty brick: the tree is
      // probed only inside non-empty ones (where the walk goes voxel by voxel).
      const int64_t k = distanceField ? tracked->emptyBricksAround(c[0] >> 3, c[1] >> 3, c[2] >> 3) : 1;
      const int level = k > 0 && distanceField ? 1 : cursor->probe(c[0], c[1], c[2], occ);
      isTracked = occ;
      if (level == 0 && enteredBelow) {
        // A brick with tracked voxels, before tLow: every crossing is early
        // (its key below the depth, no tie), so the cells are stepped here
        // with the brick's mask read directly (the loop below would look up
        // the distance field and probe the tree at every cell). Leaves at the
        // brick's edge, or at the first cell not left before tLow, which the
        // loop below takes from where this stopped.
        const RayGrid::Mask512& mask = *cursor->lastBrick();
        const int64_t brick[3] = {c[0] >> 3, c[1] >> 3, c[2] >> 3};
        bool sameBrick = true;
        for (;;) {
          const int bit = int(((c[0] & 7) << 6) | ((c[1] & 7) << 3) | (c[2] & 7));
          isTracked = (mask[size_t(bit >> 6)] >> (bit & 63)) & 1;
          const double tn = std::min(next[0], std::min(next[1], next[2]));
          if (tn > tLow) break;
          if (isTracked) {
            free->addFree(int32_t(c[0]), int32_t(c[1]), int32_t(c[2]));
            ++out.freeCells;
          }
          ++out.steps;
          bool left = false;
          for (int a = 0; a < 3; ++a) {
            if (next[a] != tn) continue;
            c[a] += step[a];
            left |= c[a] < 0 || c[a] >= D[a];
            next[a] = time(a, step[a] > 0 ? c[a] + 1 : c[a]);
          }
          if (left) return out;  // the depth lies beyond the grid
          if ((c[0] >> 3) != brick[0] || (c[1] >> 3) != brick[1] || (c[2] >> 3) != brick[2]) {
            sameBrick = false;
            break;
          }
        }
        if (!sameBrick) continue;  // enteredBelow holds: every step was early
      }
      if (level >= 1) {
        // An empty box around the cell: the bricks closer than the distance
        // field's nearest non-empty brick, or (without the field) its brick,
        // region or super-region (level 1, 2, 3). The box of k > 1 bricks
        // holds the cell's brick, so it is left no earlier (time() is
        // monotone along an axis): its exit alone is the box's.
        int64_t lo[3], hi[3];
        double tb = inf;
        uint32_t boxes = 1;
        if (k > 1) {
          for (int a = 0; a < 3; ++a) {
            lo[a] = ((c[a] >> 3) - k + 1) * 8;
            hi[a] = ((c[a] >> 3) + k) * 8;
          }
          tb = boxExit(lo, hi);
        } else if (level == 1 && distanceField) {
          // An empty brick next to a tracked one (the common case near a
          // surface): walk on brick by brick (the walk's own plane times at
          // multiples of 8, so the bricks are the ones its cells lie in)
          // while the bricks entered are empty with no larger empty box
          // around them, and jump once, to the entry of the first other one.
          int64_t b[3];
          double nb[3];
          for (int a = 0; a < 3; ++a) {
            b[a] = c[a] >> 3;
            nb[a] = moving[a] ? time(a, (step[a] > 0 ? b[a] + 1 : b[a]) * 8) : inf;
          }
          for (;;) {
            tb = std::min(nb[0], std::min(nb[1], nb[2]));
            if (tb >= tLow) break;
            bool outside = false;
            for (int a = 0; a < 3; ++a) {
              if (nb[a] != tb) continue;
              b[a] += step[a];
              nb[a] = time(a, (step[a] > 0 ? b[a] + 1 : b[a]) * 8);
              outside |= b[a] < 0 || b[a] >= brickEnd[a];
            }
            if (outside || tracked->emptyBricksAround(b[0], b[1], b[2]) != 1) break;
            ++boxes;
          }
        } else {
          const int shift = level == 1 ? 3 : level == 2 ? 6 : 9;
          for (int a = 0; a < 3; ++a) {
            lo[a] = (c[a] >> shift) << shift;
            hi[a] = lo[a] + (int64_t(1) << shift);
          }
          tb = boxExit(lo, hi);
        }
        // Only crossings before tLow (all "early": keys below the depth, no
        // tie rules) are jumped; the cells left there hold no tracked voxel.
        const double target = std::min(tb, tLow);
        if (std::min(next[0], std::min(next[1], next[2])) <= target) {
          out.steps += boxes;
          if (jumpTo(target)) return out;  // the depth lies beyond the grid
          enteredBelow = true;
          continue;
        }
      }
    }
    const double tn = std::min(next[0], std::min(next[1], next[2]));
    const bool early = tn <= tLow;
    double tnKey = 0;
    if (!early) {
      tnKey = key(tn);
      if (!(tnKey <= depth)) break;  // the depth is inside the current cell (tn = inf: it never leaves)
    }
    if (free && enteredBelow && isTracked) {
      free->addFree(int32_t(c[0]), int32_t(c[1]), int32_t(c[2]));
      ++out.freeCells;
    }
    ++out.steps;
    bool left = false, faceCrossed = false;
    int axes = 0;
    const Coord3 before{int32_t(c[0]), int32_t(c[1]), int32_t(c[2])};
    for (int a = 0; a < 3; ++a) {
      if (next[a] != tn) continue;
      ++axes;
      faceCrossed |= a == faceAxis;
      c[a] += step[a];
      if (c[a] < 0 || c[a] >= D[a]) left = true;
      next[a] = time(a, step[a] > 0 ? c[a] + 1 : c[a]);
    }
    if (left) {
      // A crossing that leaves the grid with the depth's key, from a cell
      // entered with the same key: the two crossings are closer than the
      // float's step (a ray clipping a boundary voxel's corner). The voxel
      // behind lies outside the grid, so the tie group's cell inside it is
      // the hit (render-canonical hit it there); ambiguous unless the face
      // axis chose it. From a cell entered below the depth, the depth lies
      // exactly on the grid's exit face: beyond the grid.
      if (early || tnKey != depth || enteredBelow) return out;
      out.hit = true;
      out.voxel = chosen ? chosenCell : before;
      out.ambiguous = inPlane || (chosen ? chosenMulti : true);
      return out;
    }
    enteredBelow = early || tnKey < depth;
    if (!early && tnKey == depth) {
      ++tied;
      lastMulti = axes > 1;
      if (faceCrossed) {
        chosen = true;
        chosenMulti = lastMulti;
        chosenCell = Coord3{int32_t(c[0]), int32_t(c[1]), int32_t(c[2])};
      }
    }
  }
  out.hit = true;
  out.voxel = chosen ? chosenCell : Coord3{int32_t(c[0]), int32_t(c[1]), int32_t(c[2])};
  out.ambiguous = inPlane || (chosen ? chosenMulti : (tied >= 2 || lastMulti));
  return out;
}

Fuser::Fuser(const Dims& dims, const GridFrame& frame, const FuseSettings& settings)
    : dims_(dims), frame_(frame), settings_(settings) {
  // Voxel keys pack 21 bits per axis.
  if (dims.x >= (1u << 21) || dims.y >= (1u << 21) || dims.z >= (1u << 21))
    throwUsage("fuse: grids up to 2097151 voxels per axis; this one is " + toString(dims));
}

FuseViewStats Fuser::add(const FuseView& view) {
  const Camera& cam = view.camera;
  const size_t W = cam.width, H = cam.height, N = W * H;
  auto sized = [N](size_t n, bool optional) { return n == N || (optional && n == 0); };
  if (!sized(view.depth.size(), false) || !sized(view.classes.size(), false) || !sized(view.faceAxis.size(), true) ||
      !sized(view.color.size(), true) || !sized(view.weight.size(), true))
    throw Error(ErrorKind::Internal, "Fuser::add: per-pixel arrays must hold width x height entries");
  FuseViewStats stats;
  stats.pixels = N;
  const PixelRays rays(cam, frame_);
  // The voxels voted, gathered per task (runs of one voxel collapsed) and
  // sorted at the end: the order tasks finish in does not matter.
  std::vector<uint64_t> voted;
  std::mutex votedMutex;
  std::atomic<uint64_t> used{0}, ambiguous{0}, noDepth{0}, unlabelled{0}, zeroWeight{0}, outside{0}, steps{0}, freeCounts{0};
  CountsPool pool(pieces_);
  // Tiles of 16 x 16 pixels: their rays cross a narrow cone of bricks that
  // stays in cache (rows fan out across the whole scene).
  constexpr size_t kTile = 16;
  const size_t tilesX = (W + kTile - 1) / kTile, tiles = tilesX * ((H + kTile - 1) / kTile);
  parallelForEach(tiles, settings_.threads, 1, [&](size_t task) {
    const size_t slot = pool.take();
    FuseCounts& counts = pool[slot];
    uint64_t u = 0, amb = 0, nd = 0, ul = 0, zw = 0, out = 0, st = 0, fc = 0;
    std::vector<uint64_t> keys;
    // The tile's votes are added after its rays, in pixel order (the same
    // table as adding each at once): their slots are prefetched as the hits
    // are found, so the table's cache misses overlap the walks.
    struct PendingVote {
      uint64_t key;
      uint32_t weight;
      uint8_t classId;
    };
    std::vector<PendingVote> pending;
    pending.reserve(kTile * kTile);
    const size_t y0 = task / tilesX * kTile, y1 = std::min(H, y0 + kTile);
    const size_t x0 = task % tilesX * kTile, x1 = std::min(W, x0 + kTile);
    for (size_t y = y0; y < y1; ++y)
      for (size_t x = x0; x < x1; ++x) {
        const size_t i = y * W + x;
        if (!view.hasDepth(i)) {
          ++nd;
          continue;
        }
        const double d = view.depth[i];
        const uint8_t cls = view.classes[i];
        if (cls == 0) {
          ++ul;
          continue;
        }
        const uint32_t w = view.weight.empty() ? settings_.weight : settings_.weight * view.weight[i];
        if (w == 0) {
          ++zw;
          continue;
        }
        const int face = view.faceAxis.empty() ? -1 : view.faceAxis[i];
        const FuseRayResult r = fuseRay(rays.ray(uint32_t(x), uint32_t(y)), frame_.voxelSize, view.measure, d, dims_,
                                        settings_.countFree && settings_.freeScope == FreeScope::All ? &counts : nullptr, face);
        st += r.steps;
        fc += r.freeCells;
        if (!r.hit) {
          ++out;
          continue;
        }
        ++u;
        amb += r.ambiguous ? 1 : 0;
        const uint64_t k = FuseCounts::voxelKey(r.voxel);
        if (pending.empty() || pending.back().key != k || pending.back().classId != cls) counts.prefetchVote(k, cls);
        pending.push_back(PendingVote{k, w, cls});
        if (!view.color.empty() && view.color[i] != FuseView::kNoColor) counts.addColor(r.voxel, view.color[i]);
        if (keys.empty() || keys.back() != k) keys.push_back(k);
      }
    for (const PendingVote& p : pending) counts.addVote(p.key, p.classId, p.weight);
    if (!keys.empty()) {
      std::lock_guard<std::mutex> lock(votedMutex);
      voted.insert(voted.end(), keys.begin(), keys.end());
    }
    used += u;
    ambiguous += amb;
    noDepth += nd;
    unlabelled += ul;
    zeroWeight += zw;
    outside += out;
    steps += st;
    freeCounts += fc;
    pool.giveBack(slot);
  });
  stats.used = used;
  stats.ambiguous = ambiguous;
  stats.noDepth = noDepth;
  stats.unlabelled = unlabelled;
  stats.zeroWeight = zeroWeight;
  stats.outside = outside;
  stats.steps = steps;
  stats.freeCounts = freeCounts;
  sortVoxelKeys(voted);
  voted.erase(std::unique(voted.begin(), voted.end()), voted.end());
  voted.shrink_to_fit();
  stats.voxelsVoted = voted.size();
  stats.votedKeys = std::move(voted);
  return stats;
}

void Fuser::track(const std::vector<Coord3>& voxels) {
  extraTracked_.insert(extraTracked_.end(), voxels.begin(), voxels.end());
  tracked_.reset();
}

void Fuser::buildTracked() {
  tracked_ = std::make_unique<RayGrid>(dims_);
  for (const FuseCounts& p : pieces_)
    p.voteTable().forEach([&](const VoteTable::Entry& e) {
      const Coord3 at = FuseCounts::voxelOfKey(e.voxel);
      tracked_->addVoxel(uint32_t(at.u), uint32_t(at.v), uint32_t(at.w));
    });
  for (const Coord3& c : extraTracked_)
    if (c.u >= 0 && c.v >= 0 && c.w >= 0 && uint32_t(c.u) < dims_.x && uint32_t(c.v) < dims_.y && uint32_t(c.w) < dims_.z)
      tracked_->addVoxel(uint32_t(c.u), uint32_t(c.v), uint32_t(c.w));
  tracked_->finish();
}

uint64_t FuseWalks::bytesFor(uint64_t rays, uint32_t width, uint32_t height, bool faceAxes) {
  const uint64_t tiles = (uint64_t(width) + kTile - 1) / kTile * ((uint64_t(height) + kTile - 1) / kTile);
  return (tiles * kBundlesPerTile + 1) * sizeof(uint64_t) + rays * (sizeof(uint8_t) + sizeof(double) + (faceAxes ? 1 : 0));
}

void Fuser::checkSizes(const FuseView& view, const char* who) const {
  const size_t N = size_t(view.camera.width) * view.camera.height;
  if (view.depth.size() != N || view.classes.size() != N || (!view.faceAxis.empty() && view.faceAxis.size() != N) ||
      (!view.weight.empty() && view.weight.size() != N))
    throw Error(ErrorKind::Internal, std::string(who) + ": per-pixel arrays must hold width x height entries");
}

uint64_t Fuser::walkedPixels(const FuseView& view) const {
  checkSizes(view, "Fuser::walkedPixels");
  const size_t N = view.depth.size();
  std::atomic<uint64_t> total{0};
  constexpr size_t kChunk = 1 << 16;
  parallelForEach((N + kChunk - 1) / kChunk, settings_.threads, 1, [&](size_t c) {
    uint64_t n = 0;
    for (size_t i = c * kChunk, end = std::min(N, i + kChunk); i < end; ++i) n += walks(view, i);
    total += n;
  });
  return total;
}

FuseWalks Fuser::walksOf(const FuseView& view) const {
  checkSizes(view, "Fuser::walksOf");
  constexpr size_t T = FuseWalks::kTile, B = FuseWalks::kBundle, PerTile = FuseWalks::kBundlesPerTile;
  static_assert(T == 2 * B && PerTile == 4);
  const size_t W = view.camera.width, H = view.camera.height;
  const size_t tilesX = (W + T - 1) / T, tiles = tilesX * ((H + T - 1) / T);
  FuseWalks out;
  out.camera = view.camera;
  out.measure = view.measure;
  out.pixels = uint64_t(W) * H;
  // Bundle b of a tile: rows by + 8 (b >> 1), columns bx + 8 (b & 1). Two
  // passes over the tiles (count, then fill at the counted places), so the
  // rays' order does not depend on the threads.
  auto forBundle = [&](size_t task, size_t b, auto&& fn) {
    const size_t by = task / tilesX * T + (b >> 1) * B, bx = task % tilesX * T + (b & 1) * B;
    for (size_t y = by; y < std::min(H, by + B); ++y)
      for (size_t x = bx; x < std::min(W, bx + B); ++x)
        if (walks(view, y * W + x)) fn(y * W + x, uint8_t((y - by) * B + (x - bx)));
  };
  out.bundleStart.assign(tiles * PerTile + 1, 0);
  parallelForEach(tiles, settings_.threads, 64, [&](size_t task) {
    for (size_t b = 0; b < PerTile; ++b) forBundle(task, b, [&](size_t, uint8_t) { ++out.bundleStart[task * PerTile + b + 1]; });
  });
  for (size_t k = 1; k < out.bundleStart.size(); ++k) out.bundleStart[k] += out.bundleStart[k - 1];
  const size_t rays = size_t(out.bundleStart.back());
  out.at.resize(rays);
  out.depth.resize(rays);
  if (!view.faceAxis.empty()) out.faceAxis.resize(rays);
  parallelForEach(tiles, settings_.threads, 64, [&](size_t task) {
    for (size_t b = 0; b < PerTile; ++b) {
      size_t r = size_t(out.bundleStart[task * PerTile + b]);
      forBundle(task, b, [&](size_t i, uint8_t at) {
        out.at[r] = at;
        out.depth[r] = view.depth[i];
        if (!out.faceAxis.empty()) out.faceAxis[r] = view.faceAxis[i];
        ++r;
      });
    }
  });
  return out;
}

FuseViewStats Fuser::addFree(const FuseWalks& walks) {
  if (settings_.freeScope != FreeScope::Voted || !settings_.countFree)
    throw Error(ErrorKind::Internal, "Fuser::addFree: only with countFree and FreeScope::Voted");
  if (!tracked_) buildTracked();
  constexpr size_t T = FuseWalks::kTile, B = FuseWalks::kBundle, PerTile = FuseWalks::kBundlesPerTile;
  const Camera& cam = walks.camera;
  const size_t W = cam.width, H = cam.height;
  const size_t tilesX = (W + T - 1) / T, tiles = tilesX * ((H + T - 1) / T);
  if (walks.bundleStart.size() != tiles * PerTile + 1 || walks.at.size() != walks.rays() ||
      (!walks.faceAxis.empty() && walks.faceAxis.size() != walks.rays()))
    throw Error(ErrorKind::Internal, "Fuser::addFree: the walks do not match their camera (Fuser::walksOf makes them)");
  FuseViewStats stats;
  stats.pixels = walks.pixels;
  const PixelRays rays(cam, frame_);
  std::atomic<uint64_t> steps{0}, freeCounts{0};
  CountsPool pool(pieces_);
  // Tiles of 16 x 16 pixels, as add() walks them.
  parallelForEach(tiles, settings_.threads, 1, [&](size_t task) {
    const size_t slot = pool.take();
    FuseCounts& counts = pool[slot];
    RayGrid::Cursor cursor(*tracked_);
    uint64_t st = 0, fc = 0;
    // Bundles of 8 x 8 pixels share one march through the tracked set's
    // empty space (ray_bundle.h, as render-canonical's caster): each ray then
    // starts where the march stopped instead of jumping the same empty boxes.
    for (size_t b = 0; b < PerTile; ++b) {
      const size_t r0 = size_t(walks.bundleStart[task * PerTile + b]), r1 = size_t(walks.bundleStart[task * PerTile + b + 1]);
      if (r0 == r1) continue;  // no pixel walks
      const uint32_t by = uint32_t(task / tilesX * T + (b >> 1) * B), bx = uint32_t(task % tilesX * T + (b & 1) * B);
      // The bounding box of the pixels that walk: the directions are affine
      // in (x, y), so its four corner rays span every ray of it.
      uint32_t lx = B, hx = 0, ly = B, hy = 0;
      for (size_t r = r0; r < r1; ++r) {
        const uint32_t x = walks.at[r] % B, y = walks.at[r] / B;
        lx = std::min(lx, x), hx = std::max(hx, x), ly = std::min(ly, y), hy = std::max(hy, y);
      }
      const std::array<std::array<double, 3>, 4> corners{
          rays.ray(bx + lx, by + ly).dir, rays.ray(bx + hx, by + ly).dir, rays.ray(bx + lx, by + hy).dir,
          rays.ray(bx + hx, by + hy).dir};
      const double tEmpty = bundleEmptyUntil(*tracked_, rays.ray(bx + lx, by + ly).origin, corners);
      // No ray of the box touches a tracked voxel: no free count to add.
      if (tEmpty == std::numeric_limits<double>::infinity()) continue;
      for (size_t r = r0; r < r1; ++r) {
        const int face = walks.faceAxis.empty() ? -1 : walks.faceAxis[r];
        const FuseRayResult res = fuseRay(rays.ray(bx + walks.at[r] % B, by + walks.at[r] / B), frame_.voxelSize,
                                          walks.measure, walks.depth[r], dims_, &counts, face, tracked_.get(), &cursor,
                                          tEmpty);
        st += res.steps;
        fc += res.freeCells;
      }
    }
    steps += st;
    freeCounts += fc;
    pool.giveBack(slot);
  });
  stats.steps = steps;
  stats.freeCounts = freeCounts;
  return stats;
}

FuseCounts Fuser::finish() && {
  FuseCounts total;
  for (FuseCounts& p : pieces_) total.merge(std::move(p));
  pieces_.clear();
  return total;
}

}  // namespace vox
