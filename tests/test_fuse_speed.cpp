// The containers `vox fuse` counts in, against exact oracles (std::map).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <tuple>

#include "libvox/render/fuse.h"
#include "libvox/render/vote_table.h"

namespace {

using vox::VoteTable;

// Random adds (clustered keys, repeats, growth across many sizes) and merges
// give the sums of a std::map, sorted by (voxel, class).
TEST(FuseVoteTable, SumsAndSortedOrderEqualAnOrderedMap) {
  std::mt19937_64 rng(17);
  for (int round = 0; round < 6; ++round) {
    VoteTable a, b;
    std::map<std::pair<uint64_t, uint8_t>, uint64_t> oracle;
    const int n = 10 << (2 * round);
    for (int i = 0; i < n; ++i) {
      // Voxels near each other, the largest keys (dims up to 2^21), class 0..255.
      const vox::Coord3 c{int32_t(rng() % 64) + (i % 3 == 0 ? 2097000 : 0), int32_t(rng() % 64), int32_t(rng() % 16)};
      const uint64_t key = vox::FuseCounts::voxelKey(c);
      const uint8_t cls = uint8_t(rng() % (i % 5 == 0 ? 256 : 3));
      const uint64_t w = 1 + rng() % 1000;
      ((i & 1) ? a : b).add(key, cls, w);
      if (i % 7 == 0) a.add(key, cls, w);  // the same entry again, right after
      oracle[{key, cls}] += w * (i % 7 == 0 ? 2 : 1);
    }
    a.merge(b);
    ASSERT_EQ(a.size(), oracle.size());
    const std::vector<VoteTable::Entry> got = a.sorted();
    size_t k = 0;
    for (const auto& [key, votes] : oracle) {
      ASSERT_EQ(got[k].voxel, key.first);
      ASSERT_EQ(got[k].classId, key.second);
      ASSERT_EQ(got[k].votes, votes);
      ++k;
    }
    a.clear();
    EXPECT_TRUE(a.empty());
    EXPECT_TRUE(a.sorted().empty());
  }
}

// Voxels with u >= 16384 stay apart from u - 16384: the key is not packed
// with the class into one word (voxelKey << 8 | class, the former hash map's
// key, lost u's bits 14-20 and merged those voxels' votes).
TEST(FuseVoteTable, LargeCoordinatesAndClassesStayDistinct) {
  vox::FuseCounts counts;
  counts.addVote({8192, 0, 0}, 1, 1);
  counts.addVote({0, 0, 0}, 1, 2);
  counts.addVote({16384, 0, 0}, 1, 4);
  counts.addVote({16384, 5, 7}, 200, 3);
  const std::vector<vox::FuseCounts::Vote> v = counts.votes();
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(std::make_tuple(v[0].at.u, v[0].classId, v[0].votes), std::make_tuple(0, uint8_t(1), uint64_t(2)));
  EXPECT_EQ(std::make_tuple(v[1].at.u, v[1].classId, v[1].votes), std::make_tuple(8192, uint8_t(1), uint64_t(1)));
  EXPECT_EQ(std::make_tuple(v[2].at.u, v[2].at.v, v[2].classId, v[2].votes), std::make_tuple(16384, 0, uint8_t(1), uint64_t(4)));
  EXPECT_EQ(std::make_tuple(v[3].at.u, v[3].at.w, v[3].classId, v[3].votes),
            std::make_tuple(16384, 7, uint8_t(200), uint64_t(3)));
}

// The radix sort of voxel keys gives std::sort's order: small and large
// inputs, keys that vary in few or in all bytes, duplicates.
TEST(FuseVoteTable, VoxelKeySortEqualsStdSort) {
  std::mt19937_64 rng(5);
  for (size_t n : {size_t(0), size_t(1), size_t(255), size_t(256), size_t(5000), size_t(100000)}) {
    for (int kind = 0; kind < 3; ++kind) {
      std::vector<uint64_t> keys(n);
      for (uint64_t& k : keys) {
        if (kind == 0) k = vox::FuseCounts::voxelKey({int32_t(rng() % 512), int32_t(rng() % 512), int32_t(rng() % 512)});
        if (kind == 1) k = vox::FuseCounts::voxelKey({7, int32_t(rng() % 3), 100});
        if (kind == 2) k = rng() >> 1;
      }
      std::vector<uint64_t> want = keys;
      std::sort(want.begin(), want.end());
      vox::sortVoxelKeys(keys);
      ASSERT_EQ(keys, want) << n << " keys, kind " << kind;
    }
  }
}

}  // namespace
