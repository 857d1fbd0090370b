#include "libvox/render/vote_table.h"

#include <algorithm>

namespace vox {

void VoteTable::reserve(size_t entries) {
  size_t cap = 16;
  int bits = 4;
  while (cap < 2 * entries + 2) {
    cap *= 2;
    ++bits;
  }
  if (cap <= slots_.size()) return;
  std::vector<Entry> old(cap);
  old.swap(slots_);
  shift_ = 64 - bits;
  mask_ = cap - 1;
  last_ = ~size_t(0);
  for (const Entry& e : old) {
    if (e.voxel == kEmpty) continue;
    size_t i = hash(e.voxel, e.classId);
    while (slots_[i].voxel != kEmpty) i = (i + 1) & mask_;
    slots_[i] = e;
  }
}

std::vector<VoteTable::Entry> VoteTable::sorted() const {
  std::vector<Entry> out;
  out.reserve(size_);
  for (const Entry& e : slots_)
    if (e.voxel != kEmpty) out.push_back(e);
  std::sort(out.begin(), out.end(),
            [](const Entry& a, const Entry& b) { return a.voxel != b.voxel ? a.voxel < b.voxel : a.classId < b.classId; });
  return out;
}

void sortVoxelKeys(std::vector<uint64_t>& keys) {
  if (keys.size() < 256) {
    std::sort(keys.begin(), keys.end());
    return;
  }
  uint64_t all = 0, common = ~uint64_t(0);
  for (uint64_t k : keys) {
    all |= k;
    common &= k;
  }
  const uint64_t varying = all ^ common;
  std::vector<uint64_t> tmp(keys.size());
  for (int shift = 0; shift < 64; shift += 8) {
    if (((varying >> shift) & 0xFF) == 0) continue;  // every key has the same byte here
    size_t count[257] = {};
    for (uint64_t k : keys) ++count[((k >> shift) & 0xFF) + 1];
    for (int b = 0; b < 256; ++b) count[b + 1] += count[b];
    for (uint64_t k : keys) tmp[count[(k >> shift) & 0xFF]++] = k;
    keys.swap(tmp);
  }
}

}  // namespace vox
