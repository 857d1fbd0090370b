// RayGrid: the occupancy of a scene in the shape ray casting wants.
//
// A four-level tree of 8 x 8 x 8 bit masks over index space (u, v, w):
//   level 0  voxels in bricks of 8^3          (one 512-bit mask per non-empty brick)
//   level 1  bricks in regions of 64^3        (one mask + child base per non-empty region)
//   level 2  regions in supers of 512^3       (one mask + child base per non-empty super)
//   level 3  a dense array of supers over the domain (-1 = empty)
// Children are stored in mask order, so a child is found by a popcount (no
// pointers, no hashing). Within a mask, bit (x << 6) | (y << 3) | z is child
// (x, y, z): OpenVDB's leaf layout, so a BoolGrid leaf's value mask is a brick.
//
// Why not the OpenVDB tree: a ray needs "how big is the empty box around this
// voxel" at every step, and the same structure must come from a page file
// without OpenVDB. This one answers in four dependent loads (one when the
// brick is cached) and holds a 256^3 scene's shell in a few MB. Domains of up
// to 2^22 bricks also get a flat table of each brick's answer (4 bytes per
// brick: 128 KB at 256^3, 8 MB at 1024^3), so a probe is one load.
//
// Build with addBrick()/addVoxel() (any order, repeated bricks are OR-ed), then
// finish(). After finish() the grid is immutable and safe to read from any
// number of threads.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "libvox/core/bits.h"
#include "libvox/core/types.h"

namespace vox {

class RayGrid {
  struct Node;  // defined below

 public:
  using Mask512 = std::array<uint64_t, 8>;  // bit b is word b >> 6, bit b & 63

  /// An empty grid over [0, X) x [0, Y) x [0, Z). Throws vox::Error (Usage) when
  /// the top array (one entry per 512^3 super-region) would exceed 2^24 entries.
  explicit RayGrid(Dims dims);

  const Dims& dims() const { return dims_; }

  /// ORs `mask` into brick (bx, by, bz), which covers voxels [8 bx, 8 bx + 8) etc.
  /// Bits of voxels outside the domain are dropped. Before finish() only.
  void addBrick(uint32_t bx, uint32_t by, uint32_t bz, const Mask512& mask);
  /// Marks one voxel occupied (inside the domain). Before finish() only.
  void addVoxel(uint32_t u, uint32_t v, uint32_t w);
  /// Builds the tree. Call once.
  void finish();

  /// Emptiness of the neighbourhood of voxel (u, v, w), which may lie outside
  /// the domain: 3 = its 512^3 super-region is empty (or it is outside the
  /// domain), 2 = its 64^3 region is empty, 1 = its 8^3 brick is empty, 0 = its
  /// brick has occupied voxels; then `brick` points at that brick's mask.
  int probe(int64_t u, int64_t v, int64_t w, const Mask512** brick) const;
  bool occupied(int64_t u, int64_t v, int64_t w) const;

  uint64_t occupiedCount() const { return occupied_; }
  /// [contentMin, contentEnd): a box of whole bricks (clipped to the domain)
  /// holding every occupied voxel. Empty grid: both zero.
  const std::array<int64_t, 3>& contentMin() const { return contentMin_; }
  const std::array<int64_t, 3>& contentEnd() const { return contentEnd_; }
  /// [occupiedMin, occupiedEnd): the smallest box of voxels holding every
  /// occupied voxel (exact, unlike the content box). Empty grid: both zero.
  const std::array<int64_t, 3>& occupiedMin() const { return occupiedMin_; }
  const std::array<int64_t, 3>& occupiedEnd() const { return occupiedEnd_; }
  size_t brickCount() const { return bricks_.size(); }
  size_t memoryBytes() const;
  /// Every occupied voxel, in brick order then bit order. Serial.
  void forEachOccupied(const std::function<void(uint32_t u, uint32_t v, uint32_t w)>& fn) const;
  /// The same voxels as a list (the brute-force caster's input).
  std::vector<Coord3> occupiedVoxels() const;

  static int bitOf(uint32_t x, uint32_t y, uint32_t z) { return int((x << 6) | (y << 3) | z); }

  /// False for domains of more than 2^24 bricks (emptyBricksAround then reads 1 everywhere).
  bool hasDistanceField() const { return !brickDist_.empty(); }
  /// Chebyshev distance, in bricks, from brick (bx, by, bz) (inside the
  /// domain) to the nearest non-empty brick, capped at 255: every brick closer
  /// than that is empty (bricks outside the domain are empty). 0 for a
  /// non-empty brick; 1 when the grid has no distance field (domains of more
  /// than 2^24 bricks). Lets a ray jump over many empty cells at once.
  uint32_t emptyBricksAround(int64_t bx, int64_t by, int64_t bz) const {
    if (brickDist_.empty()) return 1;
    return brickDist_[(size_t(bx + 1) * (brickDims_[1] + 2) + size_t(by + 1)) * (brickDims_[2] + 2) + size_t(bz + 1)];
  }

  /// probe() with the last super-region, region and brick remembered, so a ray
  /// walking through neighbouring voxels mostly skips the upper levels (each
  /// level is a dependent load that misses the cache on large grids). One per
  /// thread / ray; not thread-safe.
  class Cursor {
   public:
    explicit Cursor(const RayGrid& grid) : g_(grid) {}
    /// Same result as RayGrid::probe; `occupied` is set for level 0.
    int probe(int64_t u, int64_t v, int64_t w, bool& occupied);
    /// The same for a voxel the caller knows lies inside the domain (no bounds test).
    int probeInDomain(int64_t u, int64_t v, int64_t w, bool& occupied);
    /// The brick mask of the last probe that returned 0 (valid until the next probe).
    const Mask512* lastBrick() const { return brick_; }

