// Sparse voxel accumulation in 8^3 blocks (masks, and values only for the voxels that have them), without OpenVDB.
//
// VoxelBlocks is where builders put votes, surface flags and colours before a
// scene exists: SceneBuilder wraps one and turns it into OpenVDB trees
// (scene.h), and the direct scene writer (formats/scene/scene_vdb_direct.h) streams
// one straight into a .vdb file, so that `vox voxelize MESH` never loads
// OpenVDB (loading it costs ~45 ms and ~33 MB of resident pages per process:
// docs/startup.md).
//
// Coordinates are index space (voxel (u, v, w)); a block covers the 8^3 voxels
// of one OpenVDB leaf (origin = coordinate & ~7) and stores them in OpenVDB's
// voxel order (z fastest), so masks and values copy word for word into leaves.
//
// Thread-safety: none; fill one VoxelBlocks per thread and merge().
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <vector>

#include "libvox/core/bits.h"
#include "libvox/core/flat_map64.h"
#include "libvox/core/scene_header.h"

namespace vox {

inline constexpr int kBlockLog2 = 3;
inline constexpr int kBlockDim = 1 << kBlockLog2;
inline constexpr int kBlockVoxels = kBlockDim * kBlockDim * kBlockDim;
inline constexpr int kBlockWords = kBlockVoxels / 64;

/// Saturating sum of two vote counts (at kMaxVotesPerClass).
inline uint32_t saturatingVotes(uint32_t a, uint32_t b) {
  const uint64_t s = uint64_t(a) + b;
  return s > kMaxVotesPerClass ? kMaxVotesPerClass : uint32_t(s);
}

/// Votes of one class in one block: the voxels with votes (bit i of `voted`,
/// voxel i in the block's order) and their counts; every other voxel has 0.
/// Counts are never 0. Up to kCompactCounts voted voxels the counts are kept
/// compactly, one per set bit in voxel order (a surface block holds a few
/// dozen voted voxels: a few hundred bytes where a count per voxel takes 2 KB,
/// which was the bulk of a surface bake's memory); beyond that, one per voxel
/// (`dense`), so filling a whole block costs no repeated insertions.
struct ClassBlock {
  static constexpr size_t kCompactCounts = 128;
  uint8_t classId = 0;
  bool dense = false;
  std::array<uint64_t, kBlockWords> voted{};
  std::array<uint16_t, kBlockWords> before{};  // compact: voted voxels in the words before word k
  std::vector<uint32_t> counts;                // compact: one per voted voxel; dense: kBlockVoxels

  bool has(int i) const { return (voted[size_t(i >> 6)] >> (i & 63)) & 1; }
  bool empty() const { return std::none_of(voted.begin(), voted.end(), [](uint64_t w) { return w != 0; }); }
  /// Where voxel i's count is (or goes) in `counts`.
  size_t slot(int i) const {
    if (dense) return size_t(i);
    return size_t(before[size_t(i >> 6)]) + size_t(bitCount(voted[size_t(i >> 6)] & ((uint64_t(1) << (i & 63)) - 1)));
  }
  /// The votes of voxel i (0 when it has none).
  uint32_t at(int i) const { return has(i) ? counts[slot(i)] : 0; }
  /// Adds `votes` to voxel i, saturating at kMaxVotesPerClass; 0 adds nothing.
  /// Inline for a voxel that has votes already (most of a surface pass's
  /// pieces: about three per voxel); the first vote goes out of line.
  void add(int i, uint32_t votes) {
    if (has(i)) {
      uint32_t& c = counts[slot(i)];
      c = saturatingVotes(c, votes);
      return;
    }
    addFirst(i, votes);
  }
  /// Calls fn(i, count) for every voted voxel, in voxel order.
  template <typename Fn>
  void forEach(Fn&& fn) const {
    size_t s = 0;
    for (int k = 0; k < kBlockWords; ++k)
      for (uint64_t bits = voted[size_t(k)]; bits; bits &= bits - 1) {
        const int i = k * 64 + __builtin_ctzll(bits);
        fn(i, counts[dense ? size_t(i) : s++]);
      }
  }
  /// Adds every count of `other` (same class) to this one's.
  void addAll(const ClassBlock& other);
  /// Switches to one count per voxel.
  void makeDense();

