// floorToInt and ceilToInt (libvox/core/floor_int.h) give std::floor and
// std::ceil exactly over their contract (finite, |x| < 2^63): integers, the
// doubles next to them, halves, the grid coordinates the surface pass and the
// fuse walk pass, and random doubles of every magnitude up to 2^62.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "libvox/core/floor_int.h"

namespace {

void expectBoth(double x) {
  ASSERT_EQ(vox::floorToInt(x), int64_t(std::floor(x))) << "x = " << x;
  ASSERT_EQ(vox::ceilToInt(x), int64_t(std::ceil(x))) << "x = " << x;
}

TEST(FloorInt, IntegersTheirNeighboursAndHalves) {
  const double inf = std::numeric_limits<double>::infinity();
  for (int64_t k = -70000; k <= 70000; ++k) {
    const double x = double(k);
    expectBoth(x);
    expectBoth(std::nextafter(x, inf));
    expectBoth(std::nextafter(x, -inf));
    expectBoth(x + 0.5);
    expectBoth(x - 1e-6);  // the surface pass's candidate margins
    expectBoth(x + 1e-6);
  }
  for (double x : {0.0, -0.0, std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::denorm_min(),
                   std::numeric_limits<double>::min(), 0.49999999999999994, -0.49999999999999994, 4503599627370495.5,
                   -4503599627370495.5, 9007199254740993.0, 4.0e18, -4.0e18, 4611686018427387904.0})
    expectBoth(x);
}

TEST(FloorInt, RandomDoublesOfEveryMagnitude) {
  std::mt19937_64 rng(20261203);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-60, 62);
  for (int i = 0; i < 2000000; ++i) expectBoth(std::ldexp(mantissa(rng), exponent(rng)));
}

}  // namespace
