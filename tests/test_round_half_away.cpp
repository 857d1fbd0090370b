// roundHalfAway and llroundHalfAway against libm's std::round and std::llround:
// halves, the doubles next to them, the 2^52 boundary, and random doubles at
// every magnitude the lattice meets (grid coordinates times 2^16).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "libvox/core/round_half_away.h"

namespace {

std::vector<double> cases() {
  std::vector<double> v = {0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0x1p52, -0x1p52, 0x1p52 - 0.5, -(0x1p52 - 0.5),
                           0x1p53, -0x1p53, 0x1p62, 0.49999999999999994, -0.49999999999999994, 1e-300, -1e-300};
  for (double h = 0.5; h < 0x1p53; h = h * 2 + 0.5)  // halves at every magnitude, and their neighbours
    for (double x : {h, -h})
      v.insert(v.end(), {x, std::nextafter(x, 0.0), std::nextafter(x, 2 * x)});
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-20, 60);
  for (int i = 0; i < 200000; ++i) v.push_back(std::ldexp(unit(rng), exponent(rng)));
  return v;
}

TEST(RoundHalfAway, SameAsStdRound) {
  for (double x : cases()) {
    const double a = vox::roundHalfAway(x), b = std::round(x);
    ASSERT_EQ(a, b) << x;
    if (a == 0) {
      ASSERT_FALSE(std::signbit(a)) << x;  // +0 always, as documented
    }
  }
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(vox::roundHalfAway(inf), inf);
  EXPECT_EQ(vox::roundHalfAway(-inf), -inf);
  EXPECT_TRUE(std::isnan(vox::roundHalfAway(std::nan(""))));
}

TEST(RoundHalfAway, SameAsStdLlround) {
  for (double x : cases())
    if (std::abs(x) < 0x1p62) {
      ASSERT_EQ(vox::llroundHalfAway(x), std::llround(x)) << x;
    }
}

}  // namespace
