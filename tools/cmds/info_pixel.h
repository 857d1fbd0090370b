// `vox info FILE --pixel x,y`: the texel of an atlas or the pixel of a
// canonical render to decode, parsed strictly, so that "1.5,2" is not read as
// (1, 2) and " 1,2" or "" is not passed over.
#pragma once

#include <cstdint>
#include <string>

#include "libvox/core/error.h"

namespace voxcli {

struct PixelXY {
  uint32_t x = 0, y = 0;
  std::string text() const { return std::to_string(x) + "," + std::to_string(y); }
};

/// "x,y": two whole numbers in decimal digits (no sign, space, point or
/// exponent), each at most 2^32 - 1, and one comma between them. Throws
/// vox::Error (Usage) naming --pixel and the text on anything else.
inline PixelXY parsePixel(const std::string& text) {
  auto refuse = [&]() -> PixelXY {
    vox::throwUsage("--pixel '" + text + "': expected x,y, two whole numbers 0..4294967295 such as --pixel 12,40");
  };
  PixelXY p;
  uint32_t* into[2] = {&p.x, &p.y};
  size_t i = 0;
  for (int k = 0; k < 2; ++k) {
    if (k == 1 && (i >= text.size() || text[i++] != ',')) return refuse();
    const size_t start = i;
    uint64_t v = 0;
    for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) {
      v = v * 10 + uint64_t(text[i] - '0');
      if (v > UINT32_MAX) return refuse();
    }
    if (i == start) return refuse();
    *into[k] = uint32_t(v);
  }
  if (i != text.size()) return refuse();
  return p;
}

}  // namespace voxcli
