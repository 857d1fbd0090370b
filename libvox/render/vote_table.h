// Votes per (voxel, class) for `vox fuse` (fuse.h's FuseCounts): one flat
// open-addressing table instead of a node-based hash map.
//
// Why: every used pixel adds one vote, so this is the hottest container of a
// fusion after the ray walk. std::unordered_map allocated a node per (voxel,
// class) and chased a pointer per lookup; here a lookup is a multiply, a shift
// and (at load <= 1/2) one or two probes in one array. Consecutive pixels
// mostly vote for the same voxel: the last entry found is tried first.
//
// Keys: FuseCounts::voxelKey (21 bits per axis, < 2^63) and the class byte,
// kept apart (no 64-bit packing of both: dims up to 2^21 stay distinct).
// Sums are plain uint64 additions: the content does not depend on the order of
// add() calls; sorted() gives the deterministic order (voxel key, then class).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vox {

class VoteTable {
 public:
  struct Entry {
    uint64_t voxel = kEmpty;  // FuseCounts::voxelKey; kEmpty = free slot
    uint64_t votes = 0;
    uint8_t classId = 0;
  };
  static constexpr uint64_t kEmpty = ~uint64_t(0);

  void add(uint64_t voxel, uint8_t classId, uint64_t votes) {
    if (last_ < slots_.size() && slots_[last_].voxel == voxel && slots_[last_].classId == classId) {
      slots_[last_].votes += votes;
      return;
    }
    if ((size_ + 1) * 2 > slots_.size()) grow();
    for (size_t i = hash(voxel, classId);; i = (i + 1) & mask_) {
      Entry& e = slots_[i];
      if (e.voxel == voxel && e.classId == classId) {
        e.votes += votes;
        last_ = i;
        return;
      }
      if (e.voxel == kEmpty) {
        e.voxel = voxel;
        e.classId = classId;
        e.votes = votes;
        ++size_;
        last_ = i;
        return;
      }
    }
  }
  /// Asks the cache for the slot where add(voxel, classId, ...) starts
  /// looking: a hint only (a later add() may have grown the table). The table
  /// of a large fusion is tens of MB and each pixel's voxel a miss; callers
  /// that know a few votes ahead overlap those misses with their other work.
  void prefetch(uint64_t voxel, uint8_t classId) const {
    if (slots_.empty()) return;
    const char* at = reinterpret_cast<const char*>(&slots_[hash(voxel, classId)]);
    __builtin_prefetch(at, 1);
    __builtin_prefetch(at + sizeof(Entry) - 1, 1);
  }
  /// Adds every entry of `other`.
  void merge(const VoteTable& other) {
    reserve(size_ + other.size_);
    for (const Entry& e : other.slots_)
      if (e.voxel != kEmpty) add(e.voxel, e.classId, e.votes);
  }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  void clear() {
    slots_.clear();
    slots_.shrink_to_fit();
    size_ = 0;
    last_ = ~size_t(0);
  }
  /// Calls fn(const Entry&) for every entry, in slot order (not deterministic
  /// across different histories of add(): use for order-free work only).
  template <typename Fn>
  void forEach(Fn&& fn) const {
    for (const Entry& e : slots_)
      if (e.voxel != kEmpty) fn(e);
  }
  /// Every entry sorted by (voxel, class).
  std::vector<Entry> sorted() const;

 private:
  // The slot of (voxel, class): a hashed 4^3 group of voxels plus the voxel's
  // index in it, so a group's entries lie in 64 consecutive slots (1.5 KB):
  // the neighbouring voxels that a tile of pixels votes for share cache lines
  // and pages instead of one miss each across the whole table.
  size_t hash(uint64_t voxel, uint8_t classId) const {
    constexpr uint64_t kGroup = ~((uint64_t(3) << 42) | (uint64_t(3) << 21) | uint64_t(3));
    const uint64_t x = ((voxel & kGroup) ^ (uint64_t(classId) << 56)) * 0x9E3779B97F4A7C15ull;
    const size_t local = size_t(((voxel >> 38) & 0x30) | ((voxel >> 19) & 0xC) | (voxel & 3));
    return (size_t(x >> shift_) + local) & mask_;
  }
  void reserve(size_t entries);
  void grow() { reserve(size_ < 128 ? 256 : size_ * 2); }
  std::vector<Entry> slots_;  // power-of-two size, at most half full
  size_t size_ = 0;
  size_t last_ = ~size_t(0);
  int shift_ = 64;
  size_t mask_ = 0;
};

/// Sorts voxel keys ascending (the same order as std::sort): an LSD radix
/// sort over the bytes in which the keys differ (6 passes for grids up to
/// 2^16 per axis, fewer for smaller ones), linear in the keys. The per-view
/// voted keys of a fusion are sorted serially between parallel loops.
void sortVoxelKeys(std::vector<uint64_t>& keys);

}  // namespace vox
