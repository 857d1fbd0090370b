// Fusing depth + label images into voxel counts (`vox fuse`, docs/fuse.md).
//
// Each pixel's ray is render-canonical's ray (PixelRays, render.h: the ray
// through the pixel centre, grid space, not normalised), walked cell by cell
// with the plane times of raycast.h's definition:
//     time(a, p) = (p - origin[a]) * (1.0 / dir[a])
// A plane crossing at time t lies at the stored-depth value
//     key(t) = t * |dir| * voxelSize   (--depth-kind distance, what render-canonical writes)
//     key(t) = t                       (--depth-kind z: the camera-space depth; exact
//                                        because the camera-space direction has z = -1)
// rounded to float when the depth image stores float32 samples (exactly the
// value a render of a voxel entered there stores).
//
// Rules (the pixel's depth d is finite and > 0):
//   * The hit voxel is the cell the ray is in after every crossing with
//     key(t) <= d: a depth exactly on a voxel face belongs to the voxel behind
//     it (the one the ray enters there, as render-canonical's depth is the
//     entry distance). When several crossings round to the same float as d,
//     the last of them wins (the deeper voxel). A ray crossing an edge or
//     corner exactly enters the diagonal cell; a ray lying inside a grid
//     plane is in the cell on the plane's lower side. Both count as
//     ambiguous: render-canonical picks among the touching voxels by their
//     occupancy, which a depth does not carry.
//   * Free space: every cell the walk leaves before the hit cell and entered
//     at a crossing with key(t) < d (strictly: cells entered at a crossing
//     that rounds to d itself may hold the true hit) gets one free count.
//     With noise-free depth from the same ray definition each such cell is
//     empty in the rendered scene (its entry is before the hit's).
//   * Only cells inside the grid [0, X) x [0, Y) x [0, Z) are counted; a hit
//     outside the grid votes nothing (the cells inside before it still get
//     their free counts).
//
// Counts are integers summed per worker piece and merged: the result does not
// depend on the thread count or on the order of views.
//
// With FreeScope::Voted (`vox fuse --free voted`, the default) free counts
// are kept only at tracked voxels (the votes of a first pass, plus track()'s),
// and the walk jumps the empty bricks of that set (fuseRay's `tracked`).
//
// Memory: free counts in hashed 8^3 bricks of uint32 (2 KB per brick the rays
// cross, per worker), votes in a flat table per (voxel, class) hit (vote_table.h,
// 24 bytes at load <= 1/2); never the volume.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <unordered_map>
#include <vector>

#include "libvox/core/types.h"
#include "libvox/render/camera.h"
#include "libvox/render/ray_grid.h"
#include "libvox/render/raycast.h"
#include "libvox/render/render.h"
#include "libvox/render/vote_table.h"

namespace vox {

enum class DepthKind { Distance, Z };

/// How the stored depth relates to the ray parameter (see the header comment).
struct DepthMeasure {
  DepthKind kind = DepthKind::Distance;
  bool float32 = true;  // the depths are float32 samples: crossings are compared rounded to float
};

/// Sparse integer counts over a grid: free counts per voxel and votes per
/// (voxel, class). One per worker; merged by summing.
class FuseCounts {
 public:
  FuseCounts() = default;
  FuseCounts(FuseCounts&&) noexcept = default;
  FuseCounts& operator=(FuseCounts&&) noexcept = default;

