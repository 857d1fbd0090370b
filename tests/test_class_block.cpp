// ClassBlock (libvox/mesh/voxel_blocks.h): the compact vote counts (one per
// voted voxel, in voxel order) and the dense form past kCompactCounts give the
// same votes as a plain count per voxel, however the votes arrive.
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "libvox/mesh/voxel_blocks.h"

namespace vox {
namespace {

using Plain = std::array<uint32_t, kBlockVoxels>;

void expectSame(const ClassBlock& cb, const Plain& plain, const char* what) {
  for (int i = 0; i < kBlockVoxels; ++i) {
    ASSERT_EQ(cb.at(i), plain[size_t(i)]) << what << ": voxel " << i;
    ASSERT_EQ(cb.has(i), plain[size_t(i)] != 0) << what << ": voxel " << i;
  }
  int previous = -1;
  size_t n = 0;
  cb.forEach([&](int i, uint32_t c) {
    EXPECT_GT(i, previous) << what << ": voxel order";
    EXPECT_EQ(c, plain[size_t(i)]) << what;
    previous = i, ++n;
  });
  size_t voted = 0;
  for (uint32_t c : plain) voted += c != 0;
  EXPECT_EQ(n, voted) << what;
}

TEST(ClassBlock, CompactAndDenseMatchPlainCounts) {
  std::mt19937 rng(7);
  for (int voxels : {1, 40, 128, 129, 300, 512}) {
    ClassBlock cb;
    Plain plain{};
    for (int k = 0; k < 3 * voxels; ++k) {
      const int i = int(rng() % uint32_t(voxels)) * (kBlockVoxels / voxels);  // spread over the block
      const uint32_t v = k % 17 == 0 ? 0 : 1 + rng() % 70000;
      cb.add(i, v);
      plain[size_t(i)] = saturatingVotes(plain[size_t(i)], v);
    }
    expectSame(cb, plain, "random adds");
  }
}

TEST(ClassBlock, SaturatesAndMerges) {
  ClassBlock a, b;
  Plain pa{}, pb{};
  for (int i = 0; i < kBlockVoxels; i += 3) a.add(i, kMaxVotesPerClass - 5), pa[size_t(i)] = kMaxVotesPerClass - 5;
  a.add(0, 100);
  pa[0] = kMaxVotesPerClass;
  for (int i = 0; i < 100; i += 2) b.add(i, 9), pb[size_t(i)] = 9;
  expectSame(a, pa, "saturating");
  ClassBlock c = b;  // compact + compact
  ClassBlock d;
  for (int i = 1; i < 60; i += 4) d.add(i, 5);
  Plain pc = pb;
  for (int i = 1; i < 60; i += 4) pc[size_t(i)] = saturatingVotes(pc[size_t(i)], 5);
  c.addAll(d);
  expectSame(c, pc, "compact merge");
  b.addAll(a);  // compact + dense
  for (int i = 0; i < kBlockVoxels; ++i) pb[size_t(i)] = saturatingVotes(pb[size_t(i)], pa[size_t(i)]);
  expectSame(b, pb, "dense merge");
}

TEST(ClassBlock, RunsMaterializeIntoCounts) {
  VoxelBlocks blocks;
  blocks.addVotes({1, 2, 3}, 4, 10, true);
  blocks.addRun({1, 2, 0}, 8, 4, 65536, false);  // the column through (1, 2, 3), kept as runs
  VoxelBlock* b = blocks.blockAt({0, 0, 0});
  ASSERT_NE(b, nullptr);
  materializeRuns(*b);
  const ClassBlock* cb = findClassBlock(*b, 4);
  ASSERT_NE(cb, nullptr);
  for (int z = 0; z < 8; ++z) EXPECT_EQ(cb->at(blockOffset(1, 2, z)), z == 3 ? 65546u : 65536u) << z;
  EXPECT_EQ(cb->at(blockOffset(1, 3, 3)), 0u);
}

}  // namespace
}  // namespace vox