 private:
  void addFirst(int i, uint32_t votes);  // voxel i has no votes yet
};

/// The memory a class block holds, for memory estimates that measure a sample:
/// the block and its counts as heap allocations (about 16 bytes of malloc
/// header each) and the owning pointer in its VoxelBlock.
inline size_t classBlockHeapBytes(const ClassBlock& block) {
  constexpr size_t kMallocHeader = 16;
  const size_t counts = block.counts.capacity() * sizeof(uint32_t);
  return sizeof(ClassBlock) + kMallocHeader + (counts ? counts + kMallocHeader : 0) + sizeof(void*);
}

/// One 8^3 block. Bit i of a mask is voxel i in OpenVDB's order:
/// i = (x & 7) << 6 | (y & 7) << 3 | (z & 7).
struct VoxelBlock {
  std::array<int32_t, 3> origin{0, 0, 0};  // index coordinates of voxel 0, multiples of 8
  std::array<uint64_t, kBlockWords> occupied{}, surface{}, colored{};
  std::vector<std::unique_ptr<ClassBlock>> classes;  // sorted by class id, few
  // Linear RGB of the voxels of `colored`, one per set bit in voxel order
  // (colorRank): 12 bytes per coloured voxel. One for each of the block's 512
  // voxels took 6 KB whatever the fill, and a surface block colours about a
  // tenth of them: most of a coloured bake's memory, all of it fresh pages.
  std::vector<std::array<float, 3>> colors;
  // Votes that runs without the surface flag added (a solid fill's interior),
  // kept compactly while they share one class and one count: voxel i has
  // `runVotes` more votes for `runClass` when bit i of `runMask` is set, on top
  // of the class blocks. A full interior block then costs 64 bytes, not 2 KB
  // per class. materializeRuns() moves them into the class blocks.
  std::array<uint64_t, kBlockWords> runMask{};
  uint8_t runClass = 0;
  uint32_t runVotes = 0;

  bool hasRuns() const {
    for (uint64_t w : runMask)
      if (w) return true;
    return false;
  }
  /// The votes of class `classId` at voxel i (class block plus runs).
  uint32_t votesAt(uint8_t classId, const ClassBlock* cb, int i) const {
    const uint32_t base = cb ? cb->at(i) : 0;
    return ((runMask[size_t(i >> 6)] >> (i & 63)) & 1) && runClass == classId ? saturatingVotes(base, runVotes) : base;
  }
};

/// The index in `colors` of voxel i's colour: the set bits of `colored` before bit i.
inline size_t colorRank(const VoxelBlock& b, int i) {
  size_t r = 0;
  for (int k = 0; k < (i >> 6); ++k) r += size_t(bitCount(b.colored[size_t(k)]));
  return r + size_t(bitCount(b.colored[size_t(i >> 6)] & ((uint64_t(1) << (i & 63)) - 1)));
}
/// Voxel i's colour (bit i of `colored` must be set).
inline const std::array<float, 3>& colorAt(const VoxelBlock& b, int i) { return b.colors[colorRank(b, i)]; }
/// Sets voxel i's colour; the last one set wins.
void setBlockColor(VoxelBlock& b, int i, const std::array<float, 3>& rgb);
/// Calls fn(i, rgb) for every coloured voxel i whose bit is set in `mask`, in voxel order.
template <typename Fn>
void forEachColor(const VoxelBlock& b, const std::array<uint64_t, kBlockWords>& mask, Fn&& fn) {
  size_t rank = 0;  // walks every colour, so no bit count per voxel
  for (int k = 0; k < kBlockWords; ++k)
    for (uint64_t bits = b.colored[size_t(k)]; bits; bits &= bits - 1, ++rank)
      if (mask[size_t(k)] & bits & (~bits + 1)) fn(k * 64 + std::countr_zero(bits), b.colors[rank]);
}

/// Voxel index of (x, y, z) inside its block.
inline int blockOffset(int32_t x, int32_t y, int32_t z) {
  return ((x & (kBlockDim - 1)) << (2 * kBlockLog2)) | ((y & (kBlockDim - 1)) << kBlockLog2) | (z & (kBlockDim - 1));
}

class VoxelBlocks {
 public:
  VoxelBlocks();
  VoxelBlocks(VoxelBlocks&&) noexcept;
  VoxelBlocks& operator=(VoxelBlocks&&) noexcept;
  ~VoxelBlocks();

