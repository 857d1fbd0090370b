// FlatMap64 (libvox/core/flat_map64.h) against std::unordered_map as the
// oracle: random keys, both probe policies, growth, find and iteration.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <unordered_map>
#include <vector>

#include "libvox/core/flat_map64.h"

namespace vox {
namespace {

uint64_t packed(uint32_t x, uint32_t y, uint32_t z) { return uint64_t(x) << 42 | uint64_t(y) << 21 | z; }

template <typename Home>
void checkAgainstOracle(const std::vector<uint64_t>& keys) {
  FlatMap64<uint64_t, Home> map;
  std::unordered_map<uint64_t, uint64_t> oracle;
  for (size_t i = 0; i < keys.size(); ++i) {
    map[keys[i]] += i + 1;
    oracle[keys[i]] += i + 1;
  }
  ASSERT_EQ(map.size(), oracle.size());
  for (const auto& [k, v] : oracle) {
    const uint64_t* found = map.find(k);
    ASSERT_NE(found, nullptr) << "key " << k;
    EXPECT_EQ(*found, v) << "key " << k;
  }
  size_t visited = 0;
  map.forEach([&](uint64_t k, uint64_t v) {
    ++visited;
    auto it = oracle.find(k);
    ASSERT_NE(it, oracle.end()) << "forEach gave a key never inserted: " << k;
    EXPECT_EQ(v, it->second);
  });
  EXPECT_EQ(visited, oracle.size());
  // Keys never inserted are not found.
  std::mt19937_64 rng(7);
  for (int i = 0; i < 1000; ++i) {
    const uint64_t k = rng() >> 1;
    if (!oracle.count(k)) {
      EXPECT_EQ(map.find(k), nullptr);
    }
  }
}

TEST(FlatMap64, RandomKeysMatchTheOracle) {
  std::mt19937_64 rng(1);
  std::vector<uint64_t> keys;
  for (int i = 0; i < 50000; ++i) keys.push_back((rng() >> 1) % 20000);  // repeats: sums
  checkAgainstOracle<FibonacciHome>(keys);
  checkAgainstOracle<PackedCoordHome>(keys);
}

TEST(FlatMap64, PackedCoordinatesMatchTheOracle) {
  // A surface-like walk (neighbours in runs) and scattered coordinates up to
  // 2^21 on every axis, including the largest packed key.
  std::vector<uint64_t> keys;
  for (uint32_t x = 0; x < 40; ++x)
    for (uint32_t y = 0; y < 40; ++y) keys.push_back(packed(x, y, (x * 7 + y * 3) % 50));
  std::mt19937 rng(3);
  for (int i = 0; i < 20000; ++i) keys.push_back(packed(rng() & 0x1fffff, rng() & 0x1fffff, rng() & 0x1fffff));
  keys.push_back(packed(0x1fffff, 0x1fffff, 0x1fffff));
  keys.push_back(0);
  checkAgainstOracle<PackedCoordHome>(keys);
  checkAgainstOracle<FibonacciHome>(keys);
}

TEST(FlatMap64, GrowthMovesValuesAndReserveHolds) {
  FlatMap64<std::vector<int>, PackedCoordHome> map;
  for (uint32_t i = 0; i < 5000; ++i) map[packed(i, i / 3, i % 7)].push_back(int(i));
  for (uint32_t i = 0; i < 5000; ++i) {
    const std::vector<int>* v = map.find(packed(i, i / 3, i % 7));
    ASSERT_NE(v, nullptr);
    ASSERT_EQ(v->size(), 1u);
    EXPECT_EQ((*v)[0], int(i));
  }
  // After reserve(n), n keys go in without moving the first one's value.
  FlatMap64<int> reserved;
  reserved.reserve(1000);
  int* first = &reserved[12345];
  for (uint64_t k = 0; k < 999; ++k) reserved[k * 977];
  EXPECT_EQ(first, reserved.find(12345));
  reserved.clear();
  EXPECT_TRUE(reserved.empty());
  EXPECT_EQ(reserved.find(12345), nullptr);
}

}  // namespace
}  // namespace vox
