// Numbers in text mesh files (OBJ, ASCII PLY and STL): std::from_chars with
// a shortcut for the numbers such files hold.
//
// Why not std::from_chars alone: the readers spend much of their time on
// numbers, and libstdc++'s from_chars takes about 230 instructions for a
// coordinate such as "-0.037830" and 120 for a face index, where the paths
// below take about 140 and 90 (callgrind, Stanford bunny OBJ). Nearly every
// coordinate an exporter writes has at most 19 significant digits and no
// exponent: its value is m / 10^k with m <= 2^53 and k <= 22, both exact
// doubles, and one IEEE division rounds that quotient correctly (Clinger,
// "How to read floating point numbers accurately", PLDI 1990), so it is the
// value from_chars gives. Anything else (an exponent, more digits, inf, nan,
// no digits at all) goes to std::from_chars itself.
//
// Contract: for every input, the result (ptr, ec) and the value written are
// exactly std::from_chars's (chars_format::general for doubles, base 10 for
// integers), bit for bit; tests/test_text_numbers.cpp compares them on
// millions of strings. Thread-safety: pure functions.
#pragma once

#include <charconv>
#include <cstdint>
#include <system_error>

namespace vox {

/// std::from_chars(first, last, value) for a double, the same in every case.
inline std::from_chars_result parseDouble(const char* first, const char* last, double& value) {
  static constexpr double kPow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                        1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  auto isDigit = [](char c) { return unsigned(c - '0') < 10; };
  const char* p = first;
  const bool negative = p < last && *p == '-';
  if (negative) ++p;
  // Digits accumulate into m (wrapping past 19 significant digits, which then
  // go to from_chars); leading zeros are not significant.
  const char* start = p;
  while (p < last && *p == '0') ++p;
  uint64_t m = 0;
  const char* significantFrom = p;
  while (p < last && isDigit(*p)) m = m * 10 + unsigned(*p++ - '0');
  size_t significant = size_t(p - significantFrom), fraction = 0;
  bool digits = p > start;
  if (p < last && *p == '.') {
    const char* f = ++p;
    if (m == 0)
      while (p < last && *p == '0') ++p;
    const char* from = p;
    while (p < last && isDigit(*p)) m = m * 10 + unsigned(*p++ - '0');
    significant += size_t(p - from);
    fraction = size_t(p - f);
    digits = digits || fraction > 0;
  }
  if (!digits || significant > 19 || (p < last && (*p == 'e' || *p == 'E')) || m > (uint64_t(1) << 53) ||
      fraction > 22)
    return std::from_chars(first, last, value);
  // Exact operands, one correctly rounded division: this needs the default
  // round-to-nearest mode (nothing in voxbake changes it) and no -ffast-math
  // (which may turn the division into a multiplication by a rounded reciprocal).
  const double v = double(m) / kPow10[fraction];
  value = negative ? -v : v;
  return {p, std::errc()};
}

/// parseDouble that also takes one leading '+' ("+1.5"), which some exporters
/// write and std::from_chars refuses. "+-1" and "++1" are still refused. On
/// failure ptr is past the '+' when there was one, so a reader can tell text
/// that ends right there ("file ends early") from text that is not a number.
inline std::from_chars_result parseDoubleAllowingPlus(const char* first, const char* last, double& value) {
  if (first < last && *first == '+') {
    ++first;
    if (first < last && *first == '-') return {first, std::errc::invalid_argument};
  }
  return parseDouble(first, last, value);
}

/// std::from_chars(first, last, value) for an int64_t in base 10, the same in every case.
inline std::from_chars_result parseInt64(const char* first, const char* last, int64_t& value) {
  const char* p = first;
  const bool negative = p < last && *p == '-';
  if (negative) ++p;
  const char* digits = p;
  uint64_t v = 0;
  for (; p < last && unsigned(*p - '0') < 10; ++p) {
    if (p - digits == 18) return std::from_chars(first, last, value);  // 19 digits may not fit
    v = v * 10 + unsigned(*p - '0');
  }
  if (p == digits) return std::from_chars(first, last, value);
  value = negative ? -int64_t(v) : int64_t(v);
  return {p, std::errc()};
}

}  // namespace vox
