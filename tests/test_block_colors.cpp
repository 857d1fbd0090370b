// A block's colours are kept one per coloured voxel, in voxel order
// (VoxelBlock::colors, libvox/mesh/voxel_blocks.h): checked against a plain
// array of 512 optional colours under random sets, overwrites and merges.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <optional>
#include <random>

#include "libvox/mesh/voxel_blocks.h"

namespace vox {
namespace {

using Rgb = std::array<float, 3>;
using Plain = std::array<std::optional<Rgb>, kBlockVoxels>;

/// Every colour of `b` against `want`: the layout's invariant, each voxel's
/// colour, and forEachColor's visits (in voxel order, only the mask's voxels).
void expectSame(const VoxelBlock& b, const Plain& want, const std::array<uint64_t, kBlockWords>& mask) {
  size_t bits = 0;
  for (uint64_t w : b.colored) bits += size_t(bitCount(w));
  ASSERT_EQ(b.colors.size(), bits);
  for (int i = 0; i < kBlockVoxels; ++i) {
    const bool colored = (b.colored[size_t(i >> 6)] >> (i & 63)) & 1;
    ASSERT_EQ(colored, want[size_t(i)].has_value()) << "voxel " << i;
    if (colored) {
      EXPECT_EQ(colorAt(b, i), *want[size_t(i)]) << "voxel " << i;
    }
  }
  int last = -1;
  size_t visits = 0;
  forEachColor(b, mask, [&](int i, const Rgb& rgb) {
    EXPECT_GT(i, last);
    last = i;
    ++visits;
    EXPECT_TRUE((mask[size_t(i >> 6)] >> (i & 63)) & 1) << "voxel " << i;
    ASSERT_TRUE(want[size_t(i)].has_value()) << "voxel " << i;
    EXPECT_EQ(rgb, *want[size_t(i)]) << "voxel " << i;
  });
  size_t expected = 0;
  for (int i = 0; i < kBlockVoxels; ++i) expected += want[size_t(i)] && ((mask[size_t(i >> 6)] >> (i & 63)) & 1);
  EXPECT_EQ(visits, expected);
}

Rgb randomRgb(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0, 1);
  return {u(rng), u(rng), u(rng)};
}

std::array<uint64_t, kBlockWords> randomMask(std::mt19937& rng) {
  std::array<uint64_t, kBlockWords> m;
  for (uint64_t& w : m) w = (uint64_t(rng()) << 32) | rng();
  return m;
}

TEST(BlockColors, RandomSetsAndOverwritesMatchPlainArray) {
  std::mt19937 rng(7);
  for (int round = 0; round < 200; ++round) {
    VoxelBlock b;
    Plain want{};
    const int sets = int(rng() % 700);  // from empty to every voxel, with repeats
    const int spread = 1 + int(rng() % kBlockVoxels);
    for (int s = 0; s < sets; ++s) {
      const int i = int(rng() % uint32_t(spread)) * (kBlockVoxels / spread);
      const Rgb c = randomRgb(rng);
      setBlockColor(b, i, c);
      want[size_t(i)] = c;
    }
    std::array<uint64_t, kBlockWords> all;
    all.fill(~uint64_t(0));
    expectSame(b, want, all);
    expectSame(b, want, randomMask(rng));
  }
}

TEST(BlockColors, MergeKeepsOursWhereBothHaveOne) {
  std::mt19937 rng(11);
  for (int round = 0; round < 50; ++round) {
    VoxelBlocks ours, theirs;
    Plain want{};
    const Coord3 origin{8 * int32_t(rng() % 4), 8, 16};
    for (int s = 0; s < 150; ++s) {
      const int i = int(rng() % kBlockVoxels);
      const Coord3 c{origin.u + (i >> 6), origin.v + ((i >> 3) & 7), origin.w + (i & 7)};
      const Rgb rgb = randomRgb(rng);
      if (rng() & 1) {
        ours.setColor(c, {rgb[0], rgb[1], rgb[2]});
        want[size_t(i)] = rgb;  // ours: the last one set
      } else {
        theirs.setColor(c, {rgb[0], rgb[1], rgb[2]});
      }
    }
    // Theirs fill in where ours has none (their last one set).
    VoxelBlock* t = theirs.blockAt(origin);
    ASSERT_NE(t, nullptr);
    for (int i = 0; i < kBlockVoxels; ++i)
      if (!want[size_t(i)] && ((t->colored[size_t(i >> 6)] >> (i & 63)) & 1)) want[size_t(i)] = colorAt(*t, i);
    ours.merge(std::move(theirs));
    VoxelBlock* b = ours.blockAt(origin);
    ASSERT_NE(b, nullptr);
    std::array<uint64_t, kBlockWords> all;
    all.fill(~uint64_t(0));
    expectSame(*b, want, all);
    VoxelBlocks::release(*b);
    EXPECT_TRUE(b->colors.empty());
    EXPECT_EQ(b->colors.capacity(), 0u);
  }
}

}  // namespace
}  // namespace vox
