// The sRGB module against an extended-precision reference.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>

#include "libvox/core/color.h"

namespace {

// 255 * sRGB(c), computed here independently of the library, in long double.
long double reference255(float c) {
  const long double x = c;
  const long double s = x <= 0.0031308L ? 12.92L * x : 1.055L * std::pow(x, 1.0L / 2.4L) - 0.055L;
  return 255.0L * s;
}

// Correctly rounded 8-bit value (ties away from zero).
int referenceByte(float c) { return int(std::floor(reference255(c) + 0.5L)); }

}  // namespace

// The encoder is a lookup in 255 increasing thresholds, so it is monotonic by
// construction; each threshold being exactly where the correctly rounded value
// steps up (checked on the threshold and the float just below it) therefore
// proves it right on every float in [0, 1].
TEST(Color, LinearToSrgb8IsCorrectlyRoundedOnEveryFloat) {
  float previous = 0.0f;
  for (int k = 1; k < 256; ++k) {
    const float t = vox::srgb8Threshold(k);
    const float below = std::nextafter(t, 0.0f);
    ASSERT_GT(t, previous) << "thresholds increase, k = " << k;
    ASSERT_EQ(referenceByte(t), k) << "threshold " << k << " = " << t;
    ASSERT_EQ(referenceByte(below), k - 1) << "float below threshold " << k;
    // No value sits so close to a rounding boundary that long double could flip it.
    ASSERT_GT(std::fabs(reference255(t) - (k - 0.5L)), 1e-12L) << k;
    ASSERT_EQ(vox::linearToSrgb8(t), k);
    ASSERT_EQ(vox::linearToSrgb8(below), k - 1);
    previous = t;
  }
  // And a direct comparison on a regular sample of the float bit patterns.
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  for (uint32_t bits = 0; bits <= one; bits += 4099) {
    const float c = std::bit_cast<float>(bits);
    ASSERT_EQ(vox::linearToSrgb8(c), referenceByte(c)) << c;
  }
}

TEST(Color, LinearToSrgb8ClampsAndKnownValues) {
  EXPECT_EQ(vox::linearToSrgb8(-1.0f), 0);
  EXPECT_EQ(vox::linearToSrgb8(std::nanf("")), 0);
  EXPECT_EQ(vox::linearToSrgb8(2.0f), 255);
  EXPECT_EQ(vox::linearToSrgb8(1.0f), 255);
  EXPECT_EQ(vox::linearToSrgb8(0.0f), 0);
  EXPECT_EQ(vox::linearToSrgb8(0.5f), 188);  // 255 * 0.735357 = 187.52
  // Where the two copies this module replaced disagreed (4 with float pow, 3 here).
  EXPECT_EQ(vox::linearToSrgb8(0.00106234f), referenceByte(0.00106234f));
}

TEST(Color, DecodeEncodeRoundTripsEveryByte) {
  for (int k = 0; k < 256; ++k) {
    const float lin = vox::srgb8ToLinear(uint8_t(k));
    EXPECT_EQ(lin, vox::srgbToLinear(k / 255.0)) << k;
    EXPECT_EQ(vox::linearToSrgb8(lin), k) << k;
  }
  EXPECT_EQ(vox::srgbToLinear(0.0), 0.0f);
  EXPECT_EQ(vox::srgbToLinear(1.0), 1.0f);
  EXPECT_NEAR(vox::srgbToLinear(0.04045), 0.04045 / 12.92, 1e-9);  // the linear segment's end
}
