// `vox info FILE --pixel x,y`: the texel of an atlas or the pixel of a
// canonical render to decode, parsed strictly, so that "1.5,2" is not read as
// (1, 2) and " 1,2" or "" is not passed over.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libvox/core/error.h"
#include "tools/cli/comma_list.h"

namespace voxcli {

struct PixelXY {
  uint32_t x = 0, y = 0;
  std::string text() const { return std::to_string(x) + "," + std::to_string(y); }
};

/// "x,y": two whole numbers in decimal digits (no sign, space, point or
/// exponent), each at most 2^32 - 1, and one comma between them. Throws
/// vox::Error (Usage) naming --pixel and the text on anything else.
inline PixelXY parsePixel(const std::string& text) {
  const std::string expected = "x,y, two whole numbers 0..4294967295 such as --pixel 12,40";
  const std::vector<std::string> parts = splitCommaList(text, "--pixel", expected);  // empty entries named there
  auto refuse = [&]() -> PixelXY { vox::throwUsage("--pixel '" + text + "': expected " + expected); };
  if (parts.size() != 2) return refuse();
  PixelXY p;
  uint32_t* into[2] = {&p.x, &p.y};
  for (size_t k = 0; k < 2; ++k) {
    uint64_t v = 0;
    for (const char c : parts[k]) {
      if (c < '0' || c > '9') return refuse();
      v = v * 10 + uint64_t(c - '0');
      if (v > UINT32_MAX) return refuse();
    }
    *into[k] = uint32_t(v);
  }
  return p;
}

}  // namespace voxcli