   private:
    const RayGrid& g_;
    uint64_t superKey_ = ~uint64_t(0), regionKey_ = ~uint64_t(0), brickKey_ = ~uint64_t(0);
    const Node* super_ = nullptr;
    const Node* region_ = nullptr;
    const Mask512* brick_ = nullptr;
    int brickLevel_ = 3;
  };

 private:
  struct Node {
    Mask512 mask{};
    uint32_t base = 0;                  // index of the first child in the next level's array
    std::array<uint16_t, 8> prefix{};   // children before word i
    uint32_t child(int bit) const {
      const int word = bit >> 6, b = bit & 63;
      const uint64_t below = b ? (mask[size_t(word)] & ((uint64_t(1) << b) - 1)) : 0;
      return base + prefix[size_t(word)] + uint32_t(bitCount(below));
    }
    bool has(int bit) const { return (mask[bit >> 6] >> (bit & 63)) & 1; }
  };
  Dims dims_;
  std::array<uint32_t, 3> topDims_{};
  std::vector<int32_t> top_;
  std::vector<Node> supers_, regions_;
  std::vector<Mask512> bricks_;
  std::array<uint32_t, 3> brickDims_{};
  std::array<int64_t, 3> contentMin_{}, contentEnd_{};
  std::array<int64_t, 3> occupiedMin_{}, occupiedEnd_{};
  void includeInOccupiedBox(uint32_t bx, uint32_t by, uint32_t bz, const Mask512& mask);
  std::vector<uint8_t> brickDist_;  // (bx+1, by+1, bz+1) in a 1-brick padded box; see emptyBricksAround
  void buildDistanceField(const std::vector<uint64_t>& brickKeys);
  // What probe() answers for each brick of the domain, flat (x major): the
  // brick's index in bricks_ (>= 0), or minus its emptiness level (-1 brick,
  // -2 region, -3 super-region empty). One load instead of the tree's three
  // dependent ones; only for domains of at most kMaxBrickSlots bricks (16 MB),
  // larger ones walk the tree.
  static constexpr uint64_t kMaxBrickSlots = uint64_t(1) << 22;
  std::vector<int32_t> brickSlot_;
  void buildBrickSlots();
  std::vector<std::pair<uint64_t, Mask512>> pending_;  // (brick key, mask) until finish()
  uint64_t occupied_ = 0;
  bool finished_ = false;
};

inline int RayGrid::Cursor::probe(int64_t u, int64_t v, int64_t w, bool& occupied) {
  // Negative indices wrap to huge unsigned ones: one comparison per axis.
  if ((uint64_t(u) >= g_.dims_.x) | (uint64_t(v) >= g_.dims_.y) | (uint64_t(w) >= g_.dims_.z)) {
    occupied = false;
    return 3;
  }
  return probeInDomain(u, v, w, occupied);
}

inline int RayGrid::Cursor::probeInDomain(int64_t u, int64_t v, int64_t w, bool& occupied) {
  occupied = false;
  const RayGrid& g = g_;
  if (!g.brickSlot_.empty()) {
    const uint64_t slot = (uint64_t(u >> 3) * g.brickDims_[1] + uint64_t(v >> 3)) * g.brickDims_[2] + uint64_t(w >> 3);
    if (slot != brickKey_) {
      brickKey_ = slot;
      const int32_t s = g.brickSlot_[size_t(slot)];
      brick_ = s >= 0 ? &g.bricks_[size_t(s)] : nullptr;
      brickLevel_ = s >= 0 ? 0 : -s;
    }
  } else if (const uint64_t bkey = (uint64_t(u >> 3) << 42) | (uint64_t(v >> 3) << 21) | uint64_t(w >> 3);
             bkey != brickKey_) {
    brickKey_ = bkey;
    const uint64_t rkey = (uint64_t(u >> 6) << 42) | (uint64_t(v >> 6) << 21) | uint64_t(w >> 6);
    if (rkey != regionKey_) {
      regionKey_ = rkey;
      const uint64_t skey = (uint64_t(u >> 9) << 42) | (uint64_t(v >> 9) << 21) | uint64_t(w >> 9);
      if (skey != superKey_) {
        superKey_ = skey;
        const int32_t s = g.top_[(size_t(u >> 9) * g.topDims_[1] + size_t(v >> 9)) * g.topDims_[2] + size_t(w >> 9)];
        super_ = s < 0 ? nullptr : &g.supers_[size_t(s)];
      }
      region_ = nullptr;
      if (super_) {
        const int rbit = bitOf(uint32_t(u >> 6) & 7, uint32_t(v >> 6) & 7, uint32_t(w >> 6) & 7);
        if (super_->has(rbit)) region_ = &g.regions_[super_->child(rbit)];
      }
    }
    brick_ = nullptr;
    if (!super_) {
      brickLevel_ = 3;
    } else if (!region_) {
      brickLevel_ = 2;
    } else {
      const int bbit = bitOf(uint32_t(u >> 3) & 7, uint32_t(v >> 3) & 7, uint32_t(w >> 3) & 7);
      if (region_->has(bbit)) {
        brick_ = &g.bricks_[region_->child(bbit)];
        brickLevel_ = 0;
      } else {
        brickLevel_ = 1;
      }
    }
  }
  if (brickLevel_ == 0) {
    const int bit = bitOf(uint32_t(u & 7), uint32_t(v & 7), uint32_t(w & 7));
    occupied = ((*brick_)[size_t(bit >> 6)] >> (bit & 63)) & 1;
  }
  return brickLevel_;
}

}  // namespace vox