  void addFree(int32_t u, int32_t v, int32_t w) {
    const uint64_t key = brickKey(u >> 3, v >> 3, w >> 3);
    if (key != lastKey_) {
      last_ = brickFor(u >> 3, v >> 3, w >> 3, key);
      lastKey_ = key;
    }
    uint32_t& c = (*last_)[size_t(((u & 7) << 6) | ((v & 7) << 3) | (w & 7))];
    if (c != UINT32_MAX) ++c;
  }
  void addVote(Coord3 c, uint8_t classId, uint32_t weight) { votes_.add(voxelKey(c), classId, weight); }
  /// The same by voxel key, and a hint that such a vote comes soon (VoteTable::prefetch).
  void addVote(uint64_t voxelKey, uint8_t classId, uint32_t weight) { votes_.add(voxelKey, classId, weight); }
  void prefetchVote(uint64_t voxelKey, uint8_t classId) const { votes_.prefetch(voxelKey, classId); }
  /// Adds one colour sample (8-bit sRGB) at `c`: summed in linear light as
  /// integers (1/2^24 units), so the average does not depend on the order.
  void addColor(Coord3 c, uint32_t rgb);
  struct ColorSum {
    uint64_t r = 0, g = 0, b = 0, n = 0;
  };
  /// The colour sums per voxel key (FuseCounts::voxelKey).
  const std::unordered_map<uint64_t, ColorSum>& colorSums() const { return colors_; }
  /// Adds `n` free counts at `c` (saturating).
  void addFreeCount(Coord3 c, uint64_t n);
  /// The 512 free counts of the 8^3 brick at `origin` (a multiple of 8 on
  /// each axis), created zeroed when absent; index (x << 6) | (y << 3) | z.
  uint32_t* freeBrick(Coord3 origin);
  /// The free count at `c` (0 when none).
  uint32_t freeAt(Coord3 c) const;
  /// Replaces the free count at `c` (a brick must hold it already unless n == 0).
  void setFree(Coord3 c, uint32_t n);
  /// Calls fn(origin, counts) for every brick of free counts in key order;
  /// counts[(x << 6) | (y << 3) | z] is voxel origin + (x, y, z) (OpenVDB's
  /// leaf order), 0 = none.
  template <typename Fn>
  void forEachFreeBrick(Fn&& fn) const {
    for (uint64_t key : sortedBrickKeys()) {
      const Coord3 o{int32_t(key >> 42) * 8, int32_t((key >> 21) & 0x1FFFFF) * 8, int32_t(key & 0x1FFFFF) * 8};
      fn(o, free_.at(key)->data());
    }
  }
  /// Adds `other`'s counts into this one (saturating at 2^32 - 1).
  void merge(FuseCounts&& other);

  /// Every voxel with a free count > 0, in key order (brick key, then the
  /// voxel within the brick): deterministic.
  std::vector<std::pair<Coord3, uint32_t>> freeVoxels() const;
  /// Every (voxel, class, votes), sorted by (voxel key, class).
  struct Vote {
    Coord3 at;
    uint8_t classId = 0;
    uint64_t votes = 0;
  };
  std::vector<Vote> votes() const;
  /// The votes unsorted (order-free work: which voxels have votes).
  const VoteTable& voteTable() const { return votes_; }
  /// forEachFreeBrick that frees each brick after `fn` has seen it (the
  /// counts are empty afterwards): writers hold one copy at a time.
  template <typename Fn>
  void drainFreeBricks(Fn&& fn) {
    for (uint64_t key : sortedBrickKeys()) {
      const auto it = free_.find(key);
      const Coord3 o{int32_t(key >> 42) * 8, int32_t((key >> 21) & 0x1FFFFF) * 8, int32_t(key & 0x1FFFFF) * 8};
      fn(o, it->second->data());
      free_.erase(it);
    }
    blocks_.clear();
    lastBlockKey_ = lastKey_ = ~uint64_t(0);
    lastBlock_ = nullptr;
    last_ = nullptr;
  }
  uint64_t freeBricks() const { return free_.size(); }
  void dropVotes() {
    votes_.clear();
    colors_.clear();
  }
  std::vector<uint64_t> sortedBrickKeys() const;

  static uint64_t brickKey(int64_t bu, int64_t bv, int64_t bw) {
    return (uint64_t(bu) << 42) | (uint64_t(bv) << 21) | uint64_t(bw);
  }
  static uint64_t voxelKey(Coord3 c) { return (uint64_t(uint32_t(c.u)) << 42) | (uint64_t(uint32_t(c.v)) << 21) | uint64_t(uint32_t(c.w)); }
  static Coord3 voxelOfKey(uint64_t k) {
    return {int32_t(k >> 42), int32_t((k >> 21) & 0x1FFFFF), int32_t(k & 0x1FFFFF)};
  }

