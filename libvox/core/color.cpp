#include "libvox/core/color.h"

#include <array>
#include <bit>
#include <cmath>

namespace vox {

float srgbToLinear(double c) {
  return float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

float srgb8ToLinear(uint8_t c) {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgbToLinear(i / 255.0);
    return t;
  }();
  return table[c];
}

namespace {

// 255 * sRGB(c) in extended precision (the reference the thresholds come from).
long double encoded255(float c) {
  const long double x = c;
  const long double s = x <= 0.0031308L ? 12.92L * x : 1.055L * std::pow(x, 1.0L / 2.4L) - 0.055L;
  return 255.0L * s;
}

// thresholds[k]: the smallest non-negative float whose encoding rounds to >= k,
// found by bisection over the bit patterns of non-negative floats (ordered like
// the values). A table rather than pow per call: exact by construction and
// ~8 comparisons instead of a pow.
const std::array<float, 256>& thresholds() {
  static const std::array<float, 256> t = [] {
    std::array<float, 256> r{};
    r[0] = 0.0f;
    for (int k = 1; k < 256; ++k) {
      uint32_t lo = 0, hi = std::bit_cast<uint32_t>(1.0f);  // encoded255(1) = 255 >= k - 0.5
      while (lo < hi) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (encoded255(std::bit_cast<float>(mid)) >= k - 0.5L) hi = mid;
        else lo = mid + 1;
      }
      r[size_t(k)] = std::bit_cast<float>(lo);
    }
    return r;
  }();
  return t;
}

}  // namespace

float srgb8Threshold(int k) { return thresholds()[size_t(k)]; }

uint8_t linearToSrgb8(float c) {
  if (!(c > 0.0f)) return 0;  // also NaN
  if (c >= 1.0f) return 255;
  const std::array<float, 256>& t = thresholds();
  int lo = 0, hi = 255;  // answer in [lo, hi]: the largest k with t[k] <= c
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (t[size_t(mid)] <= c) lo = mid;
    else hi = mid - 1;
  }
  return uint8_t(lo);
}

}  // namespace vox
