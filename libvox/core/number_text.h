// Numbers in messages and reports where the value must read back exactly
// but not look like noise: the shortest text that round-trips (std::to_chars),
// "0.8" for the double nearest 0.8, not %.17g's "0.80000000000000004", and a
// float's shortest text for a value stored as float ("0.8749981", not the
// 17 digits of its double). Thread-safety: pure functions.
#pragma once

#include <charconv>
#include <string>

namespace vox {

/// The shortest decimal text that reads back as `x` ("0.8", "1e+300", "inf", "nan").
inline std::string shortestText(double x) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

/// The shortest decimal text that reads back as the float `x`.
inline std::string shortestText(float x) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

}  // namespace vox
