// A hash map from 64-bit integer keys to values, in one flat array (open
// addressing, linear probing, Fibonacci hashing, at most half full).
//
// Why not std::unordered_map: the bakes look up 8^3 blocks and memory-estimate
// cells by packed coordinates once per voxel piece; the node-based map paid a
// node allocation per key, a division by a prime per lookup and a pointer
// chase per probe (the block map alone was 6% of a surface bake's CPU). Here a
// lookup is a multiply, a shift and, at load <= 1/2, mostly one probe.
//
// Contract:
//  * Keys are any uint64 except kEmptyKey (~0), which marks a free slot; the
//    packed coordinate keys the bakes use never reach it.
//  * References and pointers to values are invalidated by any insertion
//    (the table may grow and move them); values must be movable. Store a
//    std::unique_ptr where the value must stay put.
//  * Iteration (forEach) is in slot order: deterministic for a given history
//    of insertions, but not sorted; sort where the order reaches an output.
//  * No erase (the users only add, then drop the whole map).
//
// Memory: 2 to 4 slots of sizeof(uint64_t) + sizeof(V) (rounded up to V's
// alignment) per key, and during a growth the old array too (slotBytesPerKey()).
//
// Thread-safety: none; one map per thread, or external locking.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace vox {

/// Where a key's probe starts in a table of 2^log2Slots slots: Fibonacci
/// hashing (the key times 2^64 / golden ratio, top bits), for any keys.
struct FibonacciHome {
  static constexpr int kMinLog2Slots = 4;
  static size_t home(uint64_t key, int log2Slots) {
    return log2Slots == 0 ? 0 : size_t((key * 0x9E3779B97F4A7C15ull) >> (64 - log2Slots));
  }
};

/// For keys packing three 21-bit coordinates, x << 42 | y << 21 | z: the 4^3
/// keys of one aligned group share a run of 64 slots (the group hashed, the
/// key's place in the group appended), so lookups of neighbouring
/// coordinates, as a surface walks them, hit the same cache lines instead of
/// one random line each.
struct PackedCoordHome {
  static constexpr int kMinLog2Slots = 6;
  static size_t home(uint64_t key, int log2Slots) {
    constexpr uint64_t kLow2 = uint64_t(3) << 42 | uint64_t(3) << 21 | 3;
    const size_t inGroup = size_t((key >> 42 & 3) << 4 | (key >> 21 & 3) << 2 | (key & 3));
    const uint64_t group = key & ~kLow2;
    return FibonacciHome::home(group, log2Slots - 6) << 6 | inGroup;
  }
};

template <typename V, typename Home = FibonacciHome>
class FlatMap64 {
 public:
  static constexpr uint64_t kEmptyKey = ~uint64_t(0);

  FlatMap64() = default;
  FlatMap64(FlatMap64&&) noexcept = default;
  FlatMap64& operator=(FlatMap64&&) noexcept = default;

  /// The value of `key`, inserted value-initialised when absent.
  V& operator[](uint64_t key) {
    if (slots_.empty() || (size_ + 1) * 2 > slots_.size()) grow(slots_.empty() ? kMinSlots : slots_.size() * 2);
    for (size_t i = home(key);; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (s.key == key) return s.value;
      if (s.key == kEmptyKey) {
        s.key = key;
        ++size_;
        return s.value;
      }
    }
  }

  /// The value of `key`, or null.
  V* find(uint64_t key) {
    if (slots_.empty()) return nullptr;
    for (size_t i = home(key);; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (s.key == key) return &s.value;
      if (s.key == kEmptyKey) return nullptr;
    }
  }
  const V* find(uint64_t key) const { return const_cast<FlatMap64*>(this)->find(key); }

  /// Room for `n` keys without growing.
  void reserve(size_t n) {
    size_t want = kMinSlots;
    while (want < 2 * n) want *= 2;
    if (want > slots_.size()) grow(want);
  }

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

  /// Drops every key and the table's memory.
  void clear() { *this = FlatMap64(); }

  /// fn(key, value&) for every key, in slot order.
  template <typename Fn>
  void forEach(Fn&& fn) {
    for (Slot& s : slots_)
      if (s.key != kEmptyKey) fn(s.key, s.value);
  }
  template <typename Fn>
  void forEach(Fn&& fn) const {
    for (const Slot& s : slots_)
      if (s.key != kEmptyKey) fn(s.key, s.value);
  }

  /// Bytes per key at the most, for memory estimates: 4 slots right after a
  /// growth, plus the 2 of the old array while it is moved.
  static constexpr size_t slotBytesPerKey() { return 6 * sizeof(Slot); }

 private:
  struct Slot {
    uint64_t key = kEmptyKey;
    V value{};
  };
  static constexpr size_t kMinSlots = size_t(1) << Home::kMinLog2Slots;

  size_t home(uint64_t key) const { return Home::home(key, log2Slots_); }

  void grow(size_t slots) {
    std::vector<Slot> old(slots);
    old.swap(slots_);
    mask_ = slots - 1;
    log2Slots_ = 0;
    while ((size_t(1) << log2Slots_) < slots) ++log2Slots_;
    for (Slot& s : old) {
      if (s.key == kEmptyKey) continue;
      size_t i = home(s.key);
      while (slots_[i].key != kEmptyKey) i = (i + 1) & mask_;
      slots_[i].key = s.key;
      slots_[i].value = std::move(s.value);
    }
  }

  std::vector<Slot> slots_;
  size_t size_ = 0;
  size_t mask_ = 0;
  int log2Slots_ = 0;
};

}  // namespace vox