 private:
  using Brick = std::array<uint32_t, 512>;
  // A walk changes brick every few steps: bricks are found through 16^3-brick
  // blocks of pointers (one hash lookup per block a ray enters, an array
  // index per brick), and owned by free_ (iteration, merging).
  using Block = std::array<Brick*, 4096>;
  Brick* brickFor(int64_t bu, int64_t bv, int64_t bw, uint64_t key);
  std::unordered_map<uint64_t, std::unique_ptr<Brick>> free_;
  std::unordered_map<uint64_t, std::unique_ptr<Block>> blocks_;
  uint64_t lastBlockKey_ = ~uint64_t(0);
  Block* lastBlock_ = nullptr;
  VoteTable votes_;
  std::unordered_map<uint64_t, ColorSum> colors_;  // voxelKey -> colour sums
  uint64_t lastKey_ = ~uint64_t(0);
  Brick* last_ = nullptr;
};

/// What one pixel's ray did.
struct FuseRayResult {
  bool hit = false;     // the depth falls inside the grid: `voxel` is valid
  Coord3 voxel;
  uint32_t freeCells = 0;  // cells given a free count
  uint32_t steps = 0;      // plane crossings walked one by one, plus empty boxes jumped (`tracked`)
  bool ambiguous = false;  // the depth's float matched several crossings (or an edge crossing) and nothing told them
                           // apart, or the ray lies inside a grid plane (the cells on both sides tie)
};

/// Walks `ray` (grid space, as PixelRays makes it, not sanitized) up to depth
/// `depth` (finite, > 0) in a grid of `dims`; adds free counts to `free` (when
/// not null; without it the walk starts just before the depth, a few steps
/// per ray, with the same hit). `voxelSize` is the grid's (for key(t) of distance depths).
/// `faceAxis` (0, 1, 2, or -1 unknown): the axis of the face the ray entered
/// the hit voxel through, used only to break ties between crossings.
///
/// `tracked` (with `free`): free counts go only to the voxels it holds
/// (occupied bits), and the walk jumps over its empty 8^3 bricks (and larger
/// empty boxes) before the depth, one step per box instead of one per voxel.
/// The counts it adds are exactly the full walk's at the tracked voxels, and
/// the hit is the same. `cursor` must be a cursor of `tracked` (one per thread).
///
/// `tEmpty` (with `tracked`): a ray time before which the ray touches no
/// tracked voxel (bundleEmptyUntil's certificate for the ray's pixel tile,
/// ray_bundle.h); the walk starts there, at the cell the step-by-step walk
/// reaches at that time. 0: nothing certified.
FuseRayResult fuseRay(const Ray& ray, double voxelSize, const DepthMeasure& measure, double depth, const Dims& dims,
                      FuseCounts* free, int faceAxis = -1, const RayGrid* tracked = nullptr,
                      RayGrid::Cursor* cursor = nullptr, double tEmpty = 0);

/// One view: its camera (width x height = the images' size), a depth per
/// pixel (row-major, row 0 at the top; 0, negative, NaN or inf = no depth)
/// and a class per pixel (0 = no class: the pixel is skipped).
struct FuseView {
  Camera camera;
  DepthMeasure measure;
  std::vector<double> depth;
  std::vector<uint8_t> classes;
  std::vector<int8_t> faceAxis;  // empty, or per pixel the axis of the entered face (-1 unknown)
  std::vector<uint32_t> color;   // empty, or per pixel 0xRRGGBB of 8-bit sRGB, kNoColor = none
  std::vector<uint16_t> weight;  // empty, or per pixel the vote weight (a confidence image; 0 = skip the pixel)
  static constexpr uint32_t kNoColor = 0xFFFFFFFFu;
  double far = 0;  // > 0: depths beyond it are skipped

