// std::round / std::llround (halves away from zero) without a libm call: on
// baseline x86-64 (no SSE4.1) both are calls, one per coordinate where a mesh's
// vertices are snapped to the lattice.
#pragma once

#include <cmath>
#include <cstdint>

namespace vox {

/// std::round(x)'s value for every double; a zero comes out +0 (std::round
/// keeps x's sign: -0 for -0.3), which no caller tells apart.
inline double roundHalfAway(double x) {
  if (!(std::abs(x) < 0x1p52)) return x;    // already an integer (or NaN, infinity)
  const double whole = double(int64_t(x));  // toward zero, exact
  const double frac = x - whole;            // exact
  return frac >= 0.5 ? whole + 1 : frac <= -0.5 ? whole - 1 : whole;
}

/// std::llround(x) where |x| < 2^52 (every lattice coordinate); libm's beyond.
inline int64_t llroundHalfAway(double x) {
  if (!(std::abs(x) < 0x1p52)) return std::llround(x);
  return int64_t(roundHalfAway(x));  // an integer below 2^52 + 1: converts exactly
}

}  // namespace vox
