// floor() and ceil() of a double as an integer, without libm.
//
// Why: the x86-64 baseline voxbake is built for has no rounding instruction
// (SSE4.1's roundsd), so std::floor is a call or a long inline sequence; the
// surface pass and the fuse walk take one per row or step. For every finite x
// with |x| < 2^63 the result is exactly std::floor(x) (std::ceil(x)): the
// conversion truncates toward zero, and one comparison steps down (up) where
// that was the wrong way. Larger, infinite or NaN inputs are undefined
// behaviour, as the conversion is; callers pass coordinates of a grid.
#pragma once

#include <cstdint>

namespace vox {

/// std::floor(x) as an integer, for finite |x| < 2^63.
inline int64_t floorToInt(double x) {
  const int64_t i = int64_t(x);
  return i - (double(i) > x ? 1 : 0);
}

/// std::ceil(x) as an integer, for finite |x| < 2^63.
inline int64_t ceilToInt(double x) {
  const int64_t i = int64_t(x);
  return i + (double(i) < x ? 1 : 0);
}

}  // namespace vox