  /// False for the pixels fuse skips as `no_depth`: 0, negative, NaN, inf or
  /// beyond `far`. The one test, so the label check and the fuser agree.
  bool hasDepth(size_t i) const {
    const double d = depth[i];
    return d > 0 && std::isfinite(d) && !(far > 0 && d > far);
  }
};

/// The pixels of one view that the second pass walks (Fuser::addFree: those
/// with a depth, a class and a non-zero weight), kept between the passes in
/// place of the decoded view: 10 bytes per walked pixel (its depth, face axis
/// and place in its bundle) and 8 per 64 pixels, where the decoded view takes
/// 10 or more bytes per pixel, walked or not. The fresh memory of whole kept
/// views was a fifth of a 100-view fusion's CPU (docs/bench-fuse.md).
///
/// Layout: the rays of each 8 x 8 pixel bundle together, bundles in the
/// walk's order (16 x 16 pixel tiles row by row, each tile's four bundles row
/// by row; a bundle past the image's edge is empty), each bundle's rays in
/// pixel order.
struct FuseWalks {
  static constexpr uint32_t kTile = 16, kBundle = 8, kBundlesPerTile = 4;
  Camera camera;
  DepthMeasure measure;
  uint64_t pixels = 0;                // the view's width x height
  std::vector<uint64_t> bundleStart;  // per bundle its first ray; one entry more at the end
  std::vector<uint8_t> at;            // per ray: its pixel in the bundle, 8 * row + column
  std::vector<double> depth;          // per ray: the pixel's depth
  std::vector<int8_t> faceAxis;       // per ray (-1 unknown), or empty: the view has none
  size_t rays() const { return depth.size(); }
  /// The bytes of the arrays above for `rays` rays of a width x height view.
  static uint64_t bytesFor(uint64_t rays, uint32_t width, uint32_t height, bool faceAxes);
  uint64_t bytes() const { return bytesFor(rays(), camera.width, camera.height, !faceAxis.empty()); }
};

struct FuseViewStats {
  uint64_t pixels = 0;
  uint64_t used = 0;          // pixels whose hit voted
  uint64_t noDepth = 0;       // 0, negative, NaN, inf or beyond far
  uint64_t unlabelled = 0;    // depth but class 0
  uint64_t zeroWeight = 0;    // depth and class, but confidence 0
  uint64_t outside = 0;       // depth outside the grid (before it, beyond it, or the ray misses it)
  uint64_t ambiguous = 0;     // used pixels whose voxel the depth could not single out (FuseRayResult::ambiguous)
  uint64_t steps = 0;         // plane crossings walked over every ray
  uint64_t freeCounts = 0;    // free counts added
  uint64_t voxelsVoted = 0;   // distinct voxels this view voted for
  std::vector<uint64_t> votedKeys;  // FuseCounts::voxelKey of those voxels, sorted
};

/// Where free counts are kept (docs/fuse.md, "Free space").
enum class FreeScope {
  All,    // every cell a ray crosses before its hit: one walk step per voxel
  Voted,  // only voxels with votes (this run's, or given by track()): two passes, empty bricks jumped
};

struct FuseSettings {
  // Votes per pixel: weight, times the pixel's confidence when the view has
  // one. Free counts are one per ray whatever the weight (a larger weight
  // makes carving more conservative).
  uint32_t weight = 1;   // votes per pixel
  bool countFree = true;  // false: votes only; each ray is walked from just before its depth
  FreeScope freeScope = FreeScope::All;  // Voted: add() votes only; free counts come from addFree()
  unsigned threads = 0;  // 0 = all cores
};

/// Accumulates views. Each worker piece keeps its own FuseCounts across
/// views; finish() sums them (integer sums: the same at any thread count).
class Fuser {
 public:
  Fuser(const Dims& dims, const GridFrame& frame, const FuseSettings& settings);
  FuseViewStats add(const FuseView& view);
  /// FreeScope::Voted, after add() has seen every view: also keep free counts
  /// at `voxels` (the input scene's occupied voxels and its `free` entries).
  void track(const std::vector<Coord3>& voxels);
  /// FreeScope::Voted, second pass: every view again (same order not needed),
  /// adding free counts at the tracked voxels: those that got votes in add()
  /// plus track()'s. Returns the view's steps and free counts (the other
  /// fields are add()'s business and stay 0).
  FuseViewStats addFree(const FuseView& view) { return addFree(walksOf(view)); }
  /// The same from the view's walked pixels (walksOf), which a caller may
  /// keep between the passes instead of the view.
  FuseViewStats addFree(const FuseWalks& walks);
  /// The pixels of `view` the second pass walks. Throws vox::Error
  /// (Internal) when its per-pixel arrays are not width x height long.
  FuseWalks walksOf(const FuseView& view) const;
  /// How many pixels of `view` the second pass walks (walksOf's rays(),
  /// without making them).
  uint64_t walkedPixels(const FuseView& view) const;
  FuseCounts finish() &&;

 private:
  void buildTracked();
  /// Whether the passes walk pixel i of `view` (a depth, a class, a non-zero weight).
  bool walks(const FuseView& view, size_t i) const {
    if (!view.hasDepth(i) || view.classes[i] == 0) return false;
    return (view.weight.empty() ? settings_.weight : settings_.weight * view.weight[i]) != 0;
  }
  void checkSizes(const FuseView& view, const char* who) const;
  std::vector<Coord3> extraTracked_;
  std::unique_ptr<RayGrid> tracked_;
  Dims dims_;
  GridFrame frame_;
  FuseSettings settings_;
  std::deque<FuseCounts> pieces_;  // deque: adding one keeps the others in place
};

}  // namespace vox
