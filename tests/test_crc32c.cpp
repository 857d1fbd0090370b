#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "libvox/core/crc32c.h"
#include "libvox/core/morton.h"

namespace {

// Known vectors: RFC 3720 (iSCSI) appendix B.4 and the "123456789" check value.
TEST(Crc32c, KnownVectors) {
  const std::string check = "123456789";
  EXPECT_EQ(vox::crc32c(check.data(), check.size()), 0xE3069283u);
  EXPECT_EQ(vox::crc32cPortable(check.data(), check.size()), 0xE3069283u);
  std::vector<uint8_t> zeros(32, 0), ones(32, 0xff), up(32), down(32);
  for (int i = 0; i < 32; ++i) up[size_t(i)] = uint8_t(i), down[size_t(i)] = uint8_t(31 - i);
  for (auto fn : {&vox::crc32c, &vox::crc32cPortable}) {
    EXPECT_EQ(fn(zeros.data(), 32, 0), 0x8A9136AAu);
    EXPECT_EQ(fn(ones.data(), 32, 0), 0x62A8AB43u);
    EXPECT_EQ(fn(up.data(), 32, 0), 0x46DD794Eu);
    EXPECT_EQ(fn(down.data(), 32, 0), 0x113FDB5Cu);
    EXPECT_EQ(fn(nullptr, 0, 0), 0u);
  }
}

TEST(Crc32c, HardwareAndTableAgreeAtEveryLengthAndAlignment) {
  std::mt19937 rng(7);
  std::vector<uint8_t> buf(1200);
  for (auto& b : buf) b = uint8_t(rng());
  for (size_t offset = 0; offset < 8; ++offset)
    for (size_t n = 0; n + offset <= buf.size(); n += (n < 64 ? 1 : 37))
      ASSERT_EQ(vox::crc32c(buf.data() + offset, n), vox::crc32cPortable(buf.data() + offset, n)) << n;
}

TEST(Crc32c, IncrementalEqualsWhole) {
  const std::string s = "The quick brown fox jumps over the lazy dog";
  const uint32_t whole = vox::crc32c(s.data(), s.size());
  EXPECT_EQ(whole, 0x22620404u);  // published CRC32C of this sentence
  for (size_t cut = 0; cut <= s.size(); ++cut)
    EXPECT_EQ(vox::crc32c(s.data() + cut, s.size() - cut, vox::crc32c(s.data(), cut)), whole);
}

TEST(Morton, InterleavesAndInverts) {
  EXPECT_EQ(vox::mortonEncode(1, 0, 0), 1u);
  EXPECT_EQ(vox::mortonEncode(0, 1, 0), 2u);
  EXPECT_EQ(vox::mortonEncode(0, 0, 1), 4u);
  EXPECT_EQ(vox::mortonEncode(2, 0, 0), 8u);
  EXPECT_EQ(vox::mortonEncode(3, 3, 3), 63u);
  EXPECT_EQ(vox::mortonEncode(vox::kMortonAxisMax, vox::kMortonAxisMax, vox::kMortonAxisMax), (uint64_t(1) << 63) - 1);
  std::mt19937 rng(3);
  for (int i = 0; i < 10000; ++i) {
    const uint32_t x = rng() & vox::kMortonAxisMax, y = rng() & vox::kMortonAxisMax, z = rng() & vox::kMortonAxisMax;
    const auto d = vox::mortonDecode(vox::mortonEncode(x, y, z));
    ASSERT_EQ(d[0], x);
    ASSERT_EQ(d[1], y);
    ASSERT_EQ(d[2], z);
  }
  // Order: within a 2x2x2 block x varies fastest, then y, then z.
  EXPECT_LT(vox::mortonEncode(1, 1, 0), vox::mortonEncode(0, 0, 1));
}

}  // namespace