  /// Same contracts as SceneBuilder's methods of the same names (scene.h):
  /// votes saturate, the surface flag ORs, the last colour set wins.
  /// Inline while the voxel is in the same block as the last one given (a
  /// triangle's voxels mostly are), out of line otherwise.
  void addVotes(Coord3 c, uint8_t classId, uint32_t votes, bool surface) {
    if (votes == 0) return;
    const uint64_t key = blockKeyOf(c);
    if (key != lastKey_ || key == kNoKey) return addVotesSlow(c, classId, votes, surface);
    const int i = blockOffset(c.u, c.v, c.w);
    VoxelBlock& b = *last_;
    const uint64_t bit = uint64_t(1) << (i & 63);
    b.occupied[size_t(i >> 6)] |= bit;
    if (surface) b.surface[size_t(i >> 6)] |= bit;
    ClassBlock* cb = b.classes.empty() ? nullptr : b.classes.back().get();
    if (cb && cb->classId == classId) return cb->add(i, votes);
    addVotesSlow(c, classId, votes, surface);
  }
  void addRun(Coord3 start, uint32_t length, uint8_t classId, uint32_t votes, bool surface);
  void setColor(Coord3 c, RgbLinear color);
  /// The block holding voxel `c`, created empty when absent (for copying
  /// whole 8^3 leaves in, e.g. from a scene's trees); null when `c` is beyond
  /// +-2^23 (outOfRange() then says so). Masks and values written to it must
  /// keep the blocks' invariants: votes only where occupied, one entry of
  /// `colors` per bit of `colored` (setBlockColor keeps it).
  VoxelBlock* blockAt(Coord3 c);
  /// Moves `other`'s content into this one; where both have a colour for a voxel, this one's wins.
  void merge(VoxelBlocks&& other);

  /// True when a coordinate beyond +-2^23 was given (such voxels are dropped;
  /// builders report it as an error).
  bool outOfRange() const { return outOfRange_; }
  size_t blockCount() const { return blocks_.size(); }

  /// The blocks sorted by `less` (default: by origin, x then y then z), a total
  /// order on origins, so the result does not depend on the order the votes
  /// arrived in. Pointers stay valid until the next mutation.
  using BlockOrder = bool (*)(const VoxelBlock*, const VoxelBlock*);
  std::vector<VoxelBlock*> sortedBlocks(BlockOrder less = nullptr);

  /// Checks what SceneBuilder::build() checks: every occupied voxel lies in
  /// `dims`, every class with votes is in `classes`, no coordinate was out of
  /// range. Throws vox::Error (Internal) otherwise.
  void validate(const Dims& dims, const ClassTable& classes);

  /// Releases one block's memory (after a writer is done with it).
  static void release(VoxelBlock& block);

 private:
  static constexpr int32_t kCoordLimit = 1 << 23;  // coordinates beyond cannot be in any domain
  static constexpr uint64_t kNoKey = ~uint64_t(0);   // keys take 63 bits: never a block's
  static bool representable(Coord3 c) {
    auto ok = [](int32_t v) { return v > -kCoordLimit && v < kCoordLimit; };
    return ok(c.u) && ok(c.v) && ok(c.w);
  }
  /// The block key of voxel c (21 bits per axis), or kNoKey beyond +-2^23.
  static uint64_t blockKeyOf(Coord3 c) {
    if (!representable(c)) return kNoKey;
    auto part = [](int32_t v) { return uint64_t(uint32_t((v >> kBlockLog2) + (kCoordLimit >> kBlockLog2)) & 0x1fffff); };
    return (part(c.u) << 42) | (part(c.v) << 21) | part(c.w);
  }
  void addVotesSlow(Coord3 c, uint8_t classId, uint32_t votes, bool surface);
  VoxelBlock& block(int32_t x, int32_t y, int32_t z);
  FlatMap64<std::unique_ptr<VoxelBlock>, PackedCoordHome> blocks_;  // block key -> block (which never moves)
  uint64_t lastKey_ = kNoKey;
  VoxelBlock* last_ = nullptr;
  bool outOfRange_ = false;
};

/// The class block of `classId` in `block`, created (zeroed) when absent.
ClassBlock& classBlock(VoxelBlock& block, uint8_t classId);
/// The class block of `classId` in `block`, or null.
const ClassBlock* findClassBlock(const VoxelBlock& block, uint8_t classId);
/// Moves a block's run votes into its class blocks (same votes, plain form).
void materializeRuns(VoxelBlock& block);

}  // namespace vox
